"""A client process of the cluster benchmark: HTTP devices posting sample batches.

Each device is one keep-alive HTTP/1.1 connection (`_live_http.RawHttp`) that posts a batch
to `POST /api/v1/device/samples`, waits for its ack and posts the next (one batch in flight a
device, as a device without a WebSocket does), from `go` until `seconds` have passed. A batch
that got no ack (an error status, a broken connection) is sent again unchanged, same `seq`,
after a short pause: the platform stores it once, and a duplicate ack means it was stored
before. Only acknowledged samples are counted.

It reads its configuration as the first line of stdin (as `_live_client.py` does), writes
`{"event": "ready"}` once every device has an answer to a first batch, and after `go`
`{"event": "result", ...}` with, per device, the samples acknowledged; per second since `go`,
the samples acknowledged then; the ack times; the errors; and which node answered (the load
balancer's `X-Twinlink-Node`).
"""

from __future__ import annotations

import asyncio
import gc
import sys
import time
from collections import Counter
from pathlib import Path
from typing import Any

import orjson

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _live_client import Control, drive, emit, run, stats_ms, value_pool
from _live_http import RawHttp

PATH = "/api/v1/device/samples"
RETRY_PAUSE_S = 0.2  # after a batch got no ack, before it is sent again
NODE_HEADER = b"x-twinlink-node"


class NodeHttp(RawHttp):
    """RawHttp that also remembers which node answered (haproxy's X-Twinlink-Node)."""

    node: str = "-"

    async def post(self, body: bytes) -> tuple[int, bytes]:
        if self.writer is None or self.writer.is_closing():
            self.reader, self.writer = await asyncio.open_connection(self.host, self.port)
        assert self.reader is not None
        self.writer.write(
            f"POST {PATH} HTTP/1.1\r\n{self.head}\r\nContent-Length: {len(body)}\r\n\r\n".encode()
            + body
        )
        head = await self.reader.readuntil(b"\r\n\r\n")
        status, size, close = int(head[9:12]), 0, False
        for line in head.split(b"\r\n")[1:]:
            name, _, value = line.partition(b":")
            name = name.strip().lower()
            if name == b"content-length":
                size = int(value)
            elif name == NODE_HEADER:
                self.node = value.strip().decode()
            elif name == b"connection" and value.strip().lower() == b"close":
                close = True
        data = await self.reader.readexactly(size)
        if close:
            await self.close()
        return status, data


class Tally:
    """What the devices of this process saw, from `go` on."""

    def __init__(self, t0: float) -> None:
        self.t0 = t0
        self.per_second: Counter[int] = Counter()
        self.ack_ns: list[int] = []
        self.nodes: Counter[str] = Counter()
        self.errors: Counter[str] = Counter()
        self.resent = 0
        self.duplicates = 0


def batch_body(seq: int, size: int, pool: list[dict[str, float]], start: int) -> bytes:
    """One batch of `size` samples stamped now, 1 µs apart (so their times differ)."""
    now = time.time_ns()
    samples = [
        {"time": now + i * 1000, "values": pool[(start + i) % len(pool)]} for i in range(size)
    ]
    return orjson.dumps({"seq": seq, "samples": samples})


async def send_batch(
    client: NodeHttp, seq: int, size: int, pool: list[dict[str, float]], tally: Tally
) -> int:
    """Post one batch until it is acknowledged (never skip one that got no ack); the samples
    acknowledged."""
    body = batch_body(seq, size, pool, seq)
    t0 = time.perf_counter_ns()
    while True:
        try:
            status, answer = await client.post(body)
        except (OSError, asyncio.IncompleteReadError) as err:
            status, answer = 0, f"{type(err).__name__}: {err}".encode()
            await client.close()
        if status == 200:
            break
        tally.errors[f"HTTP {status}: {answer[:160].decode(errors='replace')}"] += 1
        tally.resent += 1
        await asyncio.sleep(RETRY_PAUSE_S)
    now = time.perf_counter_ns()
    ack = orjson.loads(answer)
    # a duplicate ack: stored by an earlier send whose answer was lost, every sample kept
    got = size if ack.get("duplicate") else int(ack["accepted"])
    tally.duplicates += bool(ack.get("duplicate"))
    tally.ack_ns.append(now - t0)
    tally.per_second[int(time.time() - tally.t0)] += got
    tally.nodes[client.node] += 1
    return got


async def one_device(
    client: NodeHttp,
    seq: int,
    size: int,
    pool: list[dict[str, float]],
    until: float,
    tally: Tally,
) -> int:
    """Post batches from `seq` + 1 on until `until` (perf_counter); the samples acknowledged."""
    acked = 0
    while time.perf_counter() < until:
        seq += 1
        acked += await send_batch(client, seq, size, pool, tally)
    return acked


async def http_devices(cfg: dict[str, Any], ctl: Control) -> None:
    size, seconds = int(cfg["batch_size"]), float(cfg["seconds"])
    pool = value_pool(int(cfg["signals"]))
    clients = [
        NodeHttp(cfg["url"], {"Authorization": f"Bearer {t}", "Content-Type": "application/json"})
        for t in cfg["tokens"]
    ]
    # Sequence numbers as the SDK makes them: from the time in µs, never reused by a restart.
    seq0 = time.time_ns() // 1000
    try:
        # One batch each first: opens the connections and makes each twin's series.
        warm = Tally(time.time())
        first = await asyncio.gather(*(send_batch(c, seq0, size, pool, warm) for c in clients))
        emit("ready", devices=len(clients), warmup_errors=dict(warm.errors))
        await ctl.wait("go")
        gc.disable()  # the client's pauses are not the server's
        tally = Tally(time.time())
        until = time.perf_counter() + seconds
        acked = await asyncio.gather(
            *(one_device(c, seq0, size, pool, until, tally) for c in clients)
        )
        gc.enable()
        emit(
            "result",
            tokens=cfg["tokens"],
            acked=[a + f for a, f in zip(acked, first, strict=True)],
            start=tally.t0,
            end=time.time(),
            per_second=sorted(tally.per_second.items()),
            ack_ms=stats_ms(tally.ack_ns),
            batches=len(tally.ack_ns),
            nodes=dict(tally.nodes),
            errors=dict(tally.errors.most_common(5)),
            resent=tally.resent,
            duplicates=tally.duplicates,
        )
        await ctl.wait("stop")  # alive until then, so its CPU time can still be read
    finally:
        await asyncio.gather(*(c.close() for c in clients))


async def main() -> None:
    await drive(http_devices)


if __name__ == "__main__":
    run(main)
