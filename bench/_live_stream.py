"""Device-to-subscriber latency on the live WebSocket, and command round trips.

Latency: a paced SDK device in one process, a `GET /api/v1/live` subscriber in another; per
sample, the subscriber's clock at arrival minus the sample's `time` (both clocks are this
machine's). Commands: an SDK device answering `ping` at once in a process of its own, and
`POST /api/v1/twins/{slug}/commands` with `wait: true` from this process (_live_http)."""

from __future__ import annotations

import asyncio
from typing import Any

import orjson
from websockets.asyncio.client import connect
from websockets.exceptions import InvalidStatus

from _live_fleet import Bench
from _live_http import Make, RawHttp, closed_loop
from _live_procs import ClientGroup, ClientProc, CpuWindow
from _live_report import GOALS, Row, at_least, at_most, failed, per_s, unavailable

SETTLE_S = 0.5  # after the device's last ack, for its samples to reach the subscriber


async def live_missing(bench: Bench) -> str | None:
    """Why the live WebSocket cannot be used, or None when it answers with a welcome."""
    headers = {"Authorization": f"Bearer {bench.server.admin_token}"}
    try:
        async with connect(f"{bench.ws_url}/api/v1/live", additional_headers=headers) as ws:
            first = orjson.loads(await asyncio.wait_for(ws.recv(), 10))
    except InvalidStatus as err:
        return f"GET /api/v1/live refused the handshake (HTTP {err.response.status_code})"
    if first.get("type") != "welcome":
        return f"GET /api/v1/live sent {first!r} instead of a welcome"
    return None


async def latency(bench: Bench) -> list[Row]:
    opts = bench.opts
    why = await live_missing(bench)
    if why is not None:
        return [unavailable(f"live latency at {per_s(r)}", why) for r in opts.rates]
    rows = []
    for rate in opts.rates:
        case = f"live latency at {per_s(rate)}"
        print(f"  {case} for {opts.latency_seconds:g} s ...", flush=True)
        try:
            rows.append(_latency_row(case, rate, await _latency_run(bench, rate)))
        except Exception as err:
            rows.append(failed(case, err))
    return rows


async def _latency_run(bench: Bench, rate: int) -> dict[str, Any]:
    opts = bench.opts
    skip_s = min(1.0, opts.latency_seconds / 4)  # connection warm-up, not counted
    subscriber = ClientProc(
        "subscriber",
        {
            "mode": "subscribe",
            "live_url": f"{bench.ws_url}/api/v1/live",
            "token": bench.server.admin_token,
            "twin": bench.fleet.slugs[-1],
            "skip_s": skip_s,
        },
    )
    device = ClientProc(
        "paced device",
        {
            "mode": "paced",
            "url": bench.server.url,
            "token": bench.fleet.tokens[-1],
            "rate": rate,
            "seconds": opts.latency_seconds,
            "flush_interval": opts.latency_flush_s,
            "batch_size": 1000,
            "signals": opts.signals,
        },
    )
    async with ClientGroup([subscriber, device]) as group:
        await group.all("ready", 60)
        cpu = CpuWindow(bench.server.pid, group.pids)
        device.send({"op": "go"})
        sent = await device.event("result", opts.latency_seconds + 120)
        cpu.sample()  # the device process ends now
        await asyncio.sleep(SETTLE_S)
        subscriber.send({"op": "stop"})
        got = await subscriber.event("result", 30)
        usage = cpu.stop()
    if not got["samples"]:
        raise RuntimeError(f"the subscriber got no samples (device sent {sent['sent']})")
    return {"rate": rate, "sent": sent["sent"], "skip_s": skip_s, **got, "cpu": usage}


def _latency_row(case: str, rate: int, run: dict[str, Any]) -> Row:
    total, server, inbound = run["total_ms"], run["server_ms"], run["device_to_server_ms"]
    row = Row(
        case,
        measured=f"p50 {total['p50']:.2f} / p99 {total['p99']:.2f} ms",
        value=total["p99"],
        cpu=run["cpu"],
        details=run,
        note=f"server part (sent - received) p50 {server['p50']:.2f} / p99 {server['p99']:.2f}"
        f" ms; device to server p50 {inbound['p50']:.2f} / p99 {inbound['p99']:.2f} ms; "
        f"{run['samples']} samples in {run['messages']} messages"
        + (f"; {run['dropped_samples']} DROPPED" if run["dropped_samples"] else ""),
        anchor="thesis: under 20 ms typically, 100-250 ms at 500 msg/s",
    )
    if rate == 1000:
        row.goal, row.met = at_most(total["p99"], GOALS["latency_p99_ms"], "ms p99")
    return row


# --- commands -------------------------------------------------------------------------------


def route_missing(status: int, body: bytes) -> bool:
    """A 404/405 from the router itself (no such route), not from a handler."""
    if status not in (404, 405):
        return False
    try:
        return bool(orjson.loads(body).get("detail") in ("Not Found", "Method Not Allowed"))
    except (orjson.JSONDecodeError, AttributeError):
        return True


def _command_request(bench: Bench) -> Make:
    path = f"/api/v1/twins/{bench.fleet.slugs[-2]}/commands"

    def make(i: int) -> tuple[str, str, bytes]:
        return "POST", path, orjson.dumps({"name": "ping", "args": {"n": i}, "wait": True})

    return make


def _command_check(status: int, body: bytes) -> str | None:
    if status != 200:
        return f"HTTP {status}: {body[:300]!r}"
    state = orjson.loads(body).get("state")
    return None if state == "succeeded" else f"state {state!r}: {body[:300]!r}"


def _headers(bench: Bench) -> dict[str, str]:
    return {
        "Authorization": f"Bearer {bench.server.admin_token}",
        "Content-Type": "application/json",
    }


async def commands(bench: Bench) -> list[Row]:
    opts = bench.opts
    seq_case = "command round trip, sequential"
    conc_case = f"commands, {opts.command_concurrency} concurrent"
    device = ClientProc(
        "command device",
        {"mode": "command_device", "url": bench.server.url, "token": bench.fleet.tokens[-2]},
    )
    async with ClientGroup([device]) as group:
        await group.all("ready", 60)
        probe = RawHttp(bench.server.url, _headers(bench))
        status, body = await probe.request(*_command_request(bench)(-1))
        await probe.close()
        if route_missing(status, body):
            why = f"POST /api/v1/twins/{{slug}}/commands: HTTP {status}, no route"
            return [unavailable(seq_case, why), unavailable(conc_case, why)]
        rows = []
        for name, conc, limit in (
            (seq_case, 1, opts.command_requests),
            (conc_case, opts.command_concurrency, 10**7),
        ):
            print(f"  {name} ...", flush=True)
            try:
                rows.append(await _command_run(bench, group, name, conc, limit))
            except Exception as err:
                rows.append(failed(name, err))
        device.send({"op": "stop"})
        answered = (await device.event("result", 30))["answered"]
    rows[-1].details["device_answered"] = answered
    return rows


async def _command_run(
    bench: Bench, group: ClientGroup, name: str, concurrency: int, limit: int
) -> Row:
    opts = bench.opts
    cpu = CpuWindow(bench.server.pid, group.pids, here=True)
    result = await closed_loop(
        bench.server.url,
        _headers(bench),
        _command_request(bench),
        _command_check,
        concurrency,
        limit,
        opts.command_seconds,
        warmup=50,
    )
    usage = cpu.stop()
    if result.errors:
        raise RuntimeError(f"{result.errors} commands failed, e.g. {result.first_error}")
    row = Row(name, cpu=usage, details=result.summary())
    if concurrency == 1:
        row.measured = f"p50 {result.p50_ms:.2f} / p99 {result.p99_ms:.2f} ms"
        row.value = result.p99_ms
        row.goal, row.met = at_most(result.p99_ms, GOALS["command_p99_ms"], "ms p99")
        row.note = f"{result.requests} commands, {result.rps:.0f}/s one at a time"
    else:
        row.measured = f"{per_s(result.rps)} (p99 {result.p99_ms:.1f} ms)"
        row.value = result.rps
        row.goal, row.met = at_least(result.rps, GOALS["commands_per_s"], "/s")
        row.note = (
            f"{result.requests} commands in {result.seconds:.1f} s, p50 {result.p50_ms:.1f} ms"
        )
    return row
