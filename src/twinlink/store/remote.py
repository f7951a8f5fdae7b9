"""Remote twins (federation/remote.py): documents of other instances, kept read-only.

A remote twin is one row per dt-id: fetching it again (an import, a refresh, a relation
followed) writes over the row, so a site imported twice holds each twin once.
"""

from __future__ import annotations

from typing import Any, Protocol

import orjson

from twinlink.domain.remote import RemoteTwin

# The columns every backend reads, in the order `remote_of` takes them.
COLUMNS = (
    "id, dt_id, url, name, document, source, fetched_ns, checked_ns, etag, last_modified,"
    " state, error"
)


def remote_of(row: Any) -> RemoteTwin:
    """A remote twin from a row of COLUMNS (SQLite's or PostgreSQL's)."""
    return RemoteTwin(
        id=row[0], dt_id=row[1], url=row[2], name=row[3], document=orjson.loads(row[4]),
        source=row[5], fetched_ns=row[6], checked_ns=row[7], etag=row[8],
        last_modified=row[9], state=row[10], error=row[11],
    )  # fmt: skip


def values_of(twin: RemoteTwin) -> tuple[object, ...]:
    """The twin's values in COLUMNS' order, but for the id (the document as JSON text)."""
    return (
        twin.dt_id, twin.url, twin.name, orjson.dumps(twin.document).decode(), twin.source,
        twin.fetched_ns, twin.checked_ns, twin.etag, twin.last_modified, twin.state, twin.error,
    )  # fmt: skip


def like_pattern(q: str) -> str:
    """`q` as a LIKE pattern matching it anywhere, its wildcards taken literally (ESCAPE '\\')."""
    escaped = q.replace("\\", "\\\\").replace("%", "\\%").replace("_", "\\_")
    return f"%{escaped.lower()}%"


class RemoteTwinStore(Protocol):
    async def put_remote_twin(self, twin: RemoteTwin) -> RemoteTwin:
        """Insert the twin, or write over the row of its dt-id (keeping that row's id);
        returns it with its id."""
        ...

    async def get_remote_twin(self, remote_id: int) -> RemoteTwin | None: ...

    async def get_remote_twin_by_dt_id(self, dt_id: str) -> RemoteTwin | None: ...

    async def get_remote_twin_by_url(self, url: str) -> RemoteTwin | None: ...

    async def list_remote_twins(self, q: str | None = None, limit: int = 1000) -> list[RemoteTwin]:
        """By name, then id; when `q` is given, only those whose name, dt-id, url or document
        (any of its text) contains it, in any case."""
        ...

    async def delete_remote_twin(self, remote_id: int) -> bool:
        """Remove the row; False when there was none."""
        ...
