"""When tokens and devices were last used, written behind the requests that use them.

Authentication must neither wait for nor fail with a write: while the disk was full, the
write of a "last used" time once turned every HTTP request into a 500 and every new device
connection into an abort. The times are kept in memory instead (the newest per token and
per device) and written in one statement per kind every `every_s` seconds and at shutdown.
A write that fails keeps them for the next try and is logged once until one succeeds; no
request ever sees it. Lists of tokens and devices show the newer of the stored time and the
one waiting here.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging

from twinlink.store.base import MetadataStore

log = logging.getLogger("twinlink.auth")

WRITE_EVERY_S = 5.0


class LastUsed:
    def __init__(self, store: MetadataStore, every_s: float = WRITE_EVERY_S) -> None:
        self.store = store
        self.every_s = every_s
        self._tokens: dict[int, int] = {}  # id -> ns, not yet written
        self._devices: dict[int, int] = {}
        self._stop = asyncio.Event()
        self._task: asyncio.Task[None] | None = None
        self._failing = False

    def token_used(self, token_id: int, now_ns: int) -> None:
        _keep_newest(self._tokens, token_id, now_ns)

    def device_seen(self, device_id: int, now_ns: int) -> None:
        _keep_newest(self._devices, device_id, now_ns)

    def token_time(self, token_id: int, stored: int | None) -> int | None:
        """The newer of `stored` and the time waiting to be written."""
        return _newer(stored, self._tokens.get(token_id))

    def device_time(self, device_id: int, stored: int | None) -> int | None:
        return _newer(stored, self._devices.get(device_id))

    def start(self) -> None:
        self._stop.clear()
        self._task = asyncio.create_task(self._run(), name="last-used-writer")

    async def close(self) -> None:
        """Stop writing every few seconds, after writing what waits (best effort)."""
        self._stop.set()
        if self._task is not None:
            await self._task
            self._task = None
        else:
            await self.write()

    async def _run(self) -> None:
        # An event rather than cancel(): a write under way always finishes, and the last
        # one runs after close() was called.
        while True:
            with contextlib.suppress(TimeoutError):
                await asyncio.wait_for(self._stop.wait(), self.every_s)
            await self.write()
            if self._stop.is_set():
                return

    async def write(self) -> bool:
        """Write the waiting times; False (logged once until it works again) when the store
        refused them, which are then kept for the next try."""
        tokens, self._tokens = self._tokens, {}
        devices, self._devices = self._devices, {}
        try:
            if tokens:
                await self.store.touch_tokens(tokens)
            if devices:
                await self.store.touch_devices(devices)
        except Exception as err:
            for token_id, ns in tokens.items():
                _keep_newest(self._tokens, token_id, ns)
            for device_id, ns in devices.items():
                _keep_newest(self._devices, device_id, ns)
            if not self._failing:
                self._failing = True
                log.warning(
                    "could not write when tokens and devices were last used (kept in memory, "
                    "tried again every %g s): %s", self.every_s, err,
                    extra={"event": "last_used_failed"},
                )  # fmt: skip
            return False
        if self._failing:
            self._failing = False
            log.info("last-used times written again", extra={"event": "last_used_written"})
        return True


def _keep_newest(times: dict[int, int], key: int, ns: int) -> None:
    if times.get(key, ns - 1) < ns:
        times[key] = ns


def _newer(a: int | None, b: int | None) -> int | None:
    if a is None:
        return b
    return a if b is None else max(a, b)
