"""Tests of grip_tools.reference."""
