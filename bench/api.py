"""API benchmark: get twin, search and apply against a real server holding N twins.

Starts `twinlink up` on a random loopback port with a temporary data folder, loads N generated
twins through POST /api/v1/apply (YAML streams of 100 twins a request), then measures each case
with an async httpx client at a few concurrencies, for a bounded number of requests and a
bounded time. Also measures cold start (process spawn to the first 200 from /healthz) on the
loaded and on an empty data folder, and the settled RSS of the server. nginx serving one twin's
YAML from a file, measured with the same client in the same run, is the floor for "get twin".

Prints a table and writes JSON to bench/results/api-<UTC timestamp>.json (or --json PATH).
Exits 1 if the server failed or any request failed, 2 if the run could not start.

    .venv/bin/python bench/api.py            # 10 000 twins, about 2.5-3.5 minutes
    .venv/bin/python bench/api.py --quick    # 1 000 twins, fewer requests: a smoke run

This file is the command line and the order of the run. The rest is in _cases.py (loading the
twins, the measured cases, cold starts), _load.py (the load generator and latency statistics),
_report.py (machine description, goals, seed figures, table, JSON), _server.py (twinlink and
nginx processes) and _twins.py with _vocabulary.py (the generated twins and queries).
"""

from __future__ import annotations

import argparse
import asyncio
import os
import shutil
import sys
import tempfile
from dataclasses import asdict
from pathlib import Path
from typing import Any

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _cases import Options, cold_starts, load_twins, measure, setup_reader
from _load import CaseResult
from _report import SEED_TABLE_1, goals, machine_info, render, write_json
from _server import Nginx, Twinlink
from _twins import GeneratedTwin, Generator, dump

NGINX_FILE = "twin.yaml"  # the one twin's YAML that nginx serves


def run(coro: Any) -> Any:
    """asyncio.run, on uvloop when it is there: the client is one Python process, and a faster
    loop keeps its share of the measured latency down."""
    try:
        import uvloop
    except ImportError:
        return asyncio.run(coro)
    with asyncio.Runner(loop_factory=uvloop.new_event_loop) as runner:
        return runner.run(coro)


def parse_args(argv: list[str] | None) -> tuple[Options, Path | None]:
    p = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument("--twins", type=int, help="twins to load (default 10000; 1000 with --quick)")
    p.add_argument("--quick", action="store_true", help="smoke run: 1000 twins, fewer requests")
    p.add_argument(
        "--json",
        type=Path,
        help="where to write the JSON results (default bench/results/api-<timestamp>.json)",
    )
    p.add_argument("--concurrency", default="1,8", help="comma-separated list (default 1,8)")
    p.add_argument(
        "--requests", type=int, help="max requests per read case (default 3000; 300 quick)"
    )
    p.add_argument("--seconds", type=float, help="max seconds per case (default 10; 3 quick)")
    p.add_argument("--seed", type=int, default=42)
    p.add_argument("--no-nginx", action="store_true", help="skip the nginx reference")
    a = p.parse_args(argv)
    read = a.requests or (300 if a.quick else 3000)
    opts = Options(
        twins=a.twins or (1000 if a.quick else 10_000),
        concurrency=[int(c) for c in a.concurrency.split(",") if c.strip()],
        read_requests=read,
        write_requests=max(50, read // 5),
        max_seconds=a.seconds or (3.0 if a.quick else 10.0),
        warmup=20 if a.quick else 50,
        cold_reps=1 if a.quick else 3,
        batch=100,
        seed=a.seed,
        nginx=not a.no_nginx,
    )
    return opts, a.json


def main(argv: list[str] | None = None) -> int:
    opts, json_path = parse_args(argv)
    tmp = Path(tempfile.mkdtemp(prefix="twinlink-bench-"))
    server = Twinlink(tmp / "data")
    nginx = Nginx()
    report: dict[str, Any] = {
        "machine": machine_info(),
        "config": asdict(opts),
        "loadavg": {"before": round(os.getloadavg()[0], 2)},
    }
    try:
        status = _benchmark(opts, tmp, server, nginx, report)
    except (RuntimeError, httpx.HTTPError) as err:
        print(f"error: {err}", file=sys.stderr)
        if server.process is not None:
            print(f"server output:\n{server.log()[-3000:]}", file=sys.stderr)
        status = 1
        report["error"] = str(err)
    finally:
        nginx.stop()
        server.stop()
        shutil.rmtree(tmp, ignore_errors=True)
    if status == 2:
        return 2

    if "goals" in report:
        print(render(report))
    path = write_json(report, json_path)
    print(f"\nresults: {path}")
    return status


def _benchmark(
    opts: Options, tmp: Path, server: Twinlink, nginx: Nginx, report: dict[str, Any]
) -> int:
    """The run, filling in `report`: 0 when all went well, 1 when requests failed, 2 when the
    server would not start. Raises RuntimeError or httpx.HTTPError when the server fails."""
    print(f"generating {opts.twins} twins (seed {opts.seed}) ...", flush=True)
    gen = Generator(opts.seed)
    twins = gen.twins(opts.twins)

    print("starting twinlink ...", flush=True)
    try:
        server.start()
    except RuntimeError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    reader = run(setup_reader(server))
    print(f"loading {opts.twins} twins through POST /api/v1/apply ...", flush=True)
    report["load"] = run(load_twins(server, twins, opts.batch))
    print(f"  {report['load']['twins_per_s']} twins/s", flush=True)
    report["rss_mb"] = {"after_load": round(server.settled_rss() / 2**20, 1)}

    nginx_url = _start_nginx(opts, nginx, twins, report)
    print(
        f"measuring (concurrency {opts.concurrency}, <= {opts.read_requests} read / "
        f"{opts.write_requests} write requests and <= {opts.max_seconds:g} s per case, "
        "search twice that) ...",
        flush=True,
    )
    nginx_pid = nginx.process.pid if nginx.process else None
    cases = run(measure(opts, server, reader, twins, gen, nginx_url, NGINX_FILE, nginx_pid))
    report["cases"] = [asdict(c) for c in cases]
    nginx.stop()
    report["rss_mb"]["after_runs"] = round(server.settled_rss() / 2**20, 1)
    server.stop()

    _finish(opts, tmp, server, report)
    return _check_errors(cases)


def _start_nginx(
    opts: Options, nginx: Nginx, twins: list[GeneratedTwin], report: dict[str, Any]
) -> str | None:
    """Serve one twin's YAML from nginx, unless told not to; its URL, or None without nginx."""
    report["nginx"] = {"status": "not installed (apt-get install -y nginx-light)"}
    if not opts.nginx:
        report["nginx"] = {"status": "skipped (--no-nginx)"}
        return None
    if Nginx.binary() is None:
        return None
    sample = next(t for t in twins if "/twins/" in t.key and not t.extra_parts)
    try:
        url = nginx.start({NGINX_FILE: dump(sample.public).encode()})
    except (RuntimeError, OSError) as err:
        report["nginx"] = {"status": f"failed to start: {err}"}
        return None
    report["nginx"] = {
        "status": "measured",
        "version": nginx.version,
        "file_bytes": len(dump(sample.public).encode()),
    }
    return url


def _finish(opts: Options, tmp: Path, server: Twinlink, report: dict[str, Any]) -> None:
    """Cold starts on the loaded and on an empty store, then the store's size and the goals."""
    print("cold starts ...", flush=True)
    report["cold_start"] = {
        "loaded store": cold_starts(
            server.data_dir, opts.cold_reps, tmp, "loaded", server.admin_token
        ),
        "empty store": cold_starts(None, opts.cold_reps, tmp, "empty"),
    }
    report["store_mb"] = (
        round(sum(f.stat().st_size for f in server.data_dir.glob("*") if f.is_file()) / 2**20, 1)
        if server.data_dir.exists()
        else None
    )
    report["loadavg"]["after"] = round(os.getloadavg()[0], 2)
    report["seed"] = SEED_TABLE_1
    report["goals"] = goals(report)


def _check_errors(cases: list[CaseResult]) -> int:
    errors = sum(c.errors for c in cases)
    if not errors:
        return 0
    print(
        f"error: {errors} requests failed, e.g. "
        f"{next(c.first_error for c in cases if c.first_error)}",
        file=sys.stderr,
    )
    return 1


if __name__ == "__main__":
    sys.exit(main())
