"""The Python tests; tests/python/run.py discovers them (top level: tests/)."""
