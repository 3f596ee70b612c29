"""Tests of sunset.model."""
