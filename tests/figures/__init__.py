"""Tests of sunset.figures."""
