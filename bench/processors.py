"""Processor benchmark: FMU processors (blueprints in worker processes beside the live data)
against a real server, with FMPy and the blueprint alone as references.

Starts `twinlink up` on a random loopback port with a temporary data folder and the built-in
blueprints, builds the Tingen FMU (examples/tingen/fmu), and makes a twin with a device for
each run. Each run creates its FMU processors (input F <- the device's `force`, outputs theta
and sigma) through the API and deletes them afterwards. Devices run in client processes of
their own (bench/_live_client.py); live subscribers run in this process.

Cases: the references (raw FMPy and the blueprint alone, in this process); throughput of one
processor end to end; the latency one processor adds at paced rates; several processors on one
stream, paced and saturated; and the NTNU thesis's figures beside ours.

Prints a table (each figure beside its goal, met or not) and writes JSON to
bench/results/processors-<UTC timestamp>.json (or --json PATH). Exits 1 when a case failed or
the server died, 2 when the server could not be started.

    .venv/bin/python bench/processors.py            # full run, about 75 s
    .venv/bin/python bench/processors.py --quick    # smoke run, about 40 s

The cases are in _proc_reference.py, _proc_cases.py (throughput, latency) and _proc_many.py;
_proc_setup.py builds the FMU and makes the processors, _proc_watch.py holds the subscribers,
_proc_report.py the goals, the thesis rows and the table.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from collections.abc import Awaitable, Callable
from dataclasses import asdict
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _live_fleet import make_fleet
from _live_report import FAILED, Row, relative
from _proc_cases import latency, throughput
from _proc_many import many
from _proc_reference import reference
from _proc_report import default_json_path, render, thesis_rows
from _proc_setup import ProcBench, ProcOptions, build_tingen
from _report import RESULTS, _version, machine_info, write_json
from _server import Twinlink
from live import _guarded, run

Runner = Callable[[ProcBench], Awaitable[list[Row]]]
CASES: dict[str, Runner] = {
    "reference": reference,
    "throughput": throughput,
    "latency": latency,
    "many": many,
}
EXTRA_PACKAGES = ("twinlink-edge", "websockets", "orjson", "numpy", "fmpy", "msgspec")


def _ints(text: str) -> list[int]:
    return [int(x) for x in text.split(",") if x.strip()]


def parse_args(argv: list[str] | None) -> tuple[ProcOptions, Path | None]:
    summary = __doc__.split("\n\n")[0]
    p = argparse.ArgumentParser(description=summary)
    p.add_argument("--quick", action="store_true", help="smoke run, under a minute")
    p.add_argument("--json", type=Path, help="results file (default bench/results/processors-*)")
    p.add_argument("--cases", default=",".join(CASES), help=f"subset of {','.join(CASES)}")
    p.add_argument("--rates", default="100,1000,10000", help="paced rates (samples/s)")
    p.add_argument("--single-rate", type=int, default=1000, help="1 sample a message (0: no)")
    p.add_argument("--processors", type=int, default=8, help="processors in the many case (8)")
    p.add_argument("--profile", action="store_true", help="py-spy the server when pushed")
    a = p.parse_args(argv)
    chosen = a.cases.split(",")
    if set(chosen) - set(CASES):
        p.error(f"unknown cases {sorted(set(chosen) - set(CASES))}; choose from {','.join(CASES)}")
    if a.processors < 1:
        p.error("--processors is at least 1")
    return _options(a, [c for c in CASES if c in chosen]), a.json


def _options(a: argparse.Namespace, cases: list[str]) -> ProcOptions:
    """The loads of a full run, or of a --quick one."""
    q = a.quick
    return ProcOptions(
        quick=q,
        cases=cases,
        signals=4,
        reference_steps=100_000,
        reference_batch=10_000,
        throughput_samples=50_000 if q else 200_000,
        batch_size=5_000,
        rates=_ints(a.rates),
        latency_seconds=3.0 if q else 10.0,
        flush_s=0.01,
        single_rate=a.single_rate,
        processors=a.processors,
        many_rate=1_000,
        many_seconds=3.0 if q else 10.0,
        saturation_samples=10_000 if q else 50_000,
        profile=a.profile,
    )


def main(argv: list[str] | None = None) -> int:
    opts, json_path = parse_args(argv)
    os.environ.pop("TWINLINK_BLUEPRINTS_DIR", None)  # the built-in blueprints (entry points)
    machine = machine_info()
    machine["packages"].update({d: _version(d) for d in EXTRA_PACKAGES})
    config = asdict(opts) | {"history_sync": os.environ.get("TWINLINK_HISTORY_SYNC", "full")}
    report: dict[str, Any] = {
        "machine": machine,
        "quick": opts.quick,
        "config": config,
        "loadavg": {"before": round(os.getloadavg()[0], 2)},
    }
    with tempfile.TemporaryDirectory(prefix="twinlink-bench-processors-") as folder:
        server = Twinlink(Path(folder) / "data")
        try:
            status = run(_benchmark(opts, server, Path(folder), report))
        except Exception as err:  # before the cases (FMU build, twins): no table
            print(f"error: {type(err).__name__}: {err}", file=sys.stderr)
            report["error"] = str(err)
            status = 1
        finally:
            server.stop()  # before the folder goes
    return status if status == 2 else _finish(report, json_path, status)


def _finish(report: dict[str, Any], json_path: Path | None, status: int) -> int:
    """The table (when the cases ran) and the JSON file."""
    report["loadavg"]["after"] = round(os.getloadavg()[0], 2)
    if report.get("rows"):
        print(render(report))
    saved = write_json(report, json_path or default_json_path())
    print(f"\nresults: {relative(saved)}")
    return status


async def _benchmark(opts: ProcOptions, server: Twinlink, tmp: Path, report: dict[str, Any]) -> int:
    """The run, filling in report["rows"]: 0 when every case ran, 1 when one failed, 2 when
    the server would not start."""
    t0 = time.perf_counter()
    print("building the Tingen FMU and starting twinlink ...", flush=True)
    fmu = build_tingen(tmp / "fmu")
    try:
        server.start()
    except RuntimeError as err:
        print(f"error: twinlink did not start: {err}", file=sys.stderr)
        return 2
    # throughput, each paced rate, one sample a message, many paced, many saturated
    twins = 1 + len(opts.rates) + (1 if opts.single_rate else 0) + 2
    fleet = await make_fleet(server, "proc", twins)
    RESULTS.mkdir(parents=True, exist_ok=True)
    bench = ProcBench(server, opts, fleet, fmu, datetime.now(UTC).strftime("%Y%m%dT%H%M%SZ"))
    rows: list[Row] = []
    for name in opts.cases:
        print(f"{name} ({time.perf_counter() - t0:.0f} s) ...", flush=True)
        rows += await _guarded(CASES[name], bench, name)
        if not server.alive():
            rows.append(Row("server", status=FAILED, note=f"died:\n{server.log()[-2000:]}"))
            break
    rows += thesis_rows(rows)
    report["rows"] = [asdict(r) for r in rows]
    report["seconds"] = round(time.perf_counter() - t0, 1)
    print(f"done in {report['seconds']:.0f} s", flush=True)
    return 1 if any(r.status == FAILED for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
