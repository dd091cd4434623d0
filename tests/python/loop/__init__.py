"""Tests of grip_tools.loop."""
