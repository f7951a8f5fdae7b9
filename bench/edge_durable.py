"""The cost of the edge SDK's durable mode: samples/s one thread adds with `Device.add`, with a
memory buffer, a folder buffer, and a folder with `durable=True` (SQLite's `synchronous`
NORMAL: each sample written to the OS; FULL: each sample also fsynced).

Only the device side is measured: the device points at a port nothing listens on, so every
batch stays in its buffer and no network or server work shares the CPU. The modes run in
turns, `--rounds` times, and the best round of each counts (the machine is shared).

    .venv/bin/python bench/edge_durable.py [--samples N] [--rounds R] [--folder DIR] [--json PATH]
"""

from __future__ import annotations

import argparse
import logging
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from twinlink_edge import Device, DiskBuffer

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _report import machine_info, write_json

NOWHERE = "http://127.0.0.1:9"  # the discard port: nothing listens, the device retries
MODES = ("memory", "folder", "durable", "durable_full")


def one_run(mode: str, samples: int, folder: Path) -> float:
    """Seconds to add `samples` samples in `mode`."""
    options: dict[str, Any] = {"backoff_initial": 60.0, "backoff_max": 60.0}
    if mode != "memory":
        sync = "FULL" if mode == "durable_full" else "NORMAL"
        options["buffer"] = DiskBuffer(folder, synchronous=sync)
        options["durable"] = mode.startswith("durable")
    dev = Device(NOWHERE, "tld_bench", max_buffered_samples=samples + 1000, **options)
    dev.start()
    try:
        started = time.perf_counter()
        for i in range(samples):
            dev.add({"x": i * 0.5, "y": i}, time_ns=1_800_000_000_000_000_000 + i)
        return time.perf_counter() - started
    finally:
        dev.close(0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=20_000)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--folder", type=Path, help="where the buffers go (default: a temp dir)")
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    logging.getLogger("twinlink_edge").setLevel(logging.CRITICAL)  # the refused connects
    best: dict[str, float] = {}
    with tempfile.TemporaryDirectory(dir=args.folder) as tmp:
        for r in range(args.rounds):
            for mode in MODES:
                # durable_full fsyncs each sample: fewer of them, or a run takes minutes
                n = args.samples // 20 if mode == "durable_full" else args.samples
                seconds = one_run(mode, n, Path(tmp) / f"{mode}-{r}")
                best[mode] = max(best.get(mode, 0.0), n / seconds)
    rows = [
        {"mode": m, "samples_per_s": round(best[m]), "us_per_add": 1e6 / best[m]} for m in MODES
    ]
    print(f"{'mode':<14} {'samples/s':>10} {'us/add':>8}")
    for row in rows:
        print(f"{row['mode']:<14} {row['samples_per_s']:>10} {row['us_per_add']:>8.1f}")
    report = {"machine": machine_info(), "samples": args.samples, "rows": rows}
    print(f"results: {write_json(report, args.json, 'edge-durable')}")


if __name__ == "__main__":
    main()
