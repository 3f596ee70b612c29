"""Tests of sunset.tape."""
