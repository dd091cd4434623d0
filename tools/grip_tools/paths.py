"""Where the repository's files are, for tools run from a clone (the package
is installed in editable mode by `make setup`). One place, so moving a module
between sub-packages never breaks a relative path."""
import os

PACKAGE = os.path.dirname(os.path.abspath(__file__))
REPO_ROOT = os.path.abspath(os.path.join(PACKAGE, "..", ".."))
TEST_DATA = os.path.join(REPO_ROOT, "tests", "data")
