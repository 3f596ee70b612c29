"""Tests of sunset.recorder."""
