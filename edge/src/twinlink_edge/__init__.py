"""twinlink-edge: the device SDK for twinlink."""

__version__ = "0.1.0"
