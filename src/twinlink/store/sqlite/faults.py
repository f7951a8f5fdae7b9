"""Disk failures of the SQLite files: SQLite's errors turned into the store's own, counted,
and logged calmly.

A full disk fails every write until someone frees space, hundreds of times a second under
load. Each failure is counted (`/metrics`) but logged at most once a minute per file, cause
first, with the number that failed since the last line; the callers answer with
StorageFullError (HTTP 507, a device's `retry`) instead of logging a traceback each.
"""

from __future__ import annotations

import logging
import sqlite3
import threading
import time
from collections.abc import Callable

from twinlink.domain.errors import StorageError, StorageFullError

log = logging.getLogger("twinlink.store")

LOG_EVERY_S = 60.0
FULL_MESSAGE = (
    "The server's storage is full: nothing of this was stored. "
    "Retry once an administrator has freed disk space."
)
IO_MESSAGE = (
    "The server's storage failed a write (disk I/O error): nothing of this was stored. Retry later."
)


def translate(err: BaseException) -> BaseException:
    """`err` as StorageFullError (SQLITE_FULL) or StorageError (SQLITE_IOERR and its extended
    codes), chained to it; any other error as it is."""
    if not isinstance(err, sqlite3.OperationalError):
        return err
    code = getattr(err, "sqlite_errorcode", None)
    if not isinstance(code, int):
        return err
    primary = code & 0xFF  # extended codes (SQLITE_IOERR_WRITE, ...) keep the primary below
    mapped: StorageError
    if primary == sqlite3.SQLITE_FULL:
        mapped = StorageFullError(FULL_MESSAGE)
    elif primary == sqlite3.SQLITE_IOERR:
        mapped = StorageError(IO_MESSAGE)
    else:
        return err
    mapped.__cause__ = err
    return mapped


def kind_of(err: StorageError) -> str:
    return "full" if isinstance(err, StorageFullError) else "io"


class StorageFaults:
    """Failed writes by kind (`full`, `io`), and their log lines: the first failure of a file
    is logged at once, later ones at most every `every_s` with a count, and the first success
    after failures says how many failed in all. Called from the stores' threads."""

    def __init__(
        self, every_s: float = LOG_EVERY_S, clock: Callable[[], float] = time.monotonic
    ) -> None:
        self.every_s = every_s
        self.clock = clock
        self.counts = {"full": 0, "io": 0}
        self._lock = threading.Lock()
        self._logged_at: dict[str, float] = {}  # file -> when its last line was written
        self._unlogged: dict[str, int] = {}  # file -> failures since that line
        self._failing: dict[str, int] = {}  # file -> failures since its last success

    def failed(self, err: StorageError, file: str, what: str) -> None:
        """Count one failed write of `file` (`what` names it: "history commit", ...)."""
        kind = kind_of(err)
        with self._lock:
            self.counts[kind] += 1
            self._failing[file] = self._failing.get(file, 0) + 1
            self._unlogged[file] = self._unlogged.get(file, 0) + 1
            now = self.clock()
            last = self._logged_at.get(file)
            if last is not None and now - last < self.every_s:
                return
            self._logged_at[file] = now
            count = self._unlogged.pop(file)
        cause = err.__cause__ if err.__cause__ is not None else err
        log.error(
            "storage %s: %s (%s); %d write(s) failed since the last report, the latest a %s; "
            "nothing of them was stored (callers were told to retry)",
            "full" if kind == "full" else "I/O error", cause, file, count, what,
            extra={"event": f"storage_{kind}", "file": file, "failed": count, "what": what},
        )  # fmt: skip

    def ok(self, file: str) -> None:
        """A write of `file` succeeded; cheap when nothing failed before it."""
        if file not in self._failing:
            return
        with self._lock:
            failed = self._failing.pop(file, 0)
            self._logged_at.pop(file, None)
            self._unlogged.pop(file, None)
        if failed:
            log.warning(
                "storage writable again (%s) after %d failed write(s)", file, failed,
                extra={"event": "storage_recovered", "file": file, "failed": failed},
            )  # fmt: skip
