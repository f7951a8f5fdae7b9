"""Gateway benchmark: the latency the API gateway (the Data Link) adds, as in the Data Link
paper's Table 1, and its throughput, beside nginx as a plain reverse proxy.

Starts the paper's test API (nginx: GET and POST, small and large JSON) and nginx as a
reverse proxy to it, then `twinlink up` on a random loopback port with a temporary data
folder, one twin, a service `echo` whose base URL is the test API, and a service account
(editor) whose token every request carries. Three routes to the test API: direct, through
nginx and through the gateway (/twins/{slug}/services/echo/...).

Table 1: GET and POST, small (2 key-value pairs) and large (100 000), 50 sequential requests
a route on one kept-alive connection after 5 warm-up, timed by the client: min, max, mean,
median, SD, and the latency each proxy adds. Throughput: small GETs with wrk at 1, 16 and 64
connections, 5 s a run, with the CPU each request costs the proxy.

Prints the tables beside the paper's figures and the goals, and writes JSON to
bench/results/gateway-<UTC timestamp>.json (or --json PATH). Exits 1 when a request failed
or a process died, 2 when nginx or twinlink could not be started.

    .venv/bin/python bench/gateway.py            # full run, about 1 minute
    .venv/bin/python bench/gateway.py --quick    # smoke run, about 20 s

The test API and the nginx proxy are in _gw_upstream.py, Table 1 in _gw_latency.py, the wrk
runs in _gw_wrk.py, CPU accounting in _gw_cpu.py, the paper's figures, the goals and the
tables in _gw_report.py.
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _gw_cpu import settle, tree
from _gw_latency import Route, table_1, tests
from _gw_report import comparisons, default_json_path, goals, paper_rows, render
from _gw_upstream import TestApi, large_payload, waits_for_body
from _gw_wrk import run_wrk, wrk_binary, wrk_version
from _live_report import relative
from _report import machine_info, write_json
from _server import Twinlink

SERVICE = "echo"


def parse_args(argv: list[str] | None) -> tuple[dict[str, Any], Path | None]:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--quick", action="store_true", help="smoke run: 20 requests, 1 s wrk runs")
    p.add_argument("--json", type=Path, help="results file (default bench/results/gateway-*)")
    p.add_argument("--requests", type=int, help="timed requests a route and test (50; 20 quick)")
    p.add_argument("--seconds", type=float, help="seconds a wrk run (5; 1 quick)")
    p.add_argument("--concurrency", default="1,16,64", help="wrk connections (1,16,64)")
    a = p.parse_args(argv)
    config = {
        "quick": a.quick,
        "requests": a.requests or (20 if a.quick else 50),
        "warmup": 3 if a.quick else 5,
        "seconds": a.seconds or (1.0 if a.quick else 5.0),
        "concurrency": [int(c) for c in a.concurrency.split(",") if c.strip()],
    }
    return config, a.json


def main(argv: list[str] | None = None) -> int:
    config, json_path = parse_args(argv)
    report: dict[str, Any] = {
        "machine": machine_info(),
        "config": config,
        "loadavg": {"before": round(os.getloadavg()[0], 2)},
        "paper": paper_rows(),
    }
    tmp = Path(tempfile.mkdtemp(prefix="twinlink-bench-gateway-"))
    api = TestApi()
    server = Twinlink(tmp / "data")
    try:
        status = _benchmark(config, api, server, report)
    except (RuntimeError, OSError, httpx.HTTPError) as err:
        print(f"error: {type(err).__name__}: {err}", file=sys.stderr)
        if server.process is not None:
            print(f"server output:\n{server.log()[-3000:]}", file=sys.stderr)
        report["error"] = str(err)
        status = 1
    finally:
        server.stop()
        api.stop()
        shutil.rmtree(tmp, ignore_errors=True)
    if status == 2:
        return 2
    report["loadavg"]["after"] = round(os.getloadavg()[0], 2)
    if "goals" in report:
        print(render(report))
    saved = write_json(report, json_path or default_json_path())
    print(f"\nresults: {relative(saved)}")
    return status


def _benchmark(config: dict[str, Any], api: TestApi, server: Twinlink, rep: dict[str, Any]) -> int:
    """The run, filling in `rep`: 0 when every request succeeded, 1 when some failed, 2 when
    nginx or twinlink would not start."""
    t0 = time.perf_counter()
    large = large_payload()
    print("starting the test API and the nginx proxy ...", flush=True)
    try:
        api.start(large)
    except (RuntimeError, FileNotFoundError) as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    rep["nginx"], rep["wrk"] = api.version, wrk_version() or "wrk not installed"
    rep["payload_bytes"] = {"small": len(tests(large)[0].expect), "large": len(large)}
    rep["api_reads_body"] = waits_for_body(api.api_url, "/large", large, _JSON)
    if not rep["api_reads_body"]:
        raise RuntimeError("the test API answers POST before reading the body")

    print("starting twinlink ...", flush=True)
    try:
        server.start()
    except RuntimeError as err:
        print(f"error: twinlink did not start: {err}", file=sys.stderr)
        return 2
    slug, token = _setup_gateway(server, api.api_url)
    rep["settle_s"] = round(settle(tree(server.pid)), 1)
    routes = [
        Route("direct", api.api_url + "/"),
        Route("nginx", api.proxy_url + "/", api.pids("proxy")),
        Route("gateway", f"{server.url}/twins/{slug}/services/{SERVICE}/", tree(server.pid)),
    ]
    rep["routes"] = {r.name: r.base for r in routes}

    print(f"Table 1: {config['requests']} requests a test and route ...", flush=True)
    headers = {"Authorization": f"Bearer {token}"}
    rows = table_1(
        tests(large), routes, config["requests"], config["warmup"], headers, api.pids("api")
    )
    rep["table_1"] = rows
    rep["comparisons"] = comparisons(rows)
    errors = sum(r["errors"] for r in rows)

    errors += _throughput(config, routes, token, api, rep)
    if not server.alive():
        raise RuntimeError(f"twinlink died:\n{server.log()[-2000:]}")
    rep["goals"] = goals(rep)
    rep["seconds"] = round(time.perf_counter() - t0, 1)
    print(f"done in {rep['seconds']:.0f} s", flush=True)
    if errors:
        print(f"error: {errors} requests failed", file=sys.stderr)
    return 1 if errors else 0


_JSON = {"Content-Type": "application/json"}


def _setup_gateway(server: Twinlink, api_url: str) -> tuple[str, str]:
    """A twin, its service `echo` (the test API) and a service account that may write
    through the gateway; returns the twin's slug and the account's token."""
    admin = {"Authorization": f"Bearer {server.admin_token}"}
    doc = {
        "version": "1.0",
        "privacy": "public",
        "id": "urn:bench:gateway",
        "name": "Gateway bench",
        "description": "A twin whose service is the Data Link paper's test API.",
    }
    service = {"name": SERVICE, "base_url": api_url + "/", "auth": {"method": "none"}}
    with httpx.Client(base_url=server.url, headers=admin, timeout=30) as client:
        r = client.post("/api/v1/twins", json=doc)
        _check(r, "creating the twin")
        slug = str(r.json()["slug"])
        _check(client.post(f"/api/v1/twins/{slug}/services", json=service), "adding the service")
        r = client.post(
            f"/api/v1/twins/{slug}/service-accounts", json={"name": "bench", "role": "editor"}
        )
        _check(r, "making the service account")
        return slug, str(r.json()["token"])


def _check(r: httpx.Response, what: str) -> None:
    if r.status_code >= 300:
        raise RuntimeError(f"{what} failed: HTTP {r.status_code}: {r.text[:500]}")


def _throughput(
    config: dict[str, Any], routes: list[Route], token: str, api: TestApi, rep: dict[str, Any]
) -> int:
    """wrk runs of small GETs on every route at every concurrency; the failed requests."""
    if wrk_binary() is None:
        rep["throughput_status"] = "not measured: wrk is not installed (apt-get install -y wrk)"
        return 0
    print(
        f"throughput: wrk, {config['seconds']:g} s a run at {config['concurrency']} connections",
        flush=True,
    )
    runs = []
    for conns in config["concurrency"]:
        for route in routes:
            groups = {"api": api.pids("api")} | ({"proxy": route.pids} if route.pids else {})
            result = run_wrk(route.base + "small", conns, config["seconds"], token, groups)
            runs.append({"route": route.name, "connections": conns, **result})
    rep["throughput"] = runs
    return sum(r["non_2xx"] + r["socket_errors"] for r in runs)


if __name__ == "__main__":
    sys.exit(main())
