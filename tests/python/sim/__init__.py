"""Tests of grip_tools.sim."""
