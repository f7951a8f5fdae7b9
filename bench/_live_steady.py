"""A steady fleet: many devices that each send one sample a batch, slowly (2 000 devices at
2 samples/s), as a building full of sensors does. Per batch, the time from sending it to its
ack, as each device sees it (after a warm-up, reported apart); and what a live subscriber to
some of those twins receives, or is told was dropped.

The devices are plain `websockets` connections (offering permessage-deflate, as the SDK
does), in client processes of their own, each sending at its own phase so the load is even.
Both client modes are here; `_live_client.py` runs them."""

from __future__ import annotations

import asyncio
import contextlib
import gc
import random
import time
from typing import Any

import orjson
from websockets.asyncio.client import ClientConnection, connect

from _live_client import Control, emit, stats_ms, until, value_pool
from _live_fleet import Bench
from _live_procs import ClientGroup, ClientProc, CpuWindow, Profiler
from _live_report import GOALS, Row, at_most, failed

STEADY_PROCS = 2
WATCHED_TWINS = 100  # twins the live subscriber follows
DRAIN_S = 15.0  # after the last send, for the last acks
# The first seconds after 2 000 devices connected at once are not the steady state: every
# twin's first batch makes its series and reads its interface. Their acks are reported apart.
WARMUP_S = 5.0


# --- client side ---------------------------------------------------------------------------


async def _open(url: str, token: str, opening: asyncio.Semaphore) -> ClientConnection:
    async with opening:
        ws = await connect(
            url, additional_headers={"Authorization": f"Bearer {token}"}, open_timeout=120
        )
        await until(ws, "welcome")
        return ws


async def _one_device(
    ws: ClientConnection, rate: float, until_t: float, pool: list[dict[str, float]], out: Any
) -> None:
    """Send one-sample batches at `rate` from a random phase until `until_t` (loop time);
    record each batch's send-to-ack time in `out`."""
    sent: dict[int, int] = {}

    async def acks() -> None:
        async for raw in ws:
            now = time.perf_counter_ns()
            msg = orjson.loads(raw)
            if msg.get("type") == "ack" and msg.get("seq") in sent:
                took = now - sent.pop(msg["seq"])
                since = loop.time() - out["t0"]
                out["latency" if since >= WARMUP_S else "warmup"].append(took)
                second = int(since)
                out["worst"][second] = max(out["worst"].get(second, 0), took)
                out["accepted"] += msg["accepted"]
            elif msg.get("type") == "error":
                out["errors"].add(str(msg.get("message"))[:200])
            if not sent and loop.time() > until_t:
                return

    loop = asyncio.get_running_loop()
    reader = asyncio.create_task(acks())
    start = loop.time() + random.random() / rate
    seq = 0
    try:
        while True:
            due = start + seq / rate
            if due > until_t:
                break
            await asyncio.sleep(max(0.0, due - loop.time()))
            seq += 1
            batch = {
                "type": "samples",
                "seq": seq,
                "samples": [{"time": time.time_ns(), "values": pool[seq % len(pool)]}],
            }
            sent[seq] = time.perf_counter_ns()
            await ws.send(orjson.dumps(batch).decode())
            out["sent"] += 1
        with contextlib.suppress(TimeoutError):
            await asyncio.wait_for(asyncio.shield(reader), DRAIN_S)
        out["unacked"] += len(sent)
    finally:
        reader.cancel()
        with contextlib.suppress(asyncio.CancelledError, Exception):
            await reader


async def steady_devices(cfg: dict[str, Any], ctl: Control) -> None:
    """Client mode `steady`: open every token's device connection, then on `go` send at
    `rate` per device for `seconds`."""
    opening = asyncio.Semaphore(32)
    conns = await asyncio.gather(*(_open(cfg["device_url"], t, opening) for t in cfg["tokens"]))
    pool = value_pool(cfg["signals"])
    out: dict[str, Any] = {"latency": [], "sent": 0, "accepted": 0, "unacked": 0, "errors": set()}
    out["warmup"] = []  # acks of the first WARMUP_S
    out["worst"] = {}  # second of the run -> the slowest ack received in it
    try:
        emit("ready", devices=len(conns))
        await ctl.wait("go")
        # The client's own collector would pause its loop (a thousand connections are many
        # objects) and the pause would be counted as the server's: off while measuring.
        gc.collect()
        gc.freeze()
        gc.disable()
        out["t0"] = asyncio.get_running_loop().time()
        until_t = out["t0"] + float(cfg["seconds"])
        rate = float(cfg["rate"])
        await asyncio.gather(*(_one_device(ws, rate, until_t, pool, out) for ws in conns))
        emit(
            "result",
            latency_ms=[round(ns / 1e6, 3) for ns in out["latency"]],
            warmup_ms=[round(ns / 1e6, 3) for ns in out["warmup"]],
            sent=out["sent"],
            accepted=out["accepted"],
            unacked=out["unacked"],
            errors=sorted(out["errors"])[:5],
            worst_ms={str(k): round(v / 1e6, 1) for k, v in sorted(out["worst"].items())},
        )
    finally:
        gc.enable()
        await asyncio.gather(*(ws.close() for ws in conns), return_exceptions=True)


async def watch_twins(cfg: dict[str, Any], ctl: Control) -> None:
    """Client mode `watch`: one live WebSocket subscribed to the `twins`' telemetry; counts
    the samples received and those the server says it dropped."""
    headers = {"Authorization": f"Bearer {cfg['token']}"}
    async with connect(cfg["live_url"], additional_headers=headers, max_size=2**24) as ws:
        await until(ws, "welcome")
        for i, twin in enumerate(cfg["twins"]):
            request = {"op": "subscribe", "id": f"s{i}", "twin": twin, "stream": "telemetry"}
            await ws.send(orjson.dumps(request).decode())
            await until(ws, "subscribed")
        emit("ready")
        counts = {"received": 0, "dropped": 0}

        async def receive() -> None:
            async for raw in ws:
                msg = orjson.loads(raw)
                if msg.get("type") == "samples":
                    counts["received"] += len(msg["samples"])
                elif msg.get("type") == "dropped":
                    counts["dropped"] += int(msg.get("samples", 0))

        receiver = asyncio.create_task(receive())
        await ctl.wait("stop")
        receiver.cancel()
        with contextlib.suppress(asyncio.CancelledError):
            await receiver
        emit("result", **counts)


# --- orchestrator side -----------------------------------------------------------------------


async def steady(bench: Bench) -> list[Row]:
    opts = bench.opts
    count, rate = opts.steady_devices, opts.steady_rate
    case = f"steady fleet, {count} devices x {rate:g} samples/s, one sample a batch"
    print(f"  {case} for {opts.steady_seconds:g} s ...", flush=True)
    try:
        return [_row(case, await _run(bench, count, rate))]
    except Exception as err:
        return [failed(case, err)]


async def _run(bench: Bench, count: int, rate: float) -> dict[str, Any]:
    opts = bench.opts
    tokens = bench.fleet.tokens[:count]
    if len(tokens) < count:
        raise RuntimeError(f"only {len(tokens)} device tokens for {count} devices")
    device_url = f"{bench.ws_url}/api/v1/device/ws"
    procs = [
        ClientProc(
            f"steady {i}",
            {
                "mode": "steady",
                "device_url": device_url,
                "tokens": tokens[i::STEADY_PROCS],
                "rate": rate,
                "seconds": opts.steady_seconds,
                "signals": opts.signals,
            },
        )
        for i in range(STEADY_PROCS)
    ]
    watched = bench.fleet.slugs[: min(WATCHED_TWINS, count)]
    watcher = ClientProc(
        "watcher",
        {
            "mode": "watch",
            "live_url": f"{bench.ws_url}/api/v1/live",
            "token": bench.server.admin_token,
            "twins": watched,
        },
    )
    svg = bench.results_dir / f"live-profile-{bench.stamp}-steady.svg"
    async with ClientGroup([*procs, watcher]) as group:
        await group.all("ready", 600)
        async with Profiler(opts.profile, bench.server.pid, svg) as profiler:
            cpu = CpuWindow(bench.server.pid, group.pids)
            group.send("go")
            results = [await p.event("result", opts.steady_seconds + 120) for p in procs]
            usage = cpu.stop()
        watcher.send({"op": "stop"})
        seen = await watcher.event("result", 60)
    latencies = sorted(ms for r in results for ms in r["latency_ms"])
    warmup = sorted(ms for r in results for ms in r["warmup_ms"])
    sent = sum(r["sent"] for r in results)
    expected_live = len(watched) / count * sent
    return {
        "devices": count,
        "rate_per_device": rate,
        "seconds": opts.steady_seconds,
        "batches_sent": sent,
        "samples_accepted": sum(r["accepted"] for r in results),
        "unacked": sum(r["unacked"] for r in results),
        "errors": sorted({e for r in results for e in r["errors"]})[:5],
        "worst_ack_ms_by_second": _worst(results),
        "ack_ms": stats_ms([round(ms * 1e6) for ms in latencies]),
        "warmup_s": WARMUP_S,
        "warmup_ack_ms": stats_ms([round(ms * 1e6) for ms in warmup]),
        "live_watched_twins": len(watched),
        "live_received": seen["received"],
        "live_dropped": seen["dropped"],
        "live_expected": round(expected_live),
        "cpu": usage,
        "profile": str(svg) if profiler.enabled else None,
    }


def _worst(results: list[dict[str, Any]]) -> list[float]:
    """The slowest ack of each second of the run, over the client processes."""
    seconds: dict[int, float] = {}
    for r in results:
        for k, v in r["worst_ms"].items():
            seconds[int(k)] = max(seconds.get(int(k), 0.0), v)
    return [seconds.get(k, 0.0) for k in range(max(seconds, default=-1) + 1)]


def _row(case: str, run: dict[str, Any]) -> Row:
    ack = run["ack_ms"]
    p99 = ack["p99"] if ack["p99"] is not None else float("inf")
    goal, met = at_most(p99, GOALS["steady_ack_p99_ms"], "ms ack p99")
    expected = max(1, run["live_expected"])
    return Row(
        case,
        measured=f"ack p50 {ack['p50']} ms, p99 {ack['p99']} ms",
        value=p99,
        goal=goal,
        met=met and not run["unacked"] and not run["errors"],
        cpu=run["cpu"],
        anchor="the issue's run before: ack p99 10.8 s, 54-65 % of live samples dropped",
        note=f"after {run['warmup_s']:g} s of warm-up (acks then: p99 "
        f"{run['warmup_ack_ms']['p99']} ms); {run['batches_sent']} batches, {run['unacked']} "
        "unacked; live: "
        f"{run['live_received']} of ~{run['live_expected']} samples of {run['live_watched_twins']}"
        f" twins received ({100 * run['live_received'] / expected:.0f} %), "
        f"{run['live_dropped']} dropped",
        details=run,
    )
