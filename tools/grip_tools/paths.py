"""Where the repository's files are, for tools run from a clone (the package
is installed in editable mode by `make setup`). One place, so moving a module
between sub-packages never breaks a relative path."""
import os

PACKAGE = os.path.dirname(os.path.abspath(__file__))
REPO_ROOT = os.path.abspath(os.path.join(PACKAGE, "..", ".."))
TEST_DATA = os.path.join(REPO_ROOT, "tests", "data")
# Material larger than the repository carries (full real logs): the folder
# `shared/data` beside the clone, or GRIP_SHARED_DATA. Tools fall back to the
# bundled copies under tests/data where one exists.
SHARED_DATA = os.environ.get("GRIP_SHARED_DATA",
                             os.path.abspath(os.path.join(REPO_ROOT, "..", "shared", "data")))
