"""Persistence behind small interfaces (`base.py`); `sqlite/` is the embedded default."""
