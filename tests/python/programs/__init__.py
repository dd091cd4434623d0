"""Tests of the C host programs (port/linux) through their command lines."""
