"""Co-simulations made through the API (cosim/service.py): their records.

A record is written `created` with its id, saved whole as its run goes (state, progress,
columns), and deleted with its folder. A node that starts a run writes itself as the
record's `node`, so that a server starting again fails only the runs it (or a node of its
host that is gone) left `running`.
"""

from __future__ import annotations

from typing import Any, Protocol

import orjson

from twinlink.domain.cosims import CosimRecord

# The columns every backend reads, in the order `cosim_of` takes them.
COLUMNS = (
    "id, name, owner_id, twin, prefix, stream, mode, factor, state, format, document, fmus,"
    " system, result_columns, row_count, progress, sim_time, message, created_ns, started_ns,"
    " ended_ns, node"
)


def cosim_of(row: Any) -> CosimRecord:
    """A co-simulation from a row of COLUMNS (SQLite's or PostgreSQL's)."""
    return CosimRecord(
        id=row[0], name=row[1], owner_id=row[2], twin=row[3], prefix=row[4], stream=row[5],
        mode=row[6], factor=row[7], state=row[8], format=row[9], document=row[10],
        fmus=orjson.loads(row[11]), system=orjson.loads(row[12]), columns=orjson.loads(row[13]),
        rows=row[14], progress=row[15], sim_time=row[16], message=row[17], created_ns=row[18],
        started_ns=row[19], ended_ns=row[20], node=row[21],
    )  # fmt: skip


def values_of(record: CosimRecord) -> tuple[object, ...]:
    """The record's values in COLUMNS' order, but for the id (JSON fields as text)."""
    return (
        record.name, record.owner_id, record.twin, record.prefix, record.stream, record.mode,
        record.factor, record.state, record.format, record.document,
        orjson.dumps(record.fmus).decode(), orjson.dumps(record.system).decode(),
        orjson.dumps(record.columns).decode(), record.rows, record.progress, record.sim_time,
        record.message, record.created_ns, record.started_ns, record.ended_ns, record.node,
    )  # fmt: skip


class CosimStore(Protocol):
    async def create_cosim(self, record: CosimRecord) -> CosimRecord:
        """Store a new co-simulation (its `id` is assigned) and return it."""
        ...

    async def save_cosim(self, record: CosimRecord) -> None:
        """Write every field of the record but its id."""
        ...

    async def get_cosim(self, cosim_id: int) -> CosimRecord | None: ...

    async def list_cosims(self, state: str | None = None) -> list[CosimRecord]:
        """Newest first; of one state when `state` is given."""
        ...

    async def delete_cosim(self, cosim_id: int) -> bool:
        """Remove the record; False when there was none."""
        ...

    async def fail_running_cosims(
        self, nodes: list[str] | None, message: str, now_ns: int
    ) -> list[CosimRecord]:
        """Mark failed the co-simulations left `running` by the nodes `nodes` (every one
        when None), with `message`; those changed, as they were."""
        ...
