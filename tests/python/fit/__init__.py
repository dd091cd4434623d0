"""Tests of grip_tools.fit."""
