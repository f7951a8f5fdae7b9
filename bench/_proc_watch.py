"""Live subscribers on a twin's streams, in the benchmark process, and the latency a processor
adds as a client sees it.

One WebSocket on `GET /api/v1/live` per stream (each connection has its own outgoing queue on
the server, so eight busy output streams cannot crowd each other out). Each message's arrival
is taken on this process's clock; a sample's added latency is the arrival of the output
sample with time t minus the arrival of the telemetry sample with time t. The heap is frozen
(gc.freeze) when subscribing, so this process's own collections stay short.
"""

from __future__ import annotations

import asyncio
import contextlib
import gc
import math
import time
from dataclasses import dataclass, field
from typing import Any

import orjson
from websockets.asyncio.client import ClientConnection, connect

from _live_client import stats_ms, until
from _proc_setup import ProcBench

POLL_S = 0.005


@dataclass
class Feed:
    """What arrived on one stream: counts, and per sample time its arrival (when kept)."""

    stream: str
    keep: bool
    samples: int = 0
    messages: int = 0
    dropped: int = 0  # samples the server dropped for this slow subscriber
    last_ns: int = 0  # arrival of the latest samples message
    arrivals: dict[int, int] = field(default_factory=dict)

    def take(self, now: int, msg: dict[str, Any]) -> None:
        kind = msg.get("type")
        if kind == "dropped":
            self.dropped += int(msg.get("samples", 0))
        elif kind == "samples":
            self.samples += len(msg["samples"])
            self.messages += 1
            self.last_ns = now
            if self.keep:
                for s in msg["samples"]:
                    self.arrivals.setdefault(s["time"], now)


class Watcher:
    """Subscribers on `streams` of `twin` (the telemetry one with the `force` signal only)."""

    def __init__(self, bench: ProcBench, twin: str, streams: list[str], keep: bool) -> None:
        self.bench = bench
        self.twin = twin
        self.feeds = {s: Feed(s, keep) for s in streams}
        self._sockets: list[ClientConnection] = []
        self._tasks: list[asyncio.Task[None]] = []

    async def __aenter__(self) -> Watcher:
        # What is alive now stays: a full collection of this process's heap (tens of ms)
        # would delay an arrival and count as latency the server added.
        gc.freeze()
        try:
            for feed in self.feeds.values():
                ws = await self._subscribe(feed.stream)
                self._tasks.append(asyncio.create_task(self._receive(ws, feed)))
            return self
        except BaseException:
            await self.close()
            raise

    async def __aexit__(self, *exc: object) -> None:
        await self.close()

    async def _subscribe(self, stream: str) -> ClientConnection:
        headers = {"Authorization": f"Bearer {self.bench.server.admin_token}"}
        ws = await connect(
            f"{self.bench.ws_url}/api/v1/live", additional_headers=headers, max_size=2**26
        )
        self._sockets.append(ws)
        await until(ws, "welcome")
        request: dict[str, Any] = {"op": "subscribe", "id": stream, "twin": self.twin}
        request["stream"] = stream
        if stream == "telemetry":
            request["signals"] = ["force"]
        await ws.send(orjson.dumps(request).decode())
        await until(ws, "subscribed")
        return ws

    @staticmethod
    async def _receive(ws: ClientConnection, feed: Feed) -> None:
        with contextlib.suppress(Exception):  # closed at the end
            async for raw in ws:
                feed.take(time.time_ns(), orjson.loads(raw))

    async def close(self) -> None:
        for task in self._tasks:
            task.cancel()
        await asyncio.gather(*self._tasks, return_exceptions=True)
        await asyncio.gather(*(ws.close() for ws in self._sockets), return_exceptions=True)

    async def wait_for(self, want: int, streams: list[str], stall_s: float = 5.0) -> bool:
        """Until each of `streams` has `want` samples (True), or none grew for `stall_s`."""
        feeds = [self.feeds[s] for s in streams]
        last, still = -1, time.perf_counter()
        while True:
            total = sum(min(f.samples, want) for f in feeds)
            if total >= want * len(feeds):
                return True
            if total != last:
                last, still = total, time.perf_counter()
            elif time.perf_counter() - still > stall_s:
                return False
            await asyncio.sleep(POLL_S)


def added(telemetry: Feed, out: Feed, skip_s: float) -> dict[str, Any]:
    """The client-side added latency of `out` over `telemetry`, per sample, after the first
    `skip_s` seconds of sample time (warm-up); percentiles, and the median of the first and
    last 10 % of the samples to see whether the delay grows."""
    times = sorted(telemetry.arrivals)
    if not times:
        return {"samples": 0, "missing": 0, "ms": stats_ms([]), "first_ms": None, "last_ms": None}
    start = times[0] + int(skip_s * 1e9)
    kept = [t for t in times if t >= start]
    deltas = [out.arrivals[t] - telemetry.arrivals[t] for t in kept if t in out.arrivals]
    tenth = max(1, len(deltas) // 10)
    return {
        "samples": len(deltas),
        "missing": len(times) - sum(1 for t in times if t in out.arrivals),
        "ms": stats_ms(deltas),
        "first_ms": stats_ms(deltas[:tenth])["p50"],
        "last_ms": stats_ms(deltas[-tenth:])["p50"],
    }


def diverged(first_ms: float | None, last_ms: float | None) -> bool:
    """The delay grew over the run: the last tenth's median is more than twice the first's
    and more than 5 ms above it (a queue building up, not jitter)."""
    if first_ms is None or last_ms is None or math.isnan(first_ms):
        return False
    return last_ms > 2 * first_ms and last_ms > first_ms + 5.0
