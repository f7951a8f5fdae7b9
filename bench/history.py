"""History reads of streams with many signals: export, samples, aggregate and downsample over
N = 1 000, 2 000 and 20 000 signals, in one batch and in many batches.

The store is filled directly through the codec (blocks as the writer stores them; the
per-stream signal cap of the writer does not apply), then every read runs in a child process
of its own against `SqliteHistory`, so a read that takes too long is stopped at `--cap`
seconds and shown as "> cap". Run it against another source tree (for a before/after
comparison) with PYTHONPATH=/that/tree/src.

    .venv/bin/python bench/history.py            # N = 1 000, 2 000, 20 000; about 2 minutes
    .venv/bin/python bench/history.py --quick    # N = 200, 2 000
"""

from __future__ import annotations

import argparse
import asyncio
import gc
import json
import os
import shutil
import sqlite3
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _report import machine_info, write_json

T0 = 1_704_067_200 * 10**9  # 2024-01-01T00:00:00Z
STEP = 10**7  # 10 ms between rows
TWIN = 1
STREAM = "telemetry"
OPS = ("export jsonl", "export csv", "samples 1000", "aggregate", "downsample 50")


@dataclass(frozen=True)
class Layout:
    name: str
    batches: int
    rows: int  # rows per batch; every signal has a value in every row


LAYOUTS = (Layout("one batch", 1, 3), Layout("many batches", 20, 5))


def fill(data_dir: Path, signals: int, layout: Layout) -> int:
    """Write the blocks of `layout` with `signals` signals; the number of values stored."""
    from twinlink.store.sqlite.history import SqliteHistory
    from twinlink.store.sqlite.history.codec import INSERT_BLOCK, block_row, encode

    async def create() -> None:  # the schema, by the tree's own migrations
        history = SqliteHistory(data_dir, "normal")
        await history.open()
        await history.close()

    asyncio.run(create())
    conn = sqlite3.connect(data_dir / "history.db", isolation_level=None)
    conn.execute("BEGIN")
    names = [f"s{i:05d}" for i in range(signals)]
    ids = []
    for name in names:
        cur = conn.execute(
            "INSERT INTO series (twin_id, stream, signal, max_span_ns) VALUES (?, ?, ?, ?)",
            (TWIN, STREAM, name, (layout.rows - 1) * STEP),
        )
        ids.append(cur.lastrowid)
    values = 0
    for b in range(layout.batches):
        times = [T0 + (b * layout.rows + r) * STEP for r in range(layout.rows)]
        rows = []
        for k, (sid, name) in enumerate(zip(ids, names, strict=True)):
            column = [float(k + r) / 7 for r in range(layout.rows)]
            rows.append(block_row(sid, encode(name, times, column)))
            values += layout.rows
        conn.executemany(INSERT_BLOCK, rows)
    conn.execute("COMMIT")
    conn.close()
    return values


async def run_op(data_dir: Path, op: str) -> dict[str, Any]:
    from twinlink.store.sqlite.history import SqliteHistory

    lo, hi = -(2**63), 2**63 - 1
    history = SqliteHistory(data_dir, "normal")
    await history.open()
    gc.collect()
    gc.freeze()  # as the server does after start: no full collection of startup objects
    try:
        started = time.perf_counter()
        size = 0
        if op.startswith("export"):
            fmt = op.split()[1]
            _, pieces = await history.export(TWIN, STREAM, None, lo, hi, fmt, "ns")
            async for piece in pieces:
                size += len(piece)
        elif op.startswith("samples"):
            page = await history.samples(TWIN, STREAM, None, lo, hi, int(op.split()[1]))
            size = sum(len(r["values"]) for r in page.rows)
        elif op == "aggregate":
            answer = await history.aggregate(TWIN, STREAM, None, T0, T0 + 10**12, 10**12, ["avg"])
            size = sum(len(r["values"]) for r in answer.rows)
        else:
            points = int(op.split()[1])
            extent = await history.extent(TWIN, STREAM, None)
            assert extent is not None
            started = time.perf_counter()
            found = await history.downsample(TWIN, STREAM, None, *extent, points, "minmax")
            size = sum(len(d.times) for d in found.values())
        return {"seconds": time.perf_counter() - started, "size": size}
    finally:
        await history.close()


def child(data_dir: str, op: str) -> None:
    print(json.dumps(asyncio.run(run_op(Path(data_dir), op))))


def measure(data_dir: Path, op: str, cap: float) -> dict[str, Any]:
    try:
        done = subprocess.run(
            [sys.executable, __file__, "--child", str(data_dir), op],
            capture_output=True,
            text=True,
            timeout=cap,
            check=False,
        )
    except subprocess.TimeoutExpired:
        return {"seconds": None, "size": None, "over_cap": True}
    if done.returncode != 0:
        return {"seconds": None, "size": None, "error": done.stderr.strip().splitlines()[-1:]}
    return {**json.loads(done.stdout.strip().splitlines()[-1]), "over_cap": False}


def show(row: dict[str, Any], cap: float) -> str:
    if row.get("over_cap"):
        took = f"> {cap:.0f} s"
    elif row["seconds"] is None:
        took = "error"
    else:
        took = f"{row['seconds']:.3f} s"
    size = row.get("size")
    unit = "bytes" if row["op"].startswith("export") else "values"
    out = "" if size is None else f"{size:,} {unit}"
    return (
        f"{row['signals']:>7,} {row['layout']:<13} {row['values']:>10,} {row['op']:<14} "
        f"{took:>11}  {out}"
    )


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    parser.add_argument("--quick", action="store_true", help="N = 200 and 2 000 only")
    parser.add_argument("--signals", default="", help="comma-separated N [1000,2000,20000]")
    parser.add_argument("--cap", type=float, default=60.0, help="most seconds per read")
    parser.add_argument("--json", type=Path, default=None, help="where to write the results")
    parser.add_argument("--ops", default="", help=f"comma-separated reads [{','.join(OPS)}]")
    args = parser.parse_args()
    if args.child:
        child(*args.child)
        return 0
    default = "200,2000" if args.quick else "1000,2000,20000"
    counts = [int(n) for n in (args.signals or default).split(",")]
    rows: list[dict[str, Any]] = []
    over: set[tuple[str, str]] = set()  # (layout, op) that went over the cap at a smaller N
    print(f"{'signals':>7} {'layout':<13} {'values':>10} {'read':<14} {'took':>11}  answer")
    for n in counts:
        for layout in LAYOUTS:
            folder = Path(tempfile.mkdtemp(prefix="twinlink-bench-history-"))
            try:
                values = fill(folder, n, layout)
                for op in args.ops.split(",") if args.ops else OPS:
                    base = {"signals": n, "layout": layout.name, "values": values, "op": op}
                    if (layout.name, op) in over:
                        row = {**base, "seconds": None, "size": None, "over_cap": True}
                        row["skipped"] = "over the cap at a smaller N"
                    else:
                        row = {**base, **measure(folder, op, args.cap)}
                    if row.get("over_cap"):
                        over.add((layout.name, op))
                    rows.append(row)
                    print(show(row, args.cap), flush=True)
            finally:
                shutil.rmtree(folder, ignore_errors=True)
    report = {
        "machine": machine_info(),
        "config": {
            "cap_s": args.cap,
            "signals": counts,
            "pythonpath": os.environ.get("PYTHONPATH"),
        },
        "rows": rows,
    }
    print(f"results: {write_json(report, args.json, 'history')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
