"""The report: the machine it ran on, the goals, the seed figures, the printed table and the
JSON file."""

from __future__ import annotations

import contextlib
import json
import math
import os
import platform
import sqlite3
import subprocess
import sys
from datetime import UTC, datetime
from importlib import metadata
from pathlib import Path
from typing import Any

import psutil

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "bench" / "results"

GOALS = {"search_p99_ms": 20.0, "cold_start_s": 2.0, "idle_rss_mb": 120.0}

# Aalto Data Link paper (Autiosalo et al., IEEE Access 2020), Table 1: client, API gateway and
# a test API each on a Raspberry Pi 4, over a switch; 50 sequential requests each. Milliseconds.
SEED_TABLE_1 = {
    "source": "Data Link for the Creation of Digital Twins (IEEE Access 2020), Table 1; "
    "Raspberry Pi 4 client, gateway and test API over a switch, 50 sequential requests",
    "rows": [
        {
            "test": "GET small (direct)",
            "min": 6.8,
            "max": 8.4,
            "mean": 7.1,
            "median": 7.1,
            "sd": 0.33,
        },
        {
            "test": "GET small via GW",
            "min": 38.8,
            "max": 47.1,
            "mean": 40.5,
            "median": 40.7,
            "sd": 1.15,
        },
        {
            "test": "POST small (direct)",
            "min": 7.2,
            "max": 8.6,
            "mean": 7.5,
            "median": 7.7,
            "sd": 0.38,
        },
        {
            "test": "POST small via GW",
            "min": 36.4,
            "max": 47.8,
            "mean": 41.8,
            "median": 42.0,
            "sd": 1.37,
        },
    ],
}

PACKAGES = (
    "twinlink",
    "fastapi",
    "starlette",
    "uvicorn",
    "pydantic",
    "httpx",
    "uvloop",
    "httptools",
    "PyYAML",
)


# --- the machine -------------------------------------------------------------------------------


def machine_info() -> dict[str, Any]:
    return {
        "date": datetime.now(UTC).isoformat(timespec="seconds"),
        "hostname": platform.node(),
        "nproc": len(os.sched_getaffinity(0))
        if hasattr(os, "sched_getaffinity")
        else os.cpu_count(),
        "cpu_model": _cpu_model(),
        "memory_gb": round(psutil.virtual_memory().total / 2**30, 1),
        "kernel": platform.release(),
        "python": platform.python_version(),
        "sqlite": sqlite3.sqlite_version,
        "packages": {d: _version(d) for d in PACKAGES},
        "git": _git_commit(),
        # What the server process imports: a PYTHONPATH can put another twinlink (or a patch) first.
        "twinlink_from": _twinlink_origin(),
        "pythonpath": os.environ.get("PYTHONPATH") or None,
    }


def _cpu_model() -> str:
    with contextlib.suppress(OSError):
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    return ""


def _version(dist: str) -> str | None:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return None


def _git_commit() -> str | None:
    """The work tree's short commit, with "+dirty-src" when src/ has uncommitted changes."""
    commit = None
    with contextlib.suppress(OSError, subprocess.CalledProcessError):
        commit = subprocess.run(
            ["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "-C", str(ROOT), "status", "--porcelain", "--", "src"],
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
        commit += "+dirty-src" if dirty else ""
    return commit


def _twinlink_origin() -> str | None:
    out = subprocess.run(
        [sys.executable, "-c", "import twinlink; print(twinlink.__file__)"],
        capture_output=True,
        text=True,
        check=False,
    )
    return out.stdout.strip() or None


# --- goals and output --------------------------------------------------------------------------


def goals(report: dict[str, Any]) -> dict[str, Any]:
    search_c1 = next(
        (r for r in report["cases"] if r["name"].startswith("search") and r["concurrency"] == 1),
        None,
    )
    p99 = search_c1["p99_ms"] if search_c1 else math.nan
    cold = report["cold_start"]["loaded store"]["median_s"]
    rss = max(report["rss_mb"]["after_load"], report["rss_mb"]["after_runs"])
    return {
        "search_p99": {
            "goal": f"search p99 < {GOALS['search_p99_ms']:.0f} ms (concurrency 1)",
            "measured": f"{p99:.1f} ms",
            "value": p99,
            "met": p99 < GOALS["search_p99_ms"],
        },
        "cold_start": {
            "goal": f"cold start < {GOALS['cold_start_s']:.0f} s (loaded store, median)",
            "measured": f"{cold:.2f} s",
            "value": cold,
            "met": cold < GOALS["cold_start_s"],
        },
        "idle_rss": {
            "goal": f"idle RSS < {GOALS['idle_rss_mb']:.0f} MB (worst of after load/runs)",
            "measured": f"{rss:.0f} MB",
            "value": rss,
            "met": rss < GOALS["idle_rss_mb"],
        },
    }


def write_json(report: dict[str, Any], path: Path | None, name: str = "api") -> Path:
    """Write the report to `path`, or to bench/results/<name>-<UTC timestamp>.json."""
    stamp = datetime.now(UTC).strftime("%Y%m%dT%H%M%SZ")
    path = path or RESULTS / f"{name}-{stamp}.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(report, indent=2, ensure_ascii=False) + "\n")
    return path


def fmt(x: float | None, digits: int = 2) -> str:
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    return f"{x:.{digits}f}"


def pct(x: float | None) -> str:
    return "-" if x is None else f"{x:.0f}%"


def render(report: dict[str, Any]) -> str:
    """The table printed at the end of a run."""
    lines = [
        *_heading(report),
        "",
        _load_line(report["load"]),
        "",
        *_case_table(report),
        "",
        *_seed_lines(),
        "",
        *_startup_lines(report),
        "",
        *_goal_lines(report),
    ]
    return "\n".join(lines)


def _heading(report: dict[str, Any]) -> list[str]:
    m = report["machine"]
    lines = [
        "",
        f"twinlink API benchmark, {m['date']}, {report['config']['twins']} twins in the store",
        f"machine: {m['nproc']} CPUs ({m['cpu_model']}), {m['memory_gb']} GiB, "
        f"Python {m['python']}, SQLite {m['sqlite']}, git {m['git']}",
    ]
    origin = m.get("twinlink_from") or ""
    if origin and not origin.startswith(str(ROOT / "src")):
        lines.append(f"twinlink imported from {origin}, not this work tree (git above is the tree)")
    lines.append(
        "NOTE: the load generator (httpx, one Python process) shares these CPUs with the "
        "server; latencies include client overhead (see the nginx row)."
    )
    la = report["loadavg"]
    lines.append(
        f"load average (1 min) before the run {la['before']}, after {la['after']}; 'other' = CPU "
        "used by other processes during a case (100% = one core)"
    )
    if (
        la["before"] > 0.5
        or la["after"] > 2.5
        or any(r["other_cpu_pct"] > 20 for r in report["cases"])
    ):
        lines.append(
            "WARNING: other work was running on this machine; figures are noisy. "
            "Re-run on a quiet machine before comparing."
        )
    return lines


def _load_line(load: dict[str, Any]) -> str:
    return (
        f"load: {load['twins']} twins ({load['documents']} documents) in {load['requests']} "
        f"apply requests of {load['twins_per_request']} twins (~{load['mean_request_kb']} KiB): "
        f"{load['seconds']} s = {load['twins_per_s']} twins/s; request p50 "
        f"{load['request_p50_ms']} ms, p99 {load['request_p99_ms']} ms"
    )


def _case_table(report: dict[str, Any]) -> list[str]:
    head = (
        f"{'case':<48} {'conc':>4} {'reqs':>6} {'req/s':>8} {'p50':>7} {'p90':>7} {'p99':>7} "
        f"{'max':>7} {'err':>4} {'srv CPU':>8} {'cli CPU':>8} {'other':>6}"
    )
    lines = [head + "   (latencies in ms)", "-" * len(head)]
    for r in report["cases"]:
        lines.append(
            f"{r['name']:<48} {r['concurrency']:>4} {r['requests']:>6} {r['rps']:>8.0f} "
            f"{fmt(r['p50_ms']):>7} {fmt(r['p90_ms']):>7} {fmt(r['p99_ms']):>7} "
            f"{fmt(r['max_ms']):>7} "
            f"{r['errors']:>4} {pct(r['server_cpu_pct']):>8} {pct(r['client_cpu_pct']):>8} "
            f"{pct(r['other_cpu_pct']):>6}"
        )
    if report["nginx"]["status"] != "measured":
        lines.append(f"{'nginx reference':<48} {report['nginx']['status']}")
    return lines


def _seed_lines() -> list[str]:
    lines = [
        "seed figures (different hardware: Raspberry Pi 4 client/gateway/API over a switch, "
        "50 sequential requests; paper Table 1):"
    ]
    for row in SEED_TABLE_1["rows"]:
        lines.append(
            f"  {row['test']:<22} median {row['median']:>5} ms  mean {row['mean']:>5}  "
            f"min {row['min']:>5}  max {row['max']:>5}"
        )
    return lines


def _startup_lines(report: dict[str, Any]) -> list[str]:
    """Cold starts, idle RSS and the size of the store."""
    lines = [
        f"cold start (spawn -> first 200 from /healthz), median of {report['config']['cold_reps']}:"
    ]
    for label, cs in report["cold_start"].items():
        lines.append(
            f"  {label:<22} {cs['median_s']:.3f} s  (runs {cs['runs_s']}; 'serving at' line "
            f"{cs['ready_line_median_s']} s; "
            f"idle RSS after start {cs['idle_rss_mb_after_start']} MB)"
        )
    rss = report["rss_mb"]
    lines.append(
        f"idle RSS: after load {rss['after_load']} MB, after the runs {rss['after_runs']} MB; "
        f"store on disk {report['store_mb']} MB"
    )
    return lines


def _goal_lines(report: dict[str, Any]) -> list[str]:
    twins = report["config"]["twins"]
    lines = [
        "goals:"
        if twins == 10_000
        else f"goals (set for 10 000 twins; this run has {twins}, so only indicative):"
    ]
    for g in report["goals"].values():
        lines.append(
            f"  {g['goal']:<44} measured {g['measured']:<10} {'MET' if g['met'] else 'NOT MET'}"
        )
    return lines
