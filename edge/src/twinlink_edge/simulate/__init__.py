"""Simulated devices: the NTNU thesis's cantilever rig ("Tingen") and a generic signal source.

The models here are pure (no I/O): `runner.py` connects them to a server through the edge SDK.
"""
