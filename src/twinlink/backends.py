"""The backends the composition root picks from the settings (app.py builds the services on
them): the stores, SQLite files in the data dir (the default) or one PostgreSQL database
(TWINLINK_STORE_URL), and the bus, in-process (the default) or Kafka (TWINLINK_BUS_URL).
Nothing else chooses an implementation; the rest sees the protocols of store/ and bus/."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Protocol

from twinlink.bus import Bus, MemoryBus
from twinlink.config import Settings
from twinlink.domain.backend_urls import kafka_bootstrap
from twinlink.store.base import MetadataStore
from twinlink.store.commands import CommandStore, PropertyStore
from twinlink.store.history import HistoryStore
from twinlink.store.leases import Claims, LeaseStore, new_holder
from twinlink.store.sqlite import SqliteStore
from twinlink.store.sqlite.commands import SqliteCommands
from twinlink.store.sqlite.faults import StorageFaults
from twinlink.store.sqlite.history import ReadLimits, SqliteHistory
from twinlink.store.sqlite.properties import SqliteProperties
from twinlink.store.tokens import SharedTokens


class Shared(Protocol):
    """What the stores of a backend share (PostgreSQL's pool of connections)."""

    async def open(self) -> None: ...

    async def close(self) -> None: ...


@dataclass(frozen=True, slots=True)
class Storage:
    """The stores in use, each behind its protocol (store/). Picking their implementation is
    this module's alone: SQLite files in the data dir (the default) or one PostgreSQL
    database (TWINLINK_STORE_URL)."""

    metadata: MetadataStore
    history: HistoryStore
    commands: CommandStore
    properties: PropertyStore
    # The backend's own counters for /metrics: group commits, writes failed by kind.
    figures: Callable[[], dict[str, int]]
    # Opened before the stores and closed after them; None when each opens its own files.
    shared: Shared | None = None
    # Which node runs each processor and connector; None when one node has the store alone
    # (SQLite), which runs them all, as it always did.
    leases: LeaseStore | None = None
    holder: str = field(default_factory=new_holder)  # this node's run, in the leases it holds
    # The gateway's upstream tokens, one login among the nodes; None with one node (SQLite),
    # whose gateway keeps its tokens in memory.
    tokens: SharedTokens | None = None

    def claims(self, kind: str) -> Claims | None:
        """The leases of one kind of item this node holds; None on the embedded store."""
        return Claims(self.leases, kind, self.holder) if self.leases is not None else None


def pick_storage(settings: Settings) -> Storage:
    """The stores TWINLINK_STORE_URL names: PostgreSQL's, or the embedded SQLite files."""
    if settings.store_url.get_secret_value():
        return postgres_storage(settings)
    return sqlite_storage(settings)


def sqlite_storage(settings: Settings) -> Storage:
    """The embedded stores: metadata.db and history.db in the data dir (the command log and
    properties share history.db's writer and its commits)."""
    faults = StorageFaults()  # disk failures of both files, counted for /metrics
    history = SqliteHistory(
        settings.data_dir,
        settings.history_sync,
        max_signals_per_stream=settings.max_signals_per_stream,
        faults=faults,
        limits=ReadLimits(
            timeout_s=settings.history_query_timeout_s,
            export_timeout_s=settings.history_export_timeout_s,
            max_values=settings.history_query_max_values,
        ),
    )

    def figures() -> dict[str, int]:
        return {
            "history_commits": history.writer.commits,
            "storage_full": faults.counts["full"],
            "storage_io_errors": faults.counts["io"],
        }

    return Storage(
        metadata=SqliteStore(settings.data_dir, faults),
        history=history,
        commands=SqliteCommands(history),
        properties=SqliteProperties(history),
        figures=figures,
    )


def postgres_storage(settings: Settings) -> Storage:
    """The scale-out stores: every table in the one PostgreSQL database at TWINLINK_STORE_URL,
    which every node shares (docs/scale-out.md); the stores share one pool of connections."""
    # Imported here: the embedded default does not load asyncpg and this backend's modules.
    from twinlink.store.postgres.commands import PostgresCommands
    from twinlink.store.postgres.db import PostgresDatabase
    from twinlink.store.postgres.history import PostgresHistory
    from twinlink.store.postgres.history import ReadLimits as PostgresReadLimits
    from twinlink.store.postgres.leases import PostgresLeases
    from twinlink.store.postgres.metadata import PostgresMetadataStore
    from twinlink.store.postgres.properties import PostgresProperties
    from twinlink.store.postgres.tokens import PostgresTokens

    db = PostgresDatabase(settings.store_url.get_secret_value())
    history = PostgresHistory(
        db,
        max_signals_per_stream=settings.max_signals_per_stream,
        limits=PostgresReadLimits(
            timeout_s=settings.history_query_timeout_s,
            export_timeout_s=settings.history_export_timeout_s,
            max_values=settings.history_query_max_values,
        ),
    )

    def figures() -> dict[str, int]:
        # Not counted by this backend: each batch is a transaction of its own (no group
        # commits), and a full disk or a failed write is the server's, in its own log.
        return {"history_commits": 0, "storage_full": 0, "storage_io_errors": 0}

    return Storage(
        metadata=PostgresMetadataStore(db),
        history=history,
        commands=PostgresCommands(db),
        properties=PostgresProperties(db),
        figures=figures,
        shared=db,
        leases=PostgresLeases(db),
        tokens=PostgresTokens(db),
    )


def pick_bus(settings: Settings) -> Bus:
    """The bus TWINLINK_BUS_URL names: Kafka's, shared by every node, or the in-process one."""
    if settings.bus_url:
        from twinlink.bus.kafka import KafkaBus  # loads aiokafka: only when it is used

        return KafkaBus(
            kafka_bootstrap(settings.bus_url), publish_timeout_s=settings.bus_publish_timeout_s
        )
    return MemoryBus()
