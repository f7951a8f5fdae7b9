"""What running processors tell: their events (stored; crashes and failures also logged) and
their blueprints' commands (sent with the rights of the processor's creator), each done in
the background so a worker's answer never waits on the store; and, at a start, which
processors had finished."""

from __future__ import annotations

import asyncio
import logging
import time
from typing import Any

from twinlink.auth.rights import Principal
from twinlink.commands import CommandService
from twinlink.domain.errors import InvalidInputError
from twinlink.domain.records import ProcessorRecord
from twinlink.processors.workerenv import EventTuple
from twinlink.store.base import MetadataStore

log = logging.getLogger("twinlink.processors")
NOTABLE = {"crashed", "failed", "memory_limit", "hung"}


async def finished_before(store: MetadataStore, records: list[ProcessorRecord]) -> dict[int, str]:
    """The enabled processors that were finished when the server stopped (their newest
    event says so): they stay finished until started again through the API."""
    finished = {}
    for record in records:
        if record.enabled:
            newest = await store.list_processor_events(record.id, 1)
            if newest and newest[0].kind == "finished":
                finished[record.id] = newest[0].message
    return finished


class Reports:
    def __init__(self, store: MetadataStore, commands: CommandService) -> None:
        self.store = store
        self.commands = commands
        self._background: set[asyncio.Task[Any]] = set()

    def events(self, record: ProcessorRecord, events: list[EventTuple]) -> None:
        for kind, message, _, data in events:
            if kind in NOTABLE:
                extra = {"event": f"processor_{kind}", "exit_code": data.get("exit_code")}
                log.warning(
                    "processor %s/%s %s: %s", record.twin_slug, record.name, kind, message,
                    extra=extra,
                )  # fmt: skip
        rows = [(record.id, t or time.time_ns(), k, m, d) for k, m, t, d in events]
        self.spawn(self.store.add_processor_events(rows))

    def send_commands(self, record: ProcessorRecord, commands: list[list[Any]]) -> None:
        for name, params, device in commands:
            self.spawn(self._send_command(record, name, params, device))

    async def _send_command(
        self, record: ProcessorRecord, name: str, params: dict[str, Any], device: str | None
    ) -> None:
        """A blueprint's command goes out with the rights of the processor's creator."""
        user = await self.store.get_user(record.created_by) if record.created_by else None
        try:
            if user is None:
                raise InvalidInputError("the processor's creator no longer exists")
            sent = await self.commands.send(
                Principal(user), record.twin_slug, name, params or None, device, wait=False
            )
            event = (
                "command",
                f"sent {name}",
                time.time_ns(),
                {"id": sent.id, "state": sent.state},
            )
        except Exception as err:  # a refused command is an event, not a crash
            event = ("command_failed", f"{name}: {err}", time.time_ns(), {})
        self.events(record, [event])

    def spawn(self, coro: Any) -> None:
        task = asyncio.ensure_future(coro)
        self._background.add(task)
        task.add_done_callback(self._background.discard)

    async def drain(self) -> None:
        """Wait for what is under way (the server stops)."""
        if self._background:
            await asyncio.gather(*self._background, return_exceptions=True)
