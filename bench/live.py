"""Live data plane benchmark: ingest, device-to-subscriber latency, commands, history queries
and the memory of connected devices, against a real server.

Starts `twinlink up` on a random loopback port with a temporary data folder (history_sync
full, the default: every ack means durable), makes twins with one device each through the API,
then runs the cases. Devices, subscribers and idle connections run in client processes of
their own (bench/_live_client.py), on the same CPUs as the server.

Prints a table (each figure beside its goal, met or not) and writes JSON to
bench/results/live-<UTC timestamp>.json (or --json PATH). Exits 1 when a case failed or the
server died, 2 when the server could not be started. Cases whose API does not exist yet are
reported as "not available" and do not fail the run.

    .venv/bin/python bench/live.py            # full run, 2.5-3 minutes
    .venv/bin/python bench/live.py --quick    # smoke run, about 1 minute

This file is the command line and the order of the run. The cases are in _live_conns.py (RSS
with many connections), _live_ingest.py (throughput), _live_stream.py (latency, commands) and
_live_history.py (downsample queries); _live_fleet.py makes the twins and device tokens,
_live_procs.py runs the client processes and measures CPU, _live_report.py holds the goals
and prints the table.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import resource
import shutil
import sys
import tempfile
import time
from collections.abc import Awaitable, Callable, Coroutine
from dataclasses import asdict
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _live_commands_ws import commands_ws
from _live_conns import connections
from _live_fleet import Bench, Fleet, Options, make_fleet
from _live_history import history
from _live_ingest import many_devices, one_device
from _live_report import FAILED, Row, default_json_path, failed, relative, render
from _live_steady import steady
from _live_stream import commands, latency
from _report import RESULTS, _version, machine_info, write_json
from _server import Twinlink

Runner = Callable[[Bench], Awaitable[list[Row]]]

# In this order: memory first, on a server that has done nothing else yet; history last, as it
# restarts the server on a loaded history file.
CASES: dict[str, list[Runner]] = {
    "connections": [connections],
    "ingest": [one_device, many_devices],
    "steady": [steady],
    "latency": [latency],
    "commands": [commands, commands_ws],
    "history": [history],
}
EXTRA_PACKAGES = ("twinlink-edge", "websockets", "orjson", "numpy")
SPARE_TWINS = 3  # after the fleet's devices: latency, commands and history use one each


def _ints(text: str) -> list[int]:
    return [int(x) for x in text.split(",") if x.strip()]


def parse_args(argv: list[str] | None) -> tuple[Options, Path | None]:
    p = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument("--quick", action="store_true", help="smoke run: fewer samples, shorter")
    p.add_argument("--json", type=Path, help="results file (default bench/results/live-*.json)")
    p.add_argument("--cases", default=",".join(CASES), help=f"subset of {','.join(CASES)}")
    p.add_argument("--signals", type=int, default=4, help="float signals per sample (4)")
    p.add_argument("--batch-sizes", default="1000,5000", help="one-device batch sizes")
    p.add_argument("--devices", default="10,100", help="device counts of the many-device case")
    p.add_argument("--client-procs", type=int, default=2, help="processes for many devices")
    p.add_argument("--rates", default="100,1000,10000", help="latency case rates (samples/s)")
    p.add_argument("--connections", type=int, help="devices held open (default 1000)")
    p.add_argument("--steady-devices", type=int, help="steady fleet devices (2000; 500 quick)")
    p.add_argument("--steady-rate", type=float, default=2.0, help="steady samples/s a device")
    p.add_argument("--history-samples", type=int, help="stored samples (10 M; 1 M quick)")
    p.add_argument(
        "--history-batch", type=int, default=10_000, help="samples per stored block (10000)"
    )
    p.add_argument("--history-sync", choices=("full", "normal"), default="full")
    p.add_argument("--profile", action="store_true", help="py-spy the server while ingesting")
    a = p.parse_args(argv)
    unknown = set(a.cases.split(",")) - set(CASES)
    if unknown:
        p.error(f"unknown cases {sorted(unknown)}; choose from {','.join(CASES)}")
    if a.signals < 1 or a.client_procs < 1:
        p.error("--signals and --client-procs are at least 1")
    q = a.quick
    opts = Options(
        quick=q,
        cases=[c for c in CASES if c in a.cases.split(",")],
        signals=a.signals,
        one_samples=100_000 if q else 500_000,
        batch_sizes=_ints(a.batch_sizes),
        many_devices=_ints(a.devices),
        many_samples=200_000 if q else 1_000_000,
        client_procs=a.client_procs,
        rates=_ints(a.rates),
        latency_seconds=3.0 if q else 10.0,
        latency_flush_s=0.002,
        command_requests=300 if q else 2000,
        command_seconds=2.0 if q else 5.0,
        command_concurrency=32,
        history_samples=a.history_samples or (1_000_000 if q else 10_000_000),
        history_batch=a.history_batch,
        history_span_s=10_000.0,
        history_requests=50 if q else 200,
        connections=a.connections or 1000,
        steady_devices=a.steady_devices or (500 if q else 2000),
        steady_rate=a.steady_rate,
        steady_seconds=10.0 if q else 30.0,
        history_sync=a.history_sync,
        profile=a.profile,
    )
    return opts, a.json


def raise_fd_limit() -> None:
    """The server (a child) inherits this: a thousand sockets need more than 1 024 fds."""
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    want = hard if hard != resource.RLIM_INFINITY else 65536
    resource.setrlimit(resource.RLIMIT_NOFILE, (max(soft, min(want, 65536)), hard))


def main(argv: list[str] | None = None) -> int:
    opts, json_path = parse_args(argv)
    raise_fd_limit()
    os.environ["TWINLINK_HISTORY_SYNC"] = opts.history_sync
    tmp = Path(tempfile.mkdtemp(prefix="twinlink-bench-live-"))
    server = Twinlink(tmp / "data")
    machine = machine_info()
    machine["packages"].update({d: _version(d) for d in EXTRA_PACKAGES})
    report: dict[str, Any] = {
        "machine": machine,
        "quick": opts.quick,
        "config": asdict(opts),
        "loadavg": {"before": round(os.getloadavg()[0], 2)},
    }
    try:
        status = run(_benchmark(opts, server, report))
    except (RuntimeError, OSError, httpx.HTTPError) as err:  # before the cases: no table
        print(f"error: {err}", file=sys.stderr)
        report["error"] = str(err)
        status = 1
    finally:
        server.stop()
        shutil.rmtree(tmp, ignore_errors=True)
    if status == 2:
        return 2
    report["loadavg"]["after"] = round(os.getloadavg()[0], 2)
    if "rows" in report:
        print(render(report))
    path = write_json(report, json_path or default_json_path())
    print(f"\nresults: {relative(path)}")
    return status


def run(coro: Coroutine[Any, Any, int]) -> int:
    """asyncio.run, on uvloop when it is there (as the server runs)."""
    try:
        import uvloop
    except ImportError:
        return asyncio.run(coro)
    return uvloop.run(coro)


async def _benchmark(opts: Options, server: Twinlink, report: dict[str, Any]) -> int:
    """The run, filling in report["rows"]: 0 when every case ran, 1 when one failed, 2 when
    the server would not start."""
    print("starting twinlink ...", flush=True)
    try:
        await asyncio.to_thread(server.start)
    except RuntimeError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    steady = opts.steady_devices if "steady" in opts.cases else 0
    count = max([opts.connections, steady, *opts.many_devices]) + SPARE_TWINS
    print(f"creating {count} twins with a device each ...", flush=True)
    fleet: Fleet = await make_fleet(server, "bench", count)
    report["fleet"] = {"devices": len(fleet), "seconds": round(fleet.seconds, 1)}
    print(f"  {fleet.seconds:.1f} s", flush=True)
    stamp = datetime.now(UTC).strftime("%Y%m%dT%H%M%SZ")
    bench = Bench(server, opts, fleet, RESULTS, stamp)
    RESULTS.mkdir(parents=True, exist_ok=True)
    rows: list[Row] = []
    report["rows"] = rows
    t0 = time.perf_counter()
    for name in opts.cases:
        print(f"{name} ({time.perf_counter() - t0:.0f} s) ...", flush=True)
        for runner in CASES[name]:
            rows += await _guarded(runner, bench, name)
        if not server.alive():
            rows.append(Row("server", status=FAILED, note=f"died:\n{server.log()[-2000:]}"))
            break
    report["rows"] = [asdict(r) for r in rows]
    report["seconds"] = round(time.perf_counter() - t0, 1)
    return 1 if any(r.status == FAILED for r in rows) else 0


async def _guarded(runner: Runner, bench: Bench, name: str) -> list[Row]:
    try:
        return await runner(bench)
    except Exception as err:  # a case's own failure must not hide the others
        if bench.server.alive():
            return [failed(name, err)]
        return [failed(name, RuntimeError(f"{err}; server log:\n{bench.server.log()[-2000:]}"))]


if __name__ == "__main__":
    sys.exit(main())
