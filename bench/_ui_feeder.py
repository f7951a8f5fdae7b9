"""A device for bench/ui_chart.py: streams paced batches through the device WebSocket (a batch
of `batch` samples every `batch / rate` seconds, timed on a fixed schedule so it does not
drift), each sample stamped with its own time, until told to stop."""

from __future__ import annotations

import asyncio
import contextlib
import math
import time
from dataclasses import dataclass, field
from typing import Any

import orjson
from websockets.asyncio.client import ClientConnection, connect


@dataclass
class FeedResult:
    sent: int = 0
    accepted: int = 0
    batches: int = 0
    late_batches: int = 0  # sent after their slot had passed (this process could not keep up)
    errors: list[str] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def rate(self) -> float:
        return self.sent / self.seconds if self.seconds else 0.0


def batch_message(seq: int, end_ns: int, count: int, step_ns: int, first_index: int) -> bytes:
    """`count` samples `step_ns` apart ending at `end_ns`: an angle that rings and a force with
    a one-sample spike every 10 000 samples (so a chart that loses spikes would show it)."""
    samples = []
    for i in range(count):
        n = first_index + i
        t = end_ns - (count - 1 - i) * step_ns
        angle = 0.3 * math.exp(-(n % 20_000) / 6000) * abs(math.sin(n * 0.006))
        force = 5.0 if n % 10_000 == 0 else 1.0 + 0.2 * math.sin(n * 0.0005)
        samples.append({"time": t, "values": {"angle": round(angle, 6), "force": round(force, 4)}})
    return orjson.dumps({"type": "samples", "seq": seq, "stream": "telemetry", "samples": samples})


async def _read_acks(ws: ClientConnection, result: FeedResult, stored: asyncio.Event) -> None:
    async for raw in ws:
        message: dict[str, Any] = orjson.loads(raw)
        if message.get("type") == "ack":
            result.accepted += int(message.get("accepted", 0))
            stored.set()
        elif message.get("type") == "error":
            result.errors.append(str(message.get("message"))[:200])


async def feed(
    ws_url: str, token: str, rate: int, batch: int, stop: asyncio.Event, ready: asyncio.Event
) -> FeedResult:
    """Stream until `stop` is set; `ready` is set once the first batch is stored (so the
    stream exists when a page asks for it)."""
    result = FeedResult()
    period = batch / rate
    step_ns = round(1e9 / rate)
    headers = {"Authorization": f"Bearer {token}"}
    async with connect(f"{ws_url}/api/v1/device/ws", additional_headers=headers) as ws:
        welcome = orjson.loads(await ws.recv())
        if welcome.get("type") != "welcome":
            raise RuntimeError(f"the device was not welcomed: {welcome}")
        reader = asyncio.create_task(_read_acks(ws, result, ready))
        loop = asyncio.get_running_loop()
        seq0 = time.time_ns() // 1000
        start = slot = loop.time()
        while not stop.is_set():
            message = batch_message(
                seq0 + result.batches, time.time_ns(), batch, step_ns, result.sent
            )
            await ws.send(message.decode())
            result.sent += batch
            result.batches += 1
            slot += period
            delay = slot - loop.time()
            if delay < 0:
                result.late_batches += 1
            with contextlib.suppress(TimeoutError):
                await asyncio.wait_for(stop.wait(), max(0.0, delay))
        result.seconds = loop.time() - start
        await asyncio.sleep(0.5)  # the last acks
        reader.cancel()
        with contextlib.suppress(asyncio.CancelledError, Exception):
            await reader
    return result
