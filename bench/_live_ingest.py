"""Ingest throughput with persistence: samples/s from the first add to the final ack (every
acked sample is durable), from one device and from many devices together. The devices are SDK
`AsyncDevice`s in client processes of their own."""

from __future__ import annotations

from typing import Any

from _live_fleet import Bench
from _live_procs import ClientGroup, ClientProc, CpuWindow, Profiler
from _live_report import GOALS, Row, at_least, failed, per_s


async def run_ingest(
    bench: Bench, tokens: list[str], samples: int, batch_size: int, procs: int, label: str
) -> dict[str, Any]:
    """`samples` samples from each device of `tokens`, the devices spread over `procs`
    client processes; the aggregate rate and the CPU used meanwhile."""
    chunks = [tokens[i::procs] for i in range(procs)]
    configs = [
        {
            "mode": "ingest",
            "url": bench.server.url,
            "tokens": chunk,
            "samples": samples,
            "batch_size": batch_size,
            "signals": bench.opts.signals,
        }
        for chunk in chunks
        if chunk
    ]
    svg = bench.results_dir / f"live-profile-{bench.stamp}-{label}.svg"
    async with ClientGroup(ClientProc(f"ingest client {i}", c) for i, c in enumerate(configs)) as g:
        await g.all("ready", 120)
        async with Profiler(bench.opts.profile, bench.server.pid, svg) as profiler:
            cpu = CpuWindow(bench.server.pid, g.pids)
            g.send("go")
            results = await g.all("result", 900)
            usage = cpu.stop()
    sent = sum(r["sent"] for r in results)
    accepted = sum(r["accepted"] for r in results)
    if accepted != sent:
        errors = sorted({e for r in results for e in r["errors"]})
        raise RuntimeError(f"{sent - accepted} of {sent} samples not accepted: {errors[:3]}")
    seconds = max(r["end"] for r in results) - min(r["start"] for r in results)
    return {
        "devices": len(tokens),
        "processes": len(configs),
        "batch_size": batch_size,
        "samples": accepted,
        "seconds": round(seconds, 3),
        "samples_per_s": round(accepted / seconds, 1),
        "reconnects": sum(r["connections"] for r in results) - len(tokens),
        "cpu": usage,
        "profile": str(svg) if profiler.enabled else None,
    }


async def one_device(bench: Bench) -> list[Row]:
    """One device at each batch size, then the best of them judged against the goal."""
    opts = bench.opts
    rows: list[Row] = []
    runs: list[dict[str, Any]] = []
    for size in opts.batch_sizes:
        case = f"ingest, 1 device, batch {size}"
        print(f"  {case}: {opts.one_samples} samples ...", flush=True)
        try:
            run = await run_ingest(
                bench, bench.fleet.tokens[:1], opts.one_samples, size, 1, f"one-{size}"
            )
        except Exception as err:
            rows.append(failed(case, err))
            continue
        runs.append(run)
        rows.append(_row(case, run, goal=None))
    if runs:
        best = max(runs, key=lambda r: r["samples_per_s"])
        rows.append(_row(f"ingest, 1 device, best (batch {best['batch_size']})", best, "one"))
    return rows


async def many_devices(bench: Bench) -> list[Row]:
    opts = bench.opts
    rows: list[Row] = []
    for count in opts.many_devices:
        procs = min(opts.client_procs, count)
        case = f"ingest, {count} devices ({procs} client procs)"
        each = max(1, opts.many_samples // count)
        print(f"  {case}: {each} samples each ...", flush=True)
        try:
            tokens = bench.fleet.tokens[:count]
            if len(tokens) < count:
                raise RuntimeError(f"only {len(tokens)} device tokens (see --connections)")
            run = await run_ingest(bench, tokens, each, 1000, procs, f"many-{count}")
        except Exception as err:
            rows.append(failed(case, err))
            continue
        rows.append(_row(case, run, "many"))
    return rows


def _row(case: str, run: dict[str, Any], goal: str | None) -> Row:
    rate = run["samples_per_s"]
    row = Row(
        case,
        measured=per_s(rate, "samples"),
        value=rate,
        cpu=run["cpu"],
        details=run,
        note=f"{run['samples']} samples in {run['seconds']:.1f} s, batch {run['batch_size']}"
        + (f", {run['reconnects']} reconnects" if run["reconnects"] else ""),
    )
    if goal is not None:
        row.goal, row.met = at_least(rate, GOALS[f"ingest_{goal}"], "/s")
        srv = run["cpu"]["server_cpu_pct"]
        row.anchor = (
            f"thesis edge API 500 msg/s (this is {rate / 500:.0f}x); ThingsBoard CE on 2 vCPU "
            f"1 000 msg/s at 27% CPU (this is {rate / 1000:.0f}x, at {srv:.0f}% server CPU)"
        )
    return row
