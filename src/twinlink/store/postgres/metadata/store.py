"""The metadata store in PostgreSQL: the tables of migrations 0010 and 0020 in the database
the backend's stores share (db.py), which the composition root opens before this."""

from __future__ import annotations

from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.postgres.metadata.connectors import ConnectorTables
from twinlink.store.postgres.metadata.cosims import CosimTables
from twinlink.store.postgres.metadata.deployments import DeploymentTables
from twinlink.store.postgres.metadata.devices import DeviceTables
from twinlink.store.postgres.metadata.gateway import GatewayTables
from twinlink.store.postgres.metadata.library import LibraryTables
from twinlink.store.postgres.metadata.processors import ProcessorTables
from twinlink.store.postgres.metadata.remote import RemoteTables
from twinlink.store.postgres.metadata.runs import RunTables
from twinlink.store.postgres.metadata.search import SearchTables
from twinlink.store.postgres.metadata.twins import TwinTables
from twinlink.store.postgres.metadata.users import UserTables


class PostgresMetadataStore(
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

    def __init__(self, db: PostgresDatabase) -> None:
        self.db = db

    async def open(self) -> None:
        """Nothing of its own to open: the shared database is opened (and migrated) first."""

    async def close(self) -> None:
        """Nothing of its own to close."""

    async def ping(self) -> bool:
        async with self.db.connection() as conn:
            return bool(await conn.fetchval("SELECT true"))
