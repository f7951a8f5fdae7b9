"""A minimal HTTP/1.1 keep-alive client, and closed-loop workers on it.

httpx spends 2.5-6 ms of CPU per request in this benchmark (its connection pool checks every
connection's socket on each request), more than the server spends on a command round trip;
on 2 shared CPUs that would measure httpx. This client writes a prepared request and reads
one `Content-Length` answer: tens of microseconds. It knows only what twinlink's answers need
(no chunked bodies, no redirects, no TLS).
"""

from __future__ import annotations

import asyncio
import itertools
import math
import statistics
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any
from urllib.parse import urlsplit

Make = Callable[[int], tuple[str, str, bytes]]  # i -> (method, path, body)
Check = Callable[[int, bytes], str | None]  # status, body -> problem or None


class RawHttp:
    """One keep-alive connection to `url` sending `headers` with every request."""

    def __init__(self, url: str, headers: dict[str, str]) -> None:
        parts = urlsplit(url)
        self.host, self.port = parts.hostname or "127.0.0.1", parts.port or 80
        lines = [f"Host: {self.host}:{self.port}", *(f"{k}: {v}" for k, v in headers.items())]
        self.head = "\r\n".join(lines)
        self.reader: asyncio.StreamReader | None = None
        self.writer: asyncio.StreamWriter | None = None

    async def request(self, method: str, path: str, body: bytes = b"") -> tuple[int, bytes]:
        if self.writer is None or self.writer.is_closing():
            self.reader, self.writer = await asyncio.open_connection(self.host, self.port)
        assert self.reader is not None
        length = f"\r\nContent-Length: {len(body)}" if body or method != "GET" else ""
        self.writer.write(
            f"{method} {path} HTTP/1.1\r\n{self.head}{length}\r\n\r\n".encode() + body
        )
        answer = await self.reader.readuntil(b"\r\n\r\n")
        status = int(answer[9:12])
        size, close = 0, False
        for line in answer.split(b"\r\n")[1:]:
            name, _, value = line.partition(b":")
            name = name.strip().lower()
            if name == b"content-length":
                size = int(value)
            elif name == b"transfer-encoding":
                raise RuntimeError(f"{path}: a {value.strip().decode()} answer is not supported")
            elif name == b"connection" and value.strip().lower() == b"close":
                close = True
        data = await self.reader.readexactly(size)
        if close:
            await self.close()
        return status, data

    async def close(self) -> None:
        if self.writer is not None:
            self.writer.close()
            self.writer = None


@dataclass
class LoopResult:
    concurrency: int
    requests: int = 0
    errors: int = 0
    first_error: str | None = None
    seconds: float = 0.0
    rps: float = 0.0
    p50_ms: float = math.nan
    p90_ms: float = math.nan
    p99_ms: float = math.nan
    max_ms: float = math.nan
    mean_ms: float = math.nan
    latencies_ms: list[float] = field(default_factory=list, repr=False)

    def summary(self) -> dict[str, Any]:
        return {k: v for k, v in vars(self).items() if k != "latencies_ms"}


def percentile(ordered: list[float], q: float) -> float:
    """Nearest rank of an already sorted list."""
    if not ordered:
        return math.nan
    return ordered[min(len(ordered), max(1, math.ceil(q * len(ordered)))) - 1]


async def closed_loop(
    url: str,
    headers: dict[str, str],
    make: Make,
    check: Check,
    concurrency: int,
    max_requests: int,
    max_seconds: float,
    warmup: int = 20,
) -> LoopResult:
    """`concurrency` workers, each on its own connection, each sending its next request when
    the answer to the last one is read, until `max_requests` or `max_seconds`. The first
    `warmup` requests (indices past the measured ones) are not counted."""
    result = LoopResult(concurrency)
    clients = [RawHttp(url, headers) for _ in range(concurrency)]
    warm = itertools.count()
    for_real = itertools.count()
    stamps: list[float] = []

    async def worker(client: RawHttp) -> None:
        while (i := next(warm)) < warmup:
            await client.request(*make(max_requests + i))
        deadline = time.perf_counter() + max_seconds
        while (i := next(for_real)) < max_requests and time.perf_counter() < deadline:
            t0 = time.perf_counter()
            try:
                status, body = await client.request(*make(i))
                problem = check(status, body)
            except (OSError, asyncio.IncompleteReadError, RuntimeError) as err:
                problem = f"{type(err).__name__}: {err}"
            stamps.append(t0)
            result.latencies_ms.append(1000 * (time.perf_counter() - t0))
            if problem is not None:
                result.errors += 1
                result.first_error = result.first_error or problem

    start = time.perf_counter()
    try:
        await asyncio.gather(*(worker(c) for c in clients))
    finally:
        await asyncio.gather(*(c.close() for c in clients))
    _summarise(result, min(stamps, default=start))
    return result


def _summarise(result: LoopResult, start: float) -> None:
    ordered = sorted(result.latencies_ms)
    result.requests = len(ordered)
    result.seconds = time.perf_counter() - start
    result.rps = result.requests / result.seconds if result.seconds else 0.0
    if ordered:
        result.p50_ms, result.p90_ms = percentile(ordered, 0.5), percentile(ordered, 0.9)
        result.p99_ms, result.max_ms = percentile(ordered, 0.99), ordered[-1]
        result.mean_ms = statistics.fmean(ordered)
