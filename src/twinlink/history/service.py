"""Reading a twin's history: who may, which range is meant, and answers ready for JSON.

Anyone with a role on a twin (viewer, editor, owner) and platform admins may read its
history. A twin the caller may not see is not found (404), as everywhere; a twin the caller
sees (a public part) but has no role on is forbidden (403).
"""

from __future__ import annotations

import time
from collections.abc import AsyncIterator, Callable
from dataclasses import dataclass
from typing import Any

import orjson

from twinlink.auth.rights import Principal, has_role
from twinlink.domain.errors import ForbiddenError
from twinlink.domain.history import MAX_TIME, MEDIA_TYPES, MIN_TIME
from twinlink.domain.records import TwinRecord
from twinlink.history.params import QueryError, format_cursor, human_ns, iso_ns
from twinlink.registry.service import RegistryService
from twinlink.store.history import HistoryReadStore

MAX_BUCKETS = 100_000
_INT64 = 2**63


@dataclass(frozen=True, slots=True)
class Selection:
    """Which samples a query is about: signals (None for all) of one stream, in [start, end]
    (ns, inclusive; MIN_TIME/MAX_TIME when open)."""

    stream: str
    signals: list[str] | None = None
    start: int = MIN_TIME
    end: int = MAX_TIME

    def check(self) -> None:
        if self.start > self.end:
            raise QueryError(
                f"`start` ({iso_ns(self.start)}) is after `end` ({iso_ns(self.end)}); swap them"
            )

    def echo(self) -> dict[str, Any]:
        return {
            "stream": self.stream,
            "start": None if self.start == MIN_TIME else self.start,
            "end": None if self.end == MAX_TIME else self.end,
        }


@dataclass(slots=True)
class Export:
    filename: str
    media_type: str
    signals: list[str]
    body: AsyncIterator[bytes]


class HistoryService:
    def __init__(
        self,
        registry: RegistryService,
        history: HistoryReadStore,
        clock: Callable[[], int] = time.time_ns,
    ) -> None:
        self.registry = registry
        self.history = history
        self.clock = clock

    async def twin(self, principal: Principal, slug: str) -> TwinRecord:
        twin, role = await self.registry.require_twin(principal, slug)
        if not has_role(principal, role, "viewer"):
            raise ForbiddenError(f"the history of {slug!r} needs a role on it (viewer or more)")
        return twin

    async def streams(self, principal: Principal, slug: str) -> dict[str, Any]:
        twin = await self.twin(principal, slug)
        return {"twin": twin.slug, "streams": await self.history.streams(twin.id)}

    async def latest(
        self, principal: Principal, slug: str, stream: str, signals: list[str] | None
    ) -> dict[str, Any]:
        twin = await self.twin(principal, slug)
        values = await self.history.latest(twin.id, stream, signals)
        return {"twin": twin.slug, "stream": stream, "values": values}

    async def samples(
        self,
        principal: Principal,
        slug: str,
        sel: Selection,
        limit: int,
        after: tuple[int, int] | None,
    ) -> dict[str, Any]:
        sel.check()
        twin = await self.twin(principal, slug)
        page = await self.history.samples(
            twin.id, sel.stream, sel.signals, sel.start, sel.end, limit, after
        )
        return {
            "twin": twin.slug,
            **sel.echo(),
            "rows": page.rows,
            "next_cursor": format_cursor(page.next_key) if page.next_key else None,
        }

    async def _clamped(self, twin: TwinRecord, sel: Selection) -> tuple[int, int] | None:
        """[start, end] narrowed to the stored data, None when the range holds none."""
        extent = await self.history.extent(twin.id, sel.stream, sel.signals)
        if extent is None:
            return None
        start, end = max(sel.start, extent[0]), min(sel.end, extent[1])
        return (start, end) if start <= end else None

    async def aggregate(
        self, principal: Principal, slug: str, sel: Selection, bucket_ns: int, fns: list[str]
    ) -> dict[str, Any]:
        sel.check()
        twin = await self.twin(principal, slug)
        answer: dict[str, Any] = {
            "twin": twin.slug,
            **sel.echo(),
            "bucket": human_ns(bucket_ns),
            "bucket_ns": bucket_ns,
            "fn": fns,
            "rows": [],
            "skipped": [],
        }
        clamped = await self._clamped(twin, sel)
        if clamped is None:
            return answer
        start, end = clamped
        buckets = end // bucket_ns - start // bucket_ns + 1
        if buckets > MAX_BUCKETS:
            raise QueryError(
                f"the range holds {buckets} buckets of {human_ns(bucket_ns)}; at most "
                f"{MAX_BUCKETS} are allowed: widen `bucket` or narrow `start`/`end`"
            )
        result = await self.history.aggregate(
            twin.id, sel.stream, sel.signals, start, end, bucket_ns, fns
        )
        answer["skipped"] = _text_signals(sel, result.text_only, "aggregate")
        answer["rows"] = _exact_sums(result.rows)
        return answer

    async def downsample(
        self, principal: Principal, slug: str, sel: Selection, points: int, method: str
    ) -> dict[str, Any]:
        sel.check()
        twin = await self.twin(principal, slug)
        answer: dict[str, Any] = {
            "twin": twin.slug,
            **sel.echo(),
            "method": method,
            "points": points,
            "signals": {},
            "skipped": [],
        }
        clamped = await self._clamped(twin, sel)
        if clamped is None:
            return answer
        result = await self.history.downsample(
            twin.id, sel.stream, sel.signals, *clamped, points, method
        )
        text = [name for name, r in result.items() if r.text_only]
        answer["skipped"] = _text_signals(sel, text, "downsample")
        answer["signals"] = {
            name: {"time": r.times.tolist(), "value": r.values.tolist()}
            for name, r in result.items()
            if not r.text_only
        }
        return answer

    async def export(
        self, principal: Principal, slug: str, sel: Selection, fmt: str, time_format: str
    ) -> Export:
        sel.check()
        twin = await self.twin(principal, slug)
        signals, body = await self.history.export(
            twin.id, sel.stream, sel.signals, sel.start, sel.end, fmt, time_format
        )
        return Export(f"{twin.slug}-{sel.stream}.{fmt}", MEDIA_TYPES[fmt], signals, body)


def _exact_sums(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Sums of integers are exact Python ints; one beyond 64 bits (which orjson cannot write
    as a number) goes out as its exact digits all the same."""
    for row in rows:
        for value in row["values"].values():
            total = value.get("sum")
            if type(total) is int and not -_INT64 <= total < 2 * _INT64:
                value["sum"] = orjson.Fragment(str(total).encode())
    return rows


def _text_signals(sel: Selection, text: list[str], what: str) -> list[str]:
    """Signals holding text cannot be aggregated or downsampled: refused when asked for by
    name, left out (and listed) when every signal was asked for."""
    if text and sel.signals is not None:
        raise QueryError(
            f"cannot {what} {', '.join(map(repr, text))}: it holds text, not numbers. "
            "Ask /samples or /export for its values, or leave it out of `signals`"
        )
    return text
