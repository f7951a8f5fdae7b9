"""The storage backends that service-level tests run against, through the store protocols.

A backend is one entry of `BACKENDS`: a function that opens every store of that backend in a
folder (and closes them after). The `stores` fixture, and `history` in `_history.py`, run each
test that takes them once per backend, with the backend's name in the test id
(`test_x[sqlite]`). SQLite is the only one today; PostgreSQL comes as one more entry. A
module opts in by importing the fixture (`from tests.unit._storage import stores as stores`).
"""

from __future__ import annotations

from collections.abc import AsyncIterator, Callable
from contextlib import AbstractAsyncContextManager, AsyncExitStack, asynccontextmanager
from dataclasses import dataclass
from pathlib import Path

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


@asynccontextmanager
async def sqlite_stores(folder: Path) -> AsyncIterator[Stores]:
    data_dir = folder / "data"
    history = SqliteHistory(data_dir, "normal")  # no fsync per commit: tests need no power cuts
    stores = Stores(
        SqliteStore(data_dir), history, SqliteCommands(history), SqliteProperties(history)
    )
    async with opened(stores) as ready:
        yield ready


@asynccontextmanager
async def opened(stores: Stores) -> AsyncIterator[Stores]:
    """Open the stores in the order the app does (history before the stores that write
    through it), and close them in reverse."""
    async with AsyncExitStack() as stack:
        for store in (stores.metadata, stores.history, stores.commands, stores.properties):
            await store.open()
            stack.push_async_callback(store.close)
        yield stores


BACKENDS: dict[str, Callable[[Path], AbstractAsyncContextManager[Stores]]] = {
    "sqlite": sqlite_stores,
}


@pytest.fixture(params=list(BACKENDS))
async def stores(request: pytest.FixtureRequest, tmp_path: Path) -> AsyncIterator[Stores]:
    async with BACKENDS[request.param](tmp_path) as opened_stores:
        yield opened_stores
