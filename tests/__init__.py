"""The tests of sunset, mirroring the package."""
