"""The command log, written behind the caller: many state changes of a command become one
row per group commit (`CommandStore.save_commands`)."""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Awaitable, Callable, Iterable

from twinlink.domain.commands import CommandRecord
from twinlink.domain.errors import StorageError

log = logging.getLogger("twinlink.commands")
Save = Callable[[list[CommandRecord]], Awaitable[None]]


class WriteBehind:
    """Command state changes, written behind the caller: each change is in the log within one
    group commit, and changes made while a commit runs share the next one (one upsert per
    command, however often its state changed). `sync` waits until everything saved so far is
    committed.

    A write that fails (a full disk) keeps its changes for the next one (unless newer ones
    of the same command came meanwhile) and fails the `sync` calls waiting for it; it is
    tried again with the next `save` or `sync`, not in a loop against a disk that is full."""

    def __init__(self, save: Save) -> None:
        self._write = save
        self._dirty: dict[str, CommandRecord] = {}
        self._waiters: list[asyncio.Future[None]] = []
        self._task: asyncio.Task[None] | None = None
        self.closed = False

    def save(self, record: CommandRecord) -> None:
        if self.closed:  # shutting down: the history file is closing; open commands reload
            return
        self._dirty[record.id] = record
        self._kick()

    async def sync(self) -> None:
        if self._task is None and not self._dirty:
            return
        waiter: asyncio.Future[None] = asyncio.get_running_loop().create_future()
        self._waiters.append(waiter)
        self._kick()
        await waiter

    def _kick(self) -> None:
        if self._task is None:
            self._task = asyncio.create_task(self._run(), name="command-log-writer")

    async def close(self) -> None:
        """Write what is unsaved, then take no more (shutting down). Best effort: on a disk
        that refuses it, open commands reload from what the log last took."""
        try:
            await self.sync()
        except StorageError:
            log.warning("%d command change(s) not written at shutdown: storage failed",
                        len(self._dirty), extra={"event": "command_log_failed"})  # fmt: skip
        self.closed = True

    async def _run(self) -> None:
        try:
            while self._dirty or self._waiters:
                taken = self._dirty
                self._dirty = {}
                waiters, self._waiters = self._waiters, []
                if not taken:
                    _settle(waiters, None)
                    continue
                try:
                    await self._write(list(taken.values()))
                except Exception as err:
                    if not isinstance(err, StorageError):  # the store logged that one
                        log.exception("writing the command log failed",
                                      extra={"event": "command_log_failed"})  # fmt: skip
                    for command_id, record in taken.items():  # newer changes win
                        self._dirty.setdefault(command_id, record)
                    _settle([*waiters, *self._waiters], err)
                    self._waiters = []
                    return
                _settle(waiters, None)
        finally:
            self._task = None


def _settle(waiters: Iterable[asyncio.Future[None]], error: BaseException | None) -> None:
    for waiter in waiters:
        if waiter.done():
            continue
        if error is None:
            waiter.set_result(None)
        else:
            waiter.set_exception(error)
