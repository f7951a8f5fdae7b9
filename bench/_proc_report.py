"""Goals of the processor benchmark, its comparison with the NTNU thesis, and the table.

The rows and the table's columns are the live benchmark's (_live_report.py)."""

from __future__ import annotations

from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from _live_report import OK, Row, _table, per_s
from _report import RESULTS

GOALS = {
    "steps_per_s": 20_000.0,  # one FMU processor, end to end
    "latency_p99_ms": 5.0,  # added by one processor, as a client sees it, at 1 000 samples/s
}

# The NTNU thesis (Tvilling digital platform): with an FMU in the loop, the delay grew without
# bound above 175-185 messages/s, and each message took 50-70 ms longer than without the FMU.
THESIS_RATE = "thesis: delay diverged at 175-185 msg/s with an FMU"
THESIS_DELAY = "thesis: +50-70 ms per message with an FMU"


def thesis_rows(rows: list[Row]) -> list[Row]:
    """Our figures beside the thesis's: the highest paced rates that kept up (in samples/s and
    in messages/s: the thesis counts messages), and the delay the processor added per message
    (one sample a message when that run was made)."""
    runs = [r.details for r in rows if r.status == OK and "diverged" in r.details]
    if not runs:
        return []
    kept = [r for r in runs if _kept_up(r)]
    gave_up = sorted({r["rate"] for r in runs if not _kept_up(r)})
    busiest = max(kept, key=lambda r: r["messages_per_s"], default=None)
    rate_row = Row("highest paced rates without divergence", measured="none", anchor=THESIS_RATE)
    if busiest is not None:
        samples = max(r["rate"] for r in kept)
        rate_row.measured = (
            f"{per_s(samples, 'samples')}; {per_s(busiest['messages_per_s'], 'msg')}"
        )
        rate_row.value = busiest["messages_per_s"]
        rate_row.note = (
            "the highest tried; no growing delay, no sample dropped, every output arrived; "
            f"most messages at {per_s(busiest['rate'])}"
            + (", one sample each" if not busiest["flush_s"] else " in 10 ms batches")
            + (f"; NOT kept up at {', '.join(per_s(r) for r in gave_up)}" if gave_up else "")
        )
    one = [r for r in runs if not r["flush_s"]] or runs
    low = min(one, key=lambda r: r["rate"])
    ms, server = low["client"]["ms"], low["processor"]["added_ms"]
    delay_row = Row(
        f"delay added per message at {per_s(low['rate'])}",
        measured=f"p50 {ms['p50']:.2f} / p99 {ms['p99']:.2f} ms",
        value=ms["p50"],
        note=f"client side, {low['messages']} messages"
        + (", one sample each" if not low["flush_s"] else " (10 ms batches)")
        + "; the server's part (bus in -> bus out) "
        f"p50 {server['p50']:.2f} / p99 {server['p99']:.2f} ms",
        anchor=THESIS_DELAY,
    )
    return [rate_row, delay_row]


def _kept_up(run: dict[str, Any]) -> bool:
    return (
        not run["diverged"]
        and run["processor"]["dropped"] == 0
        and run["live_dropped"] == 0
        and run["received"] == run["sent"]
    )


def default_json_path() -> Path:
    return RESULTS / f"processors-{datetime.now(UTC).strftime('%Y%m%dT%H%M%SZ')}.json"


def render(report: dict[str, Any]) -> str:
    m, la, rows = report["machine"], report["loadavg"], report["rows"]
    lines = [
        "",
        f"twinlink processors benchmark, {m['date']}" + (" (--quick)" if report["quick"] else ""),
        f"machine: {m['nproc']} CPUs ({m['cpu_model']}), {m['memory_gb']} GiB, "
        f"Python {m['python']}, FMPy {m['packages'].get('fmpy')}, git {m['git']}",
        "FMU: Tingen cantilever (FMI 2.0 co-simulation, examples/tingen/fmu), input F from the "
        "device's `force`, outputs theta and sigma; one step per input sample",
        f"server: history_sync {report['config']['history_sync']}; devices in client processes, "
        "live subscribers in this process (cli); srv = the server's main process, its "
        f"processor workers apart (see notes); load average before {la['before']}, after "
        f"{la.get('after', '-')}",
        "",
        *_table(rows),
    ]
    if la["before"] > 0.5 or any(r["cpu"].get("other_cpu_pct", 0) > 20 for r in rows):
        lines += [
            "",
            "WARNING: other work was running on this machine ('other' above 20% of a core, or "
            "a load average above 0.5 at the start); figures are noisy. Re-run on a quiet "
            "machine before comparing.",
        ]
    judged = [r for r in rows if r["met"] is not None]
    missing = [r["case"] for r in rows if r["status"] != OK]
    lines += [
        "",
        f"goals: {sum(r['met'] for r in judged)} of {len(judged)} met"
        + (f"; failed: {', '.join(missing)}" if missing else "")
        + (" (--quick: shorter runs, so only indicative)" if report["quick"] else ""),
        "the thesis ran other hardware and another platform: compare orders of magnitude.",
    ]
    return "\n".join(lines)
