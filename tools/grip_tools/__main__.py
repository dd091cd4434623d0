"""python -m grip_tools <command> [args]: the same as the `grip` command."""
import sys

from grip_tools.cli import main

if __name__ == "__main__":
    sys.exit(main())
