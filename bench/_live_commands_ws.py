"""Command round trips over the live WebSocket (`{"op": "command"}` on `GET /api/v1/live`),
the path a script or the web UI uses: one connection, commands pipelined on it.

The same SDK device as the HTTP case answers `ping` at once in a process of its own; this
process sends the commands and times each from send to its `command` answer."""

from __future__ import annotations

import asyncio
import time
from typing import Any

import orjson
from websockets.asyncio.client import ClientConnection, connect

from _live_fleet import Bench
from _live_procs import ClientGroup, ClientProc, CpuWindow
from _live_report import GOALS, Row, at_least, at_most, failed, per_s, unavailable
from _live_stream import live_missing

WINDOW = 64  # commands in flight in the concurrent case


async def commands_ws(bench: Bench) -> list[Row]:
    seq_case = "command round trip, live WS, sequential"
    conc_case = f"commands, live WS, {WINDOW} in flight"
    why = await live_missing(bench)
    if why is not None:
        return [unavailable(seq_case, why), unavailable(conc_case, why)]
    device = ClientProc(
        "command device",
        {"mode": "command_device", "url": bench.server.url, "token": bench.fleet.tokens[-2]},
    )
    rows: list[Row] = []
    async with ClientGroup([device]) as group:
        await group.all("ready", 60)
        headers = {"Authorization": f"Bearer {bench.server.admin_token}"}
        async with connect(f"{bench.ws_url}/api/v1/live", additional_headers=headers) as ws:
            orjson.loads(await ws.recv())  # welcome
            runner = _Runner(ws, bench.fleet.slugs[-2])
            await runner.run(1, 50, 10.0)  # warm up
            for name, window, limit in (
                (seq_case, 1, bench.opts.command_requests),
                (conc_case, WINDOW, 10**7),
            ):
                print(f"  {name} ...", flush=True)
                try:
                    rows.append(await _measure(bench, group, runner, name, window, limit))
                except Exception as err:
                    rows.append(failed(name, err))
        device.send({"op": "stop"})
        await device.event("result", 30)
    return rows


async def _measure(
    bench: Bench, group: ClientGroup, runner: _Runner, name: str, window: int, limit: int
) -> Row:
    cpu = CpuWindow(bench.server.pid, group.pids, here=True)
    took = await runner.run(window, limit, bench.opts.command_seconds)
    usage = cpu.stop()
    done = sorted(runner.latencies_ms)
    p50, p99 = _rank(done, 0.50), _rank(done, 0.99)
    rate = len(done) / took
    row = Row(name, cpu=usage, details={"commands": len(done), "seconds": took, "p50_ms": p50,
                                        "p99_ms": p99, "per_s": rate})  # fmt: skip
    if window == 1:
        row.measured, row.value = f"p50 {p50:.2f} / p99 {p99:.2f} ms", p99
        row.goal, row.met = at_most(p99, GOALS["command_p99_ms"], "ms p99")
        row.note = f"{len(done)} commands, {rate:.0f}/s one at a time"
    else:
        row.measured, row.value = f"{per_s(rate)} (p99 {p99:.1f} ms)", rate
        row.goal, row.met = at_least(rate, GOALS["commands_per_s"], "/s")
        row.note = f"{len(done)} commands in {took:.1f} s, p50 {p50:.1f} ms"
    return row


def _rank(values: list[float], q: float) -> float:
    return values[min(len(values) - 1, int(q * len(values)))] if values else float("nan")


class _Runner:
    """Keeps `window` commands in flight for at most `limit` commands or `seconds`."""

    def __init__(self, ws: ClientConnection, slug: str) -> None:
        self.ws = ws
        self.slug = slug
        self.next_id = 0
        self.latencies_ms: list[float] = []

    async def run(self, window: int, limit: int, seconds: float) -> float:
        self.latencies_ms = []
        sent: dict[str, float] = {}
        start = time.perf_counter()
        deadline = start + seconds
        while len(sent) < window and len(self.latencies_ms) + len(sent) < limit:
            await self._send(sent)
        while sent:
            reply = orjson.loads(await asyncio.wait_for(self.ws.recv(), 30))
            self._answered(reply, sent)
            more = len(self.latencies_ms) + len(sent) < limit
            if more and time.perf_counter() < deadline and len(sent) < window:
                await self._send(sent)
        return time.perf_counter() - start

    async def _send(self, sent: dict[str, float]) -> None:
        self.next_id += 1
        ref = str(self.next_id)
        message = {"op": "command", "id": ref, "twin": self.slug, "name": "ping",
                   "args": {"n": self.next_id}}  # fmt: skip
        sent[ref] = time.perf_counter()
        await self.ws.send(orjson.dumps(message).decode())

    def _answered(self, reply: dict[str, Any], sent: dict[str, float]) -> None:
        if reply.get("type") not in ("command", "error"):
            return
        began = sent.pop(str(reply.get("id")), None)
        if began is None:
            return
        state = (reply.get("command") or {}).get("state")
        if reply["type"] == "error" or state != "succeeded":
            raise RuntimeError(f"a command did not succeed: {reply!r}"[:400])
        self.latencies_ms.append((time.perf_counter() - began) * 1000)
