"""History queries: a 1-hour window downsampled to 1 000 points out of many stored samples.

The samples (one float signal, evenly spaced over `history_span_s`, ending a minute ago) are
written straight into the stopped server's `history.db` with the repository's HistoryWriter,
in batches of 10 000 as a fast device would send them; then the server is started again and
`GET /api/v1/twins/{slug}/streams/{stream}/downsample` is timed over random 1-hour windows.
The same windows are also timed against the store alone (no HTTP), as a reference."""

from __future__ import annotations

import asyncio
import random
import sqlite3
import time
from pathlib import Path
from typing import Any
from urllib.parse import urlencode

import numpy as np
import orjson

from _live_fleet import Bench
from _live_http import RawHttp, closed_loop, percentile
from _live_procs import CpuWindow
from _live_report import GOALS, Row, at_most, failed, per_s, unavailable
from _live_stream import route_missing

SIGNAL = "force"
STREAM = "telemetry"
BATCH = 10_000
IN_FLIGHT = 8  # batches handed to the writer at once, so its rounds group them
WINDOW_NS = 3600 * 10**9
POINTS = 1000
METHODS = ("minmax", "lttb")


def twin_id(data_dir: Path, slug: str) -> int:
    conn = sqlite3.connect(f"file:{data_dir / 'twinlink.sqlite3'}?mode=ro", uri=True)
    try:
        return int(conn.execute("SELECT id FROM twins WHERE slug = ?", (slug,)).fetchone()[0])
    finally:
        conn.close()


async def load(
    path: Path, tid: int, slug: str, samples: int, span_s: float, per_batch: int = BATCH
) -> dict[str, Any]:
    """Write `samples` samples of SIGNAL into `path` (the server is stopped) in batches of
    `per_batch` (each batch is one stored block); their range."""
    from twinlink.domain.samples import SampleBatch, Value
    from twinlink.store.sqlite.history.writer import HistoryWriter

    end = time.time_ns() - 60 * 10**9
    step = span_s * 1e9 / samples
    start = end - int(step * (samples - 1))
    rng = np.random.default_rng(7)
    writer = HistoryWriter(path, "normal")  # loading is not what is measured: no fsync each
    await writer.open()
    pending: set[asyncio.Future[bool]] = set()
    t0 = time.perf_counter()
    try:
        for first in range(0, samples, per_batch):
            idx = np.arange(first, min(samples, first + per_batch))
            times = (start + idx * step).astype(np.int64).tolist()
            wave = 10 * np.sin(idx * step * 2 * np.pi / 600e9) + rng.normal(0, 0.5, len(idx))
            values: list[dict[str, Value]] = [{SIGNAL: v} for v in wave.round(4).tolist()]
            batch = SampleBatch(tid, slug, STREAM, times, values, time.time_ns())
            pending.add(asyncio.ensure_future(writer.append(batch)))
            if len(pending) >= IN_FLIGHT:
                done, pending = await asyncio.wait(pending, return_when=asyncio.FIRST_COMPLETED)
                for f in done:
                    f.result()
        await asyncio.gather(*pending)
    finally:
        await writer.close()
    seconds = time.perf_counter() - t0
    return {
        "samples": samples,
        "batch": per_batch,
        "start_ns": start,
        "end_ns": end,
        "rate_hz": round(1e9 / step, 1),
        "seconds": round(seconds, 2),
        "samples_per_s": round(samples / seconds),
        "file_mb": round(path.stat().st_size / 2**20, 1),
    }


def windows(data: dict[str, Any], count: int) -> list[tuple[int, int]]:
    """`count` random 1-hour windows inside the data (the whole range when it is shorter)."""
    rng = random.Random(11)
    lo, hi = data["start_ns"], data["end_ns"]
    latest = max(lo, hi - WINDOW_NS)
    return [(s, min(hi, s + WINDOW_NS)) for s in (rng.randint(lo, latest) for _ in range(count))]


def downsample_url(slug: str, method: str, window: tuple[int, int]) -> str:
    query = {
        "signals": SIGNAL,
        "points": POINTS,
        "method": method,
        "start": window[0],  # integer ns since the epoch; ISO 8601 works too
        "end": window[1],
    }
    return f"/api/v1/twins/{slug}/streams/{STREAM}/downsample?{urlencode(query)}"


async def history(bench: Bench) -> list[Row]:
    opts = bench.opts
    slug = bench.fleet.slugs[-3]
    case = f"history: load {opts.history_samples / 1e6:g} M samples"
    print(f"  {case} (server stopped) ...", flush=True)
    tid = twin_id(bench.server.data_dir, slug)
    bench.server.stop()
    try:
        data = await load(
            bench.server.data_dir / "history.db",
            tid,
            slug,
            opts.history_samples,
            opts.history_span_s,
            opts.history_batch,
        )
    finally:
        await asyncio.to_thread(bench.server.start)
    rows = [_load_row(case, data)]
    wins = windows(data, opts.history_requests)
    rows += await _http_rows(bench, slug, wins)
    rows += await asyncio.to_thread(_store_rows, bench.server.data_dir / "history.db", tid, wins)
    return rows


def _load_row(case: str, data: dict[str, Any]) -> Row:
    hours = (data["end_ns"] - data["start_ns"]) / 3.6e12
    return Row(
        case,
        measured=per_s(data["samples_per_s"], "samples"),
        value=data["samples_per_s"],
        note=f"HistoryWriter, batches of {data['batch']}, {data['rate_hz']:g} Hz over "
        f"{hours:.2f} h; history.db {data['file_mb']} MB; {data['seconds']:.1f} s",
        details=data,
    )


async def _http_rows(bench: Bench, slug: str, wins: list[tuple[int, int]]) -> list[Row]:
    headers = {"Authorization": f"Bearer {bench.server.admin_token}"}
    names = [f"history downsample {m}, 1 h -> {POINTS} pts" for m in METHODS]
    probe = RawHttp(bench.server.url, headers)
    status, body = await probe.request("GET", downsample_url(slug, METHODS[0], wins[0]))
    await probe.close()
    if route_missing(status, body):
        why = "GET /api/v1/twins/{slug}/streams/{stream}/downsample: no route yet"
        return [unavailable(n, why) for n in names]
    rows = []
    for name, method in zip(names, METHODS, strict=True):
        print(f"  {name} ...", flush=True)
        try:
            rows.append(await _http_run(bench, name, slug, method, wins, headers))
        except Exception as err:
            rows.append(failed(name, err))
    return rows


def _check(status: int, body: bytes) -> str | None:
    if status != 200:
        return f"HTTP {status}: {body[:300]!r}"
    got = len(orjson.loads(body)["signals"].get(SIGNAL, {}).get("time", []))
    return None if 0 < got <= POINTS else f"{got} points, expected 1 to {POINTS}"


async def _http_run(
    bench: Bench,
    name: str,
    slug: str,
    method: str,
    wins: list[tuple[int, int]],
    headers: dict[str, str],
) -> Row:
    def make(i: int) -> tuple[str, str, bytes]:
        return "GET", downsample_url(slug, method, wins[i % len(wins)]), b""

    cpu = CpuWindow(bench.server.pid, here=True)
    result = await closed_loop(bench.server.url, headers, make, _check, 1, len(wins), 300, 5)
    usage = cpu.stop()
    if result.errors:
        raise RuntimeError(f"{result.errors} requests failed, e.g. {result.first_error}")
    row = Row(
        name,
        measured=f"p50 {result.p50_ms:.1f} / p99 {result.p99_ms:.1f} ms",
        value=result.p99_ms,
        cpu=usage,
        note=f"{result.requests} requests over random 1-hour windows, one at a time",
        details=result.summary(),
    )
    row.goal, row.met = at_most(result.p99_ms, GOALS["history_ms"], "ms p99")
    return row


def _store_rows(path: Path, tid: int, wins: list[tuple[int, int]]) -> list[Row]:
    """The same windows straight from the store's downsample, in this process (reference)."""
    rows = []
    for method in METHODS:
        name = f"  reference: store only, {method}"
        try:
            times = _time_store(path, tid, method, wins)
        except Exception as err:
            rows.append(failed(name, err))
            continue
        rows.append(
            Row(
                name,
                measured=f"p50 {times[0]:.1f} / p99 {times[1]:.1f} ms",
                value=times[1],
                note="SQLite read + decode + downsample in one thread, no HTTP, no JSON",
                details={"p50_ms": times[0], "p99_ms": times[1], "points": times[2]},
            )
        )
    return rows


def _time_store(
    path: Path, tid: int, method: str, wins: list[tuple[int, int]]
) -> tuple[float, float, int]:
    from twinlink.store.sqlite.history.budget import ReadBudget
    from twinlink.store.sqlite.history.downsample import downsample
    from twinlink.store.sqlite.history.queries import select_series
    from twinlink.store.sqlite.history.reader import open_read_connection

    conn = open_read_connection(path)

    def run(w: tuple[int, int]) -> list[Any]:
        budget = ReadBudget(3600.0, 2**62)  # no limit: the store alone, as a reference
        return list(downsample(conn, series, w[0], w[1], POINTS, method, budget).values())

    try:
        series = select_series(conn, tid, STREAM, [SIGNAL])
        run(wins[0])  # warm the page cache
        took = []
        for w in wins:
            t0 = time.perf_counter()
            out = run(w)
            took.append(time.perf_counter() - t0)
    finally:
        conn.close()
    took.sort()
    points = len(out[0].times) if out else 0
    return 1000 * percentile(took, 0.5), 1000 * percentile(took, 0.99), points
