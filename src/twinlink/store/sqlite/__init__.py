"""The embedded SQLite store (WAL), the default for one process."""

from twinlink.store.sqlite.store import SqliteStore

__all__ = ["SqliteStore"]
