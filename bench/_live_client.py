"""A client process of the live benchmark: devices, a subscriber or idle connections.

Runs apart from the benchmark so its CPU is not the server's nor the orchestrator's. It reads
its configuration as the first line of stdin (JSON with a `mode`), then commands, one JSON
object a line: `{"op": "go"}` and `{"op": "stop"}` (end of input means stop). It writes events,
one JSON object a line, to stdout: `{"event": "ready", ...}` once connected, `{"event":
"result", ...}` at the end, or `{"event": "error", "message": ...}`.

Modes:
- `ingest`: AsyncDevices (one per token) each add `samples` samples as fast as they can from
  `go` on and flush; the result holds the wall-clock start and end and the accepted samples.
- `paced`: one AsyncDevice adding samples at `rate` per second for `seconds` after `go`.
- `subscribe`: a live WebSocket subscriber; per sample the delay from the sample's `time` to
  its arrival here, and the server's own part (`sent - received`).
- `command_device`: an AsyncDevice answering command `ping` at once, until `stop`.
- `hold`: plain `websockets` device connections that read the welcome and wait for `stop`.
"""

from __future__ import annotations

import asyncio
import contextlib
import math
import resource
import sys
import time
from collections.abc import Awaitable, Callable, Coroutine
from typing import Any

import orjson
from websockets.asyncio.client import ClientConnection, connect

from twinlink_edge import AsyncDevice, BufferFull

Config = dict[str, Any]
YIELD_EVERY = 256  # samples a device adds before it lets the loop send


def emit(event: str, **fields: Any) -> None:
    sys.stdout.write(orjson.dumps({"event": event, **fields}).decode() + "\n")
    sys.stdout.flush()


class Control:
    """The commands from the orchestrator on stdin."""

    def __init__(self) -> None:
        self.reader = asyncio.StreamReader()

    async def open(self) -> Config:
        loop = asyncio.get_running_loop()
        protocol = asyncio.StreamReaderProtocol(self.reader)
        await loop.connect_read_pipe(lambda: protocol, sys.stdin)
        return await self.next()

    async def next(self) -> Config:
        line = await self.reader.readline()
        return orjson.loads(line) if line.strip() else {"op": "stop"}

    async def wait(self, op: str) -> None:
        while (got := (await self.next())["op"]) != op:
            if got == "stop":
                raise SystemExit(0)


def value_pool(signals: int, size: int = 997) -> list[dict[str, float]]:
    """Sample values shaped like the Tingen rig's: `signals` floats that move."""
    names = ["angle", "force", "accel_x", "rate_y", "temp", "strain", "speed", "load"]
    names += [f"s{i}" for i in range(len(names), signals)]
    return [
        {names[k]: round(math.sin(0.01 * i + k) * (k + 1), 6) for k in range(signals)}
        for i in range(size)
    ]


def new_device(cfg: Config, token: str, samples: int = 0) -> AsyncDevice:
    return AsyncDevice(
        cfg["url"],
        token,
        batch_size=cfg.get("batch_size", 1000),
        flush_interval=cfg.get("flush_interval", 0.05),
        window=cfg.get("window", 16),
        max_buffered_samples=max(1_000_000, samples + cfg.get("batch_size", 1000)),
    )


async def connect_all(devices: list[AsyncDevice], timeout: float = 60) -> None:
    for d in devices:
        await d.start()
    ok = await asyncio.gather(*(d.wait_connected(timeout) for d in devices))
    if not all(ok):
        errors = {d.last_error for d, up in zip(devices, ok, strict=True) if not up}
        raise RuntimeError(f"{ok.count(False)} devices did not connect: {sorted(map(str, errors))}")


# --- ingest -------------------------------------------------------------------------------


async def add_samples(dev: AsyncDevice, count: int, pool: list[dict[str, float]]) -> list[float]:
    """Add `count` samples as fast as the device takes them, then wait for every ack; the
    wall-clock times of the first add and of the final ack."""
    start = time.time()
    for i in range(count):
        values = pool[i % len(pool)]
        try:
            dev.add(values)
        except BufferFull:
            await dev.send(values)
        if i % YIELD_EVERY == YIELD_EVERY - 1:
            await asyncio.sleep(0)
    await dev.flush(timeout=600)
    return [start, time.time()]


async def ingest(cfg: Config, ctl: Control) -> None:
    devices = [new_device(cfg, t, cfg["samples"]) for t in cfg["tokens"]]
    pool = value_pool(cfg["signals"])
    try:
        await connect_all(devices)
        emit("ready", devices=len(devices))
        await ctl.wait("go")
        spans = await asyncio.gather(*(add_samples(d, cfg["samples"], pool) for d in devices))
        emit(
            "result",
            start=min(s[0] for s in spans),
            end=max(s[1] for s in spans),
            sent=cfg["samples"] * len(devices),
            accepted=sum(d.accepted_samples for d in devices),
            rejected=sum(d.rejected for d in devices),
            connections=sum(d.connections for d in devices),
            errors=sorted({d.last_error for d in devices if d.last_error}),
        )
    finally:
        await asyncio.gather(*(d.close(timeout=5) for d in devices))


# --- latency ------------------------------------------------------------------------------


async def paced(cfg: Config, ctl: Control) -> None:
    """Add samples at `rate` a second (stamped when added) for `seconds`, waking at most every
    millisecond and adding what is due."""
    dev = new_device(cfg, cfg["token"])
    pool = value_pool(cfg["signals"])
    rate, seconds = float(cfg["rate"]), float(cfg["seconds"])
    tick = 0.001  # a loop timer's resolution: faster rates add several samples a wake-up
    try:
        await connect_all([dev])
        emit("ready")
        await ctl.wait("go")
        loop = asyncio.get_running_loop()
        start = loop.time()
        total = int(rate * seconds)
        sent = 0
        while sent < total:
            due = min(total, int((loop.time() - start) * rate) + 1)
            for _ in range(due - sent):
                dev.add(pool[sent % len(pool)])
                sent += 1
            # Sample `sent` is due at start + sent / rate: sleep until then, a tick at least.
            await asyncio.sleep(max(tick, start + sent / rate - loop.time()))
        await dev.flush(timeout=60)
        emit("result", sent=sent, accepted=dev.accepted_samples, seconds=loop.time() - start)
    finally:
        await dev.close(timeout=5)


class Latencies:
    """Per sample: arrival here minus the sample's time. Per message: sent minus received."""

    def __init__(self, skip_s: float) -> None:
        self.skip_ns = int(skip_s * 1e9)
        self.first: int | None = None
        self.total: list[int] = []
        self.server: list[int] = []
        self.to_server: list[int] = []
        self.dropped = 0
        self.messages = 0

    def add(self, now: int, msg: dict[str, Any]) -> None:
        if msg.get("type") == "dropped":
            self.dropped += int(msg.get("samples", 0))
            return
        if msg.get("type") != "samples":
            return
        times = [s["time"] for s in msg["samples"]]
        if self.first is None:
            self.first = times[0]
        kept = [t for t in times if t >= self.first + self.skip_ns]
        if not kept:
            return
        self.messages += 1
        self.total.extend(now - t for t in kept)
        self.to_server.extend(msg["received"] - t for t in kept)
        self.server.append(msg["sent"] - msg["received"])

    def summary(self) -> dict[str, Any]:
        return {
            "samples": len(self.total),
            "messages": self.messages,
            "dropped_samples": self.dropped,
            "total_ms": stats_ms(self.total),
            "device_to_server_ms": stats_ms(self.to_server),
            "server_ms": stats_ms(self.server),
        }


def stats_ms(values_ns: list[int]) -> dict[str, float | None]:
    if not values_ns:
        return {"p50": None, "p90": None, "p99": None, "max": None}
    ordered = sorted(values_ns)

    def rank(q: float) -> float:
        return round(ordered[min(len(ordered), max(1, math.ceil(q * len(ordered)))) - 1] / 1e6, 3)

    return {"p50": rank(0.5), "p90": rank(0.9), "p99": rank(0.99), "max": rank(1.0)}


async def subscribe(cfg: Config, ctl: Control) -> None:
    headers = {"Authorization": f"Bearer {cfg['token']}"}
    async with connect(cfg["live_url"], additional_headers=headers, max_size=2**24) as ws:
        await until(ws, "welcome")
        request = {"op": "subscribe", "id": "bench", "twin": cfg["twin"], "stream": "telemetry"}
        await ws.send(orjson.dumps(request).decode())
        await until(ws, "subscribed")
        emit("ready")
        lat = Latencies(cfg["skip_s"])
        receiver = asyncio.create_task(receive(ws, lat))
        await ctl.wait("stop")
        receiver.cancel()
        with contextlib.suppress(asyncio.CancelledError):
            await receiver
        emit("result", **lat.summary())


async def until(ws: ClientConnection, kind: str) -> dict[str, Any]:
    while True:
        msg = orjson.loads(await asyncio.wait_for(ws.recv(), 30))
        if msg.get("type") == kind:
            return msg  # type: ignore[no-any-return]
        if msg.get("type") == "error":
            raise RuntimeError(f"the server answered: {msg}")


async def receive(ws: ClientConnection, lat: Latencies) -> None:
    async for raw in ws:
        lat.add(time.time_ns(), orjson.loads(raw))


# --- commands and idle connections --------------------------------------------------------


async def command_device(cfg: Config, ctl: Control) -> None:
    dev = new_device(cfg, cfg["token"])
    answered = 0

    @dev.on_command("ping")
    async def ping(args: dict[str, Any]) -> dict[str, Any]:
        nonlocal answered
        answered += 1
        return {"pong": args.get("n")}

    try:
        await connect_all([dev])
        emit("ready")
        await ctl.wait("stop")
        emit("result", answered=answered)
    finally:
        await dev.close(timeout=5)


async def hold(cfg: Config, ctl: Control) -> None:
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    resource.setrlimit(resource.RLIMIT_NOFILE, (max(soft, min(hard, 65536)), hard))
    opening = asyncio.Semaphore(32)
    held: list[ClientConnection] = []

    async def one(token: str) -> None:
        async with opening:
            ws = await connect(
                cfg["device_url"],
                additional_headers={"Authorization": f"Bearer {token}"},
                open_timeout=60,
                compression=cfg.get("compression", "deflate"),
            )
            held.append(ws)
            await until(ws, "welcome")

    outcomes = await asyncio.gather(*(one(t) for t in cfg["tokens"]), return_exceptions=True)
    failures = [repr(o) for o in outcomes if isinstance(o, BaseException)]
    try:
        emit("ready", connected=len(outcomes) - len(failures), failures=failures[:3])
        await ctl.wait("stop")
        alive = sum(1 for ws in held if ws.close_code is None)
        emit("result", alive=alive)
    finally:
        await asyncio.gather(*(ws.close() for ws in held), return_exceptions=True)


MODES: dict[str, Callable[[Config, Control], Awaitable[None]]] = {
    "ingest": ingest,
    "paced": paced,
    "subscribe": subscribe,
    "command_device": command_device,
    "hold": hold,
}


async def main() -> None:
    # Here, not at the top: _live_steady imports this module.
    from _live_steady import steady_devices, watch_twins

    MODES.update(steady=steady_devices, watch=watch_twins)
    await drive(lambda cfg, ctl: MODES[cfg["mode"]](cfg, ctl))


async def drive(mode: Callable[[Config, Control], Awaitable[None]]) -> None:
    """A client process's life: its settings from the parent, then `mode`; a failure is
    reported to the parent as an `error` event (and exit status 1)."""
    ctl = Control()
    cfg = await ctl.open()
    try:
        await mode(cfg, ctl)
    except Exception as err:
        emit("error", message=f"{type(err).__name__}: {err}")
        raise SystemExit(1) from err


def run(main: Callable[[], Coroutine[Any, Any, None]]) -> None:
    """Run a client process's `main`, on uvloop when it is installed."""
    try:
        import uvloop
    except ImportError:
        asyncio.run(main())
    else:
        uvloop.run(main())


if __name__ == "__main__":
    run(main)
