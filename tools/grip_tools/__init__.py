"""grip_tools - full-precision reference models and tooling for the grip C library.

Run `grip --help` for the command list.
"""
__version__ = "0.1.0"
