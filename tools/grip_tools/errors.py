"""Errors the `grip` command reports as one line and an exit code, never as
a traceback.

  exit 2  usage: a bad option, a file that cannot be opened
  exit 3  data: a file that was read but cannot be used (its text names
          file, line and field)

A module raises DataError (or a subclass) for bad input; the command line
(cli.py) prints `grip COMMAND: FILE:LINE: FIELD: message` and exits 3.
"""

EXIT_USAGE = 2
EXIT_DATA = 3

# The exit codes as a command's --help states them (argparse epilog).
EXIT_HELP = ("exit status: 0 done; 2 usage (a bad option, a file that cannot be opened); "
             "3 data (a file read but not usable: the message names file, line and field)")


class UsageError(Exception):
    """The command was called wrongly (exit 2)."""

    exit_code = EXIT_USAGE


class DataError(ValueError):
    """Input that was read but cannot be used (exit 3). str():
    'FILE:LINE: FIELD: message', with '-' for what is not known; without a
    file (a value from the command line), 'FIELD: message'."""

    exit_code = EXIT_DATA

    def __init__(self, file, line, field, message):
        self.file = file
        self.line = line
        self.field = field
        self.message = message
        if file is None and line is None:
            super().__init__(f"{field or '-'}: {message}")
            return
        where = f"{file if file is not None else '-'}:{line if line is not None else '-'}"
        super().__init__(f"{where}: {field or '-'}: {message}")
