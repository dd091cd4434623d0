"""Tests of grip_tools.can."""
