"""Remote twins: DT documents fetched from another instance (a Twinbase site or another
twinlink) and kept here read-only, with where and when they were fetched.

A remote twin is `reachable` when its last fetch answered (or answered 304 Not Modified),
`stale` when the last check failed but a copy is kept, and `gone` when its instance answered
404 or 410: the copy is kept so that relations to it still show what it was.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal

RemoteState = Literal["reachable", "stale", "gone"]
STATES: tuple[str, ...] = ("reachable", "stale", "gone")
# `source` of a remote twin fetched because a relation named it, not by an import of a site.
FROM_RELATION = "relation"


@dataclass(slots=True)
class RemoteTwin:
    id: int
    dt_id: str  # the document's dt-id (or its id), else the URL it was fetched from
    url: str  # where the document was fetched: its hosting-iri
    name: str
    document: dict[str, Any] = field(default_factory=dict)  # as fetched, every key kept
    source: str = FROM_RELATION  # the site imported (its URL), or "relation"
    fetched_ns: int = 0  # when the copy was last fetched (a 200)
    checked_ns: int = 0  # when it was last asked for (a 200, a 304 or an error)
    etag: str | None = None
    last_modified: str | None = None
    state: str = "reachable"
    error: str = ""  # why the last check failed (stale, gone)
