"""The interfaces of the command log and of device properties (SQLite now, PostgreSQL later).

`CommandService` and `PropertyService` reach their storage only through these; `app.py`
picks the implementation. Every write returns once it is durable.
"""

from __future__ import annotations

from typing import Protocol

from twinlink.domain.commands import CommandRecord
from twinlink.domain.properties import DeviceProperties


class CommandStore(Protocol):
    """The command log: every command sent, with its latest state."""

    async def open(self) -> None: ...

    async def close(self) -> None: ...

    async def save_commands(self, records: list[CommandRecord]) -> None:
        """Insert the commands, or update the state of those already stored (their state,
        delivery, finish, result, error and late status), all in one commit."""
        ...

    async def get_command(self, command_id: str) -> CommandRecord | None: ...

    async def list_commands(
        self, twin_id: int, state: str | None, name: str | None, device: str | None, limit: int
    ) -> list[CommandRecord]:
        """The twin's commands, newest first, filtered by the arguments that are not None."""
        ...

    async def open_commands(self) -> list[CommandRecord]:
        """Every pending or delivered command, oldest first (taken up again at start)."""
        ...

    async def delete_commands_of(self, twin_ids: list[int]) -> None: ...


class PropertyStore(Protocol):
    """Each device's reported and desired properties and the version of its desired set."""

    async def open(self) -> None: ...

    async def close(self) -> None: ...

    async def load_properties(
        self, device_id: int, twin_id: int, created_ns: int
    ) -> DeviceProperties:
        """The device's stored properties; empty when none are stored, or only those of a
        deleted device that had the same id (`created_ns` tells them apart)."""
        ...

    async def save_properties(self, props: DeviceProperties, names: list[str]) -> None:
        """Store the version and the properties `names` as they are at the call (the
        values are taken before anything is awaited)."""
        ...

    async def delete_properties_of(self, twin_ids: list[int]) -> None: ...
