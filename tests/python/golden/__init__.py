"""Tests of grip_tools.golden."""
