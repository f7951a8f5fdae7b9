"""What the benchmark does to a twinlink server: load the generated twins, run the measured
cases (healthz, get twin, search, apply; nginx as the reference) and time cold starts."""

from __future__ import annotations

import json
import random
import statistics
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any
from urllib.parse import quote

import httpx

from _load import Case, CaseResult, Req, expect, percentile, run_case
from _server import Twinlink
from _twins import GeneratedTwin, Generator, dump, dump_stream

YAML = {"Content-Type": "application/yaml"}


@dataclass
class Options:
    twins: int
    concurrency: list[int]
    read_requests: int
    write_requests: int
    max_seconds: float
    warmup: int
    cold_reps: int
    batch: int
    seed: int
    nginx: bool


async def setup_reader(server: Twinlink) -> str:
    """A non-admin user in group-1, as most readers will be; returns its session token."""
    password = "bench-reader-" + server.admin_password
    async with httpx.AsyncClient(
        base_url=server.url, timeout=30, headers={"Authorization": f"Bearer {server.admin_token}"}
    ) as admin:
        r = await admin.post(
            "/api/v1/users",
            json={"username": "reader", "password": password, "groups": ["group-1"]},
        )
        r.raise_for_status()
        r = await admin.post(
            "/api/v1/auth/login", json={"username": "reader", "password": password}
        )
        r.raise_for_status()
        return str(r.json()["token"])


async def load_twins(server: Twinlink, twins: list[GeneratedTwin], batch: int) -> dict[str, Any]:
    """POST the twins as YAML streams of `batch` twins (all parts of a twin in one request),
    one request at a time as an importer would; fills in each twin's slug."""
    by_key = {t.key: t for t in twins}
    bodies = [
        dump_stream([d for t in twins[i : i + batch] for d in t.documents()])
        for i in range(0, len(twins), batch)
    ]
    latencies = []
    outcomes: dict[str, int] = {}
    async with httpx.AsyncClient(
        base_url=server.url,
        timeout=300,
        headers={"Authorization": f"Bearer {server.admin_token}", **YAML},
    ) as c:
        start = time.perf_counter()
        for body in bodies:
            t0 = time.perf_counter()
            r = await c.post("/api/v1/apply", content=body)
            latencies.append(time.perf_counter() - t0)
            if r.status_code != 200:
                raise RuntimeError(f"loading failed: HTTP {r.status_code}: {r.text[:1000]}")
            for applied in r.json()["results"]:
                by_key[applied["id"]].slug = applied["slug"]
                outcomes[applied["outcome"]] = outcomes.get(applied["outcome"], 0) + 1
        elapsed = time.perf_counter() - start
    missing = [t.key for t in twins if not t.slug]
    if missing:
        raise RuntimeError(f"{len(missing)} twins got no slug, e.g. {missing[:3]}")
    latencies.sort()
    return {
        "twins": len(twins),
        "documents": sum(len(t.documents()) for t in twins),
        "requests": len(bodies),
        "twins_per_request": batch,
        "mean_request_kb": round(statistics.fmean(len(b) for b in bodies) / 1024, 1),
        "seconds": round(elapsed, 2),
        "twins_per_s": round(len(twins) / elapsed, 1),
        "request_p50_ms": round(1000 * percentile(latencies, 0.5), 1),
        "request_p99_ms": round(1000 * percentile(latencies, 0.99), 1),
        "outcomes": outcomes,
    }


def update_bodies(twins: list[GeneratedTwin], count: int, rng: random.Random) -> list[bytes]:
    """Public parts of random twins, each with a new description (so every apply is an update)."""
    sentinel = "BENCH-DESCRIPTION-SENTINEL"
    out = []
    for i in range(count):
        twin = rng.choice(twins)
        doc = {**twin.public, "description": sentinel}
        text = dump(doc)
        new = f"{twin.public['description']} Revised by the benchmark, revision {i}."
        # A JSON string is a valid YAML double-quoted scalar.
        out.append(text.replace(sentinel, json.dumps(new), 1).encode())
    return out


# --- the measured cases ------------------------------------------------------------------------


@dataclass
class _Inputs:
    """What the cases send, drawn once for all concurrencies."""

    get_paths: list[str]
    search_paths: list[str]
    pool_update: list[GeneratedTwin]  # twins whose descriptions the "changed" case rewrites
    pool_same: list[GeneratedTwin]  # twins the "unchanged" case re-applies as they are
    n_write: int
    reader: dict[str, str]  # headers of the non-admin reader
    admin: dict[str, str]  # headers of the admin
    search_totals: list[int]  # hits of the search warm-up requests, cleared after each case


def _inputs(
    opts: Options, server: Twinlink, reader_token: str, twins: list[GeneratedTwin], gen: Generator
) -> _Inputs:
    rng = random.Random(opts.seed + 1)
    slugs = [t.slug for t in twins]
    get_paths = [
        f"/api/v1/twins/{rng.choice(slugs)}" for _ in range(opts.read_requests + opts.warmup)
    ]
    queries = gen.queries(500)
    search_paths = [
        f"/api/v1/search?q={quote(rng.choice(queries))}"
        for _ in range(opts.read_requests + opts.warmup)
    ]
    machines = [t for t in twins if "/twins/" in t.key]
    return _Inputs(
        get_paths=get_paths,
        search_paths=search_paths,
        pool_update=machines[0::2],
        pool_same=machines[1::2],
        n_write=opts.write_requests + opts.warmup,
        reader={"Authorization": f"Bearer {reader_token}"},
        admin={"Authorization": f"Bearer {server.admin_token}"},
        search_totals=[],
    )


def _cycle(items: list[Any]) -> Callable[[int], Any]:
    return lambda i: items[i % len(items)]


def _twinlink_cases(opts: Options, url: str, inp: _Inputs, conc: int) -> list[Case]:
    # Fresh bodies per concurrency: a body applied once is "unchanged" the second time.
    upd = _cycle(update_bodies(inp.pool_update, inp.n_write, random.Random(opts.seed + 100 + conc)))
    same = _cycle(
        [
            dump(t.public).encode()
            for t in random.Random(opts.seed + 200 + conc).choices(inp.pool_same, k=inp.n_write)
        ]
    )
    get_path, search_path = _cycle(inp.get_paths), _cycle(inp.search_paths)
    reads, writes = opts.read_requests, opts.write_requests
    return [
        Case(
            "GET /healthz (no token; floor of the stack)",
            "twinlink",
            url,
            {},
            lambda i: Req("GET", "/healthz"),
            expect(200),
            reads,
        ),
        Case(
            "get twin: GET /api/v1/twins/{slug}",
            "twinlink",
            url,
            inp.reader,
            lambda i: Req("GET", get_path(i)),
            expect(200),
            reads,
        ),
        Case(
            "search: GET /api/v1/search?q=",
            "twinlink",
            url,
            inp.reader,
            lambda i: Req("GET", search_path(i)),
            expect(200),
            reads,
            lambda r: inp.search_totals.append(r.json()["total"]),
        ),
        Case(
            "apply, changed description",
            "twinlink",
            url,
            inp.admin,
            lambda i: Req("POST", "/api/v1/apply", upd(i), YAML),
            expect(200, "updated"),
            writes,
        ),
        Case(
            "apply, unchanged re-apply",
            "twinlink",
            url,
            inp.admin,
            lambda i: Req("POST", "/api/v1/apply", same(i), YAML),
            expect(200, "unchanged"),
            writes,
        ),
    ]


async def measure(
    opts: Options,
    server: Twinlink,
    reader_token: str,
    twins: list[GeneratedTwin],
    gen: Generator,
    nginx_url: str | None,
    nginx_file: str,
    nginx_pid: int | None,
) -> list[CaseResult]:
    """Every case at every concurrency, printing a line for each as it finishes."""
    inp = _inputs(opts, server, reader_token, twins, gen)
    results: list[CaseResult] = []
    for conc in opts.concurrency:
        cases = _twinlink_cases(opts, server.url, inp, conc)
        if nginx_url:
            nginx = Case(
                "nginx: GET one twin's YAML file (reference)",
                "nginx",
                nginx_url,
                {},
                lambda i: Req("GET", f"/{nginx_file}"),
                expect(200),
                opts.read_requests,
            )
            cases.insert(0, nginx)
        for case in cases:
            if not server.alive():
                raise RuntimeError(f"the server died before {case.name!r}:\n{server.log()[-3000:]}")
            search = case.name.startswith("search")
            r = await run_case(
                case,
                conc,
                # Search is the case with a latency goal: give it time for a p99 worth the name.
                opts.max_seconds * (2 if search else 1),
                opts.warmup,
                server.pid if case.target == "twinlink" else nginx_pid,
            )
            if search and inp.search_totals:
                totals = sorted(inp.search_totals)
                r.extra["hits_per_query_median"] = totals[len(totals) // 2]
                r.extra["hits_per_query_max"] = totals[-1]
                inp.search_totals.clear()
            results.append(r)
            print(
                f"  {case.name:<48} c={conc:<2} {r.requests:>6} req  {r.rps:8.0f}/s  "
                f"p50 {r.p50_ms:7.2f}  p99 {r.p99_ms:7.2f} ms  errors {r.errors}",
                flush=True,
            )
    if not server.alive():
        raise RuntimeError(f"the server died:\n{server.log()[-3000:]}")
    return results


# --- cold start --------------------------------------------------------------------------------


def cold_starts(
    data_dir: Path | None, reps: int, tmp: Path, label: str, token: str | None = None
) -> dict[str, Any]:
    """Spawn to first 200 from /healthz, `reps` times; an empty data folder is new each time."""
    times, ready_lines = [], []
    rss_mb = None
    for rep in range(reps):
        folder = data_dir if data_dir is not None else tmp / f"empty-{label}-{rep}"
        srv = Twinlink(folder) if token is None else Twinlink(folder, admin_token=token)
        try:
            srv.spawn()
            times.append(srv.wait_healthy())
            if srv.ready_line_at is not None:
                ready_lines.append(srv.ready_line_at - srv.spawned_at)
            if rep == reps - 1:
                rss_mb = srv.settled_rss() / 2**20
        finally:
            srv.stop()
    return {
        "runs_s": [round(t, 3) for t in times],
        "median_s": round(statistics.median(times), 3),
        "ready_line_median_s": round(statistics.median(ready_lines), 3) if ready_lines else None,
        "idle_rss_mb_after_start": round(rss_mb, 1) if rss_mb is not None else None,
    }
