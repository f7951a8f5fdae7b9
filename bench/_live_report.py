"""Rows of the live benchmark, its goals and anchors, the printed table and the JSON file.

Every case ends as one or more `Row`s: a figure with its goal (met or not) and an anchor from
the origin documents, or a row saying why it was not measured."""

from __future__ import annotations

from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from _report import RESULTS, ROOT

OK, FAILED, UNAVAILABLE = "ok", "failed", "not available"

# The goals, on a 2-core machine.
GOALS = {
    "ingest_one": 50_000.0,  # samples/s from one device
    "ingest_many": 100_000.0,  # samples/s from many devices together
    "latency_p99_ms": 10.0,  # device -> subscriber, at 1 000 samples/s
    "command_p99_ms": 5.0,  # sequential round trip
    "commands_per_s": 5_000.0,  # concurrent
    "history_ms": 50.0,  # 1-hour window, 1 000 points, from 10 M samples
    "steady_ack_p99_ms": 100.0,  # 2 000 devices at 2 samples/s, one sample a batch (issue 13)
}


@dataclass
class Row:
    case: str
    status: str = OK
    measured: str = ""  # the figure as a person reads it
    value: float | None = None  # the figure the goal is judged on
    goal: str = ""
    met: bool | None = None
    anchor: str = ""  # the figure beside another system's
    cpu: dict[str, float] = field(default_factory=dict)
    note: str = ""
    details: dict[str, Any] = field(default_factory=dict)


def at_least(value: float, goal: float, unit: str) -> tuple[str, bool]:
    return f">= {goal:,.0f} {unit}".replace(",", " "), value >= goal


def at_most(value: float, goal: float, unit: str) -> tuple[str, bool]:
    return f"<= {goal:g} {unit}", value <= goal


def unavailable(case: str, why: str) -> Row:
    return Row(case, status=UNAVAILABLE, measured="-", note=why)


def failed(case: str, err: BaseException) -> Row:
    return Row(case, status=FAILED, measured="-", note=f"{type(err).__name__}: {err}"[:300])


def per_s(x: float, unit: str = "") -> str:
    """`x` with thin thousands: "56 174 samples/s", or "1 000/s" without a unit."""
    n = f"{x:,.0f}".replace(",", " ")
    return f"{n} {unit}/s" if unit else f"{n}/s"


# --- output ---------------------------------------------------------------------------------


def default_json_path() -> Path:
    return RESULTS / f"live-{datetime.now(UTC).strftime('%Y%m%dT%H%M%SZ')}.json"


def render(report: dict[str, Any]) -> str:
    m = report["machine"]
    la = report["loadavg"]
    lines = [
        "",
        f"twinlink live benchmark, {m['date']}" + (" (--quick)" if report["quick"] else ""),
        f"machine: {m['nproc']} CPUs ({m['cpu_model']}), {m['memory_gb']} GiB, "
        f"Python {m['python']}, SQLite {m['sqlite']}, git {m['git']}",
        f"server: history_sync {report['config']['history_sync']}; clients: separate "
        "processes on the same CPUs; a sample = "
        f"{report['config']['signals']} float signals; load average before {la['before']}, "
        f"after {la.get('after', '-')}",
        "",
        *_table(report["rows"]),
    ]
    noisy = la["before"] > 0.5 or any(r["cpu"].get("other_cpu_pct", 0) > 20 for r in report["rows"])
    if noisy:
        lines += [
            "",
            "WARNING: other work was running on this machine ('other' above 20% of a core, "
            "or a load average above 0.5 at the start); figures are noisy. Re-run on a "
            "quiet machine before comparing.",
        ]
    judged = [r for r in report["rows"] if r["met"] is not None]
    missing = [r["case"] for r in report["rows"] if r["status"] != OK]
    lines += [
        "",
        f"goals: {sum(r['met'] for r in judged)} of {len(judged)} met"
        + (f"; failed or not available: {', '.join(missing)}" if missing else "")
        + (" (--quick: smaller loads, so only indicative)" if report["quick"] else ""),
        "anchors are other systems on other hardware: compare orders of magnitude.",
    ]
    return "\n".join(lines)


def _table(rows: list[dict[str, Any]]) -> list[str]:
    head = (
        f"{'case':<44} {'measured':<30} {'goal':<20} {'verdict':<13} "
        f"{'srv':>5} {'cli':>5} {'other':>5}"
    )
    lines = [head + "   (CPU in % of one core)", "-" * len(head)]
    for r in rows:
        cpu = r["cpu"]
        lines.append(
            f"{r['case']:<44} {r['measured']:<30} {r['goal']:<20} {_verdict(r):<13} "
            f"{_pct(cpu.get('server_cpu_pct')):>5} {_pct(cpu.get('client_cpu_pct')):>5} "
            f"{_pct(cpu.get('other_cpu_pct')):>5}"
        )
        if r["note"]:
            lines.append(f"    {r['note']}")
        if r["anchor"]:
            lines.append(f"    anchor: {r['anchor']}")
    return lines


def _verdict(row: dict[str, Any]) -> str:
    if row["status"] != OK:
        return str(row["status"]).upper()
    if row["met"] is None:
        return ""
    return "met" if row["met"] else "NOT MET"


def _pct(x: float | None) -> str:
    return "-" if x is None else f"{x:.0f}"


def relative(path: Path) -> str:
    try:
        return str(path.resolve().relative_to(ROOT))
    except ValueError:
        return str(path)
