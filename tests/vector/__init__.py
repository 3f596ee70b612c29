"""Tests of sunset.vector."""
