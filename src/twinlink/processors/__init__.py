"""Processors: blueprints run in supervised worker processes beside the live data."""
