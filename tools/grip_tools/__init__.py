"""grip_tools - full-precision reference models and tooling for the grip C library.

Run `grip --help` (or `python -m grip_tools --help`) for the command list.
"""
import os
import re


def _library_version():
    """The C library's version (include/grip/grip_version.h, its one place),
    so the tools and the library they describe never carry two numbers."""
    header = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                          "include", "grip", "grip_version.h")
    with open(header) as f:
        text = f.read()
    parts = [re.search(rf"#define GRIP_VERSION_{k}\s+(\d+)", text).group(1) for k in ("MAJOR", "MINOR", "PATCH")]
    return ".".join(parts)


__version__ = _library_version()
