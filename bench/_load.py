"""The HTTP load generator: closed-loop workers on one async httpx client.

A case is a base URL, a way to build the i-th request and a way to check its answer. `run_case`
sends warm-up requests, then the measured ones, and returns the latency percentiles together
with the CPU the server, this client and the rest of the machine used meanwhile.
"""

from __future__ import annotations

import asyncio
import contextlib
import itertools
import math
import statistics
import time
from collections.abc import Awaitable, Callable
from dataclasses import dataclass, field
from typing import Any

import httpx
import psutil

Send = Callable[[int], Awaitable[httpx.Response]]
Check = Callable[[httpx.Response], str | None]


@dataclass
class Req:
    method: str
    url: str
    content: bytes | None = None
    headers: dict[str, str] | None = None


@dataclass
class Case:
    """What to measure: where to send requests, how to build the i-th one and check its answer."""

    name: str
    target: str  # twinlink | nginx
    base_url: str
    headers: dict[str, str]
    make: Callable[[int], Req]
    check: Check
    max_requests: int
    on_warmup: Callable[[httpx.Response], None] | None = None


@dataclass
class CaseResult:
    name: str
    target: str  # twinlink | nginx
    concurrency: int
    requests: int = 0
    errors: int = 0
    seconds: float = 0.0
    rps: float = 0.0
    p50_ms: float = 0.0
    p90_ms: float = 0.0
    p99_ms: float = 0.0
    max_ms: float = 0.0
    mean_ms: float = 0.0
    server_cpu_pct: float | None = None
    client_cpu_pct: float = 0.0
    other_cpu_pct: float = 0.0  # everything else on the machine: noise from other work
    first_error: str | None = None
    note: str = ""
    extra: dict[str, Any] = field(default_factory=dict)


def percentile(sorted_values: list[float], q: float) -> float:
    """Nearest-rank percentile of an already sorted list."""
    if not sorted_values:
        return math.nan
    rank = max(1, math.ceil(q * len(sorted_values)))
    return sorted_values[min(rank, len(sorted_values)) - 1]


def expect(status: int, outcome: str | None = None) -> Check:
    def check(resp: httpx.Response) -> str | None:
        if resp.status_code != status:
            return f"HTTP {resp.status_code}: {resp.text[:300]}"
        if outcome is not None:
            got = [r["outcome"] for r in resp.json()["results"]]
            if got != [outcome]:
                return f"outcome {got}, expected [{outcome!r}]"
        return None

    return check


async def run_case(
    case: Case,
    concurrency: int,
    max_seconds: float,
    warmup: int,
    server_pid: int | None,
) -> CaseResult:
    """Send up to `case.max_requests` (stopping after `max_seconds`) with `concurrency` workers,
    each waiting for its answer before sending the next (closed loop)."""
    result = CaseResult(case.name, case.target, concurrency)
    limits = httpx.Limits(max_connections=concurrency, max_keepalive_connections=concurrency)
    async with httpx.AsyncClient(
        base_url=case.base_url, headers=case.headers, limits=limits, timeout=60
    ) as client:

        async def send(i: int) -> httpx.Response:
            r = case.make(i)
            return await client.request(r.method, r.url, content=r.content, headers=r.headers)

        # Warm-up: open the connections and let caches fill; not counted.
        await _warm_up(send, concurrency, warmup, case.max_requests, case.on_warmup)

        latencies: list[float] = []
        cpu = _CpuMeter(server_pid)
        start = time.perf_counter()
        await _closed_loop(
            send, case.check, concurrency, case.max_requests, start + max_seconds, latencies, result
        )
        elapsed = time.perf_counter() - start
        cpu.record(result, elapsed)

    _summarise(result, latencies, elapsed)
    return result


async def _warm_up(
    send: Send,
    concurrency: int,
    warmup: int,
    first_index: int,
    on_warmup: Callable[[httpx.Response], None] | None,
) -> None:
    """`warmup` requests from `concurrency` workers, with indices from `first_index` on (past
    the measured ones)."""
    counter = itertools.count()

    async def warm() -> None:
        while (i := next(counter)) < warmup:
            resp = await send(first_index + i)
            if on_warmup is not None and resp.status_code < 300:
                on_warmup(resp)

    await asyncio.gather(*(warm() for _ in range(concurrency)))


async def _closed_loop(
    send: Send,
    check: Check,
    concurrency: int,
    max_requests: int,
    deadline: float,
    latencies: list[float],
    result: CaseResult,
) -> None:
    """The measured requests: appends each latency, counts the failures in `result`."""
    counter = itertools.count()

    async def worker() -> None:
        while (i := next(counter)) < max_requests and time.perf_counter() < deadline:
            t0 = time.perf_counter()
            try:
                resp = await send(i)
                problem = check(resp)
            except httpx.HTTPError as err:
                problem = f"{type(err).__name__}: {err}"
            latencies.append(time.perf_counter() - t0)
            if problem is not None:
                result.errors += 1
                result.first_error = result.first_error or problem

    await asyncio.gather(*(worker() for _ in range(concurrency)))


def _summarise(result: CaseResult, latencies: list[float], elapsed: float) -> None:
    latencies.sort()
    result.requests = len(latencies)
    result.seconds = elapsed
    result.rps = len(latencies) / elapsed if elapsed else 0.0
    result.p50_ms = 1000 * percentile(latencies, 0.50)
    result.p90_ms = 1000 * percentile(latencies, 0.90)
    result.p99_ms = 1000 * percentile(latencies, 0.99)
    result.max_ms = 1000 * latencies[-1] if latencies else math.nan
    result.mean_ms = 1000 * statistics.fmean(latencies) if latencies else math.nan


# --- CPU accounting ----------------------------------------------------------------------------


class _CpuMeter:
    """CPU seconds spent from its creation on by the server (with its children), by this
    process (the load generator) and by the rest of the machine."""

    def __init__(self, server_pid: int | None) -> None:
        self.server = psutil.Process(server_pid) if server_pid else None
        self.me = psutil.Process()
        self.srv0 = _tree_cpu(self.server) if self.server else 0.0
        self.cli0 = _own_cpu(self.me)
        self.sys0 = _busy_cpu()

    def record(self, result: CaseResult, elapsed: float) -> None:
        """Fill in the CPU percentages of `result` (100 % = one core) over `elapsed` seconds."""
        cli = _own_cpu(self.me) - self.cli0
        srv = _tree_cpu(self.server) - self.srv0 if self.server else 0.0
        busy = _busy_cpu() - self.sys0
        if self.server is not None:
            result.server_cpu_pct = 100 * srv / elapsed
        result.client_cpu_pct = 100 * cli / elapsed
        result.other_cpu_pct = max(0.0, 100 * (busy - cli - srv) / elapsed)


def _tree_cpu(proc: psutil.Process) -> float:
    """User + system CPU seconds of a process and its children (nginx: master and workers)."""
    total = 0.0
    for p in [proc, *proc.children(recursive=True)]:
        with contextlib.suppress(psutil.NoSuchProcess):
            t = p.cpu_times()
            total += t.user + t.system
    return total


def _own_cpu(proc: psutil.Process) -> float:
    """CPU seconds of this process alone (the server and nginx are its children)."""
    t = proc.cpu_times()
    return float(t.user + t.system)


def _busy_cpu() -> float:
    """CPU seconds the whole machine has spent not idle."""
    t = psutil.cpu_times()
    return sum(t) - t.idle - getattr(t, "iowait", 0.0)
