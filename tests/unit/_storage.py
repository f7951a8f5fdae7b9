"""The storage backends that service-level tests run against, through the store protocols.

A backend is one entry of `BACKENDS`: an object that opens the stores of that backend with
their data in a folder (and closes them after). The `stores` fixture, and `history` in
`_history.py`, run each test that takes them once per backend, with the backend's name in
the test id (`test_x[sqlite]`). SQLite is the only one here, so the unit run needs no
server; tests/integration/test_postgres_*.py run the same test functions on PostgreSQL
(`tests/integration/_postgres.py`). A module opts in by importing the fixture
(`from tests.unit._storage import stores as stores`).
"""

from __future__ import annotations

from collections.abc import AsyncIterator
from contextlib import AbstractAsyncContextManager, AsyncExitStack, asynccontextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

import pytest

from twinlink.store.base import MetadataStore
from twinlink.store.commands import CommandStore, PropertyStore
from twinlink.store.history import HistoryStore
from twinlink.store.sqlite import SqliteStore
from twinlink.store.sqlite.commands import SqliteCommands
from twinlink.store.sqlite.history import SqliteHistory
from twinlink.store.sqlite.properties import SqliteProperties


@dataclass(frozen=True, slots=True)
class Stores:
    """One backend's stores, open."""

    metadata: MetadataStore
    history: HistoryStore
    commands: CommandStore
    properties: PropertyStore


class Backend(Protocol):
    def stores(self, folder: Path) -> AbstractAsyncContextManager[Stores]:
        """Every store of the backend, open, with its data in `folder`."""
        ...

    def history(self, folder: Path) -> AbstractAsyncContextManager[HistoryStore]:
        """The history store alone (what most history tests need)."""
        ...


class SqliteBackend:
    @asynccontextmanager
    async def stores(self, folder: Path) -> AsyncIterator[Stores]:
        history = SqliteHistory(folder / "data", "normal")  # no fsync: no power cuts here
        stores = Stores(
            SqliteStore(folder / "data"), history, SqliteCommands(history),
            SqliteProperties(history),
        )  # fmt: skip
        async with opened(stores.metadata, history, stores.commands, stores.properties):
            yield stores

    @asynccontextmanager
    async def history(self, folder: Path) -> AsyncIterator[HistoryStore]:
        history = SqliteHistory(folder / "data", "normal")
        async with opened(history):
            yield history


class _Openable(Protocol):
    async def open(self) -> None: ...

    async def close(self) -> None: ...


@asynccontextmanager
async def opened(*stores: _Openable) -> AsyncIterator[None]:
    """Open the stores in this order (as the app does: history before the stores that write
    through it), and close them in reverse."""
    async with AsyncExitStack() as stack:
        for store in stores:
            await store.open()
            stack.push_async_callback(store.close)
        yield


BACKENDS: dict[str, Backend] = {
    "sqlite": SqliteBackend(),
}


@pytest.fixture(params=list(BACKENDS))
async def stores(request: pytest.FixtureRequest, tmp_path: Path) -> AsyncIterator[Stores]:
    async with BACKENDS[request.param].stores(tmp_path) as opened_stores:
        yield opened_stores
