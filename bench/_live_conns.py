"""Server memory with many devices connected: the settled RSS of the server before and while
N device WebSockets are open (each with its own device token), and the cost of one.

The connections are plain `websockets` clients in a few processes of their own: they open
`GET /api/v1/device/ws`, read the welcome and wait. They offer permessage-deflate, as the SDK
does by default, so the server keeps a compression context for each."""

from __future__ import annotations

import asyncio

from _live_fleet import Bench
from _live_procs import ClientGroup, ClientProc
from _live_report import Row, failed

HOLD_PROCS = 2


async def connections(bench: Bench) -> list[Row]:
    count = bench.opts.connections
    case = f"RSS with {count} devices connected"
    print(f"  {case} ...", flush=True)
    try:
        return [await _measure(bench, count, case)]
    except Exception as err:
        return [failed(case, err)]


async def _measure(bench: Bench, count: int, case: str) -> Row:
    server = bench.server
    tokens = bench.fleet.tokens[:count]
    before = await asyncio.to_thread(server.settled_rss)
    device_url = f"{bench.ws_url}/api/v1/device/ws"
    chunks = [tokens[k::HOLD_PROCS] for k in range(HOLD_PROCS)]
    procs = [
        ClientProc(f"hold {i}", {"mode": "hold", "device_url": device_url, "tokens": chunk})
        for i, chunk in enumerate(chunks)
        if chunk
    ]
    loop = asyncio.get_running_loop()
    async with ClientGroup(procs) as group:
        t0 = loop.time()
        ready = await group.all("ready", 300)
        opened_s = loop.time() - t0
        connected = sum(r["connected"] for r in ready)
        if connected != len(tokens):
            failures = [f for r in ready for f in r["failures"]]
            raise RuntimeError(f"{len(tokens) - connected} connections failed: {failures[:3]}")
        during = await asyncio.to_thread(server.settled_rss)
        group.send("stop")
        alive = sum(r["alive"] for r in await group.all("result", 60))
    after = await asyncio.to_thread(server.settled_rss)
    per_conn_kb = (during - before) / count / 1024
    return Row(
        case,
        measured=f"{per_conn_kb:.0f} KB per connection",
        value=per_conn_kb,
        note=f"server RSS {before / 2**20:.1f} MB before, {during / 2**20:.1f} MB with "
        f"{connected} open ({alive} still open at the end), {after / 2**20:.1f} MB after "
        f"closing; opened in {opened_s:.1f} s",
        details={
            "connections": connected,
            "alive_at_end": alive,
            "rss_before_mb": round(before / 2**20, 1),
            "rss_connected_mb": round(during / 2**20, 1),
            "rss_after_close_mb": round(after / 2**20, 1),
            "per_connection_kb": round(per_conn_kb, 1),
            "open_seconds": round(opened_s, 2),
        },
    )
