"""The SQLite store: one file in the data dir, opened in WAL mode, migrated on open."""

from __future__ import annotations

from pathlib import Path

from twinlink.store.sqlite.connectors import ConnectorTables
from twinlink.store.sqlite.cosims import CosimTables
from twinlink.store.sqlite.db import Database
from twinlink.store.sqlite.deployments import DeploymentTables
from twinlink.store.sqlite.devices import DeviceTables
from twinlink.store.sqlite.faults import StorageFaults
from twinlink.store.sqlite.gateway import GatewayTables
from twinlink.store.sqlite.library import LibraryTables
from twinlink.store.sqlite.processors import ProcessorTables
from twinlink.store.sqlite.remote import RemoteTables
from twinlink.store.sqlite.runs import RunTables
from twinlink.store.sqlite.search import SearchTables
from twinlink.store.sqlite.twins import TwinTables
from twinlink.store.sqlite.users import UserTables


class SqliteStore(
    UserTables,
    TwinTables,
    SearchTables,
    DeviceTables,
    ProcessorTables,
    GatewayTables,
    ConnectorTables,
    DeploymentTables,
    LibraryTables,
    RunTables,
    CosimTables,
    RemoteTables,
):
    """Metadata store of users, tokens, twins, relations, devices, the search index,
    processors and FMUs, gateway services and connectors."""

    FILE_NAME = "twinlink.sqlite3"

    def __init__(self, data_dir: Path, faults: StorageFaults | None = None) -> None:
        self.db = Database(Path(data_dir) / self.FILE_NAME, faults)

    async def open(self) -> None:
        await self.db.open()

    async def close(self) -> None:
        await self.db.close()

    async def ping(self) -> bool:
        return bool(await self.db.read(lambda c: c.execute("SELECT 1").fetchone()[0]))
