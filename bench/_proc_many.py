"""Several FMU processors on one twin's telemetry, each writing its own stream: paced at
1 000 samples/s (the latency each adds, the worst of them), then saturated (as many samples as
fast as the device can push them, until every output stream has all of them)."""

from __future__ import annotations

from typing import Any

from _live_report import Row, per_s
from _proc_cases import counts, drive, paced_device, pushing_device
from _proc_setup import ProcBench, fmu_processors, views
from _proc_watch import Watcher, added, diverged


def _names(bench: ProcBench) -> list[str]:
    return [f"fmu{i}" for i in range(bench.opts.processors)]


async def many(bench: ProcBench) -> list[Row]:
    n, opts = bench.opts.processors, bench.opts
    print(
        f"  {n} processors at {per_s(opts.many_rate)} for {opts.many_seconds:g} s ...", flush=True
    )
    rows = [_paced_row(n, await _paced_run(bench))]
    print(
        f"  {n} processors, {opts.saturation_samples} samples as fast as possible ...", flush=True
    )
    rows.append(_saturated_row(n, await _saturated_run(bench)))
    return rows


async def _paced_run(bench: ProcBench) -> dict[str, Any]:
    opts, names = bench.opts, _names(bench)
    skip_s = min(1.0, opts.many_seconds / 4)
    slug, token = bench.next_twin()
    streams = ["telemetry", *names]
    async with fmu_processors(bench, slug, names) as started:
        async with Watcher(bench, slug, streams, keep=True) as watcher:
            device = paced_device(bench, token, opts.many_rate, opts.many_seconds, opts.flush_s)
            pids = [v["pid"] for v in started]
            run = await drive(bench, device, watcher, pids, streams)
        after = await views(bench, slug, names)
    telemetry = watcher.feeds["telemetry"]
    per = []
    for name, view in zip(names, after, strict=True):
        client = added(telemetry, watcher.feeds[name], skip_s)
        lag = diverged(client["first_ms"], client["last_ms"])
        per.append({"name": name, "client": client, "diverged": lag, **counts(view)})
    seconds = run["device"]["seconds"]
    return {
        "rate": opts.many_rate,
        "seconds": round(seconds, 3),
        "sent": run["device"]["sent"],
        "steps_per_s": round(sum(p["samples_out"] for p in per) / seconds, 1),
        "complete": run["complete"],
        "live_dropped": sum(f.dropped for f in watcher.feeds.values()),
        "processors": per,
        "cpu": run["cpu"],
    }


def _paced_row(n: int, run: dict[str, Any]) -> Row:
    per = run["processors"]
    server = max(per, key=lambda p: p["added_ms"]["p99"] or 0.0)
    client = max(per, key=lambda p: p["client"]["ms"]["p99"] or 0.0)
    dropped = sum(p["dropped"] for p in per)
    p50s = [p["added_ms"]["p50"] or 0.0 for p in per]
    lagging = [p["name"] for p in per if p["diverged"]]
    return Row(
        f"{n} processors at {per_s(run['rate'])}, worst p99",
        measured=f"server {server['added_ms']['p99']:.2f} / client "
        f"{client['client']['ms']['p99']:.2f} ms",
        value=server["added_ms"]["p99"],
        cpu=run["cpu"],
        details=run,
        note=f"{per_s(run['steps_per_s'], 'steps')} in all; server added p50 "
        f"{min(p50s):.2f}-{max(p50s):.2f} ms, worst p99 {server['name']}; client worst p99 "
        f"{client['name']} (p50 {client['client']['ms']['p50']:.2f} ms); "
        f"{'DIVERGED: ' + ', '.join(lagging) if lagging else 'stable'}; "
        f"workers {run['cpu']['workers_cpu_pct']:.0f}%"
        + (f"; DROPPED {dropped} in processors" if dropped else "")
        + (f"; {run['live_dropped']} dropped by the live queue" if run["live_dropped"] else ""),
    )


async def _saturated_run(bench: ProcBench) -> dict[str, Any]:
    samples, names = bench.opts.saturation_samples, _names(bench)
    slug, token = bench.next_twin()
    async with fmu_processors(bench, slug, names) as started:
        async with Watcher(bench, slug, names, keep=False) as watcher:
            device = pushing_device(bench, token, samples)
            pids = [v["pid"] for v in started]
            run = await drive(bench, device, watcher, pids, names, "saturated")
        after = await views(bench, slug, names)
    feeds = [watcher.feeds[n] for n in names]
    dev = run["device"]
    seconds = max(f.last_ns for f in feeds) / 1e9 - dev["start"]
    received = sum(f.samples for f in feeds)
    return {
        "samples": samples,
        "received": received,
        "seconds": round(seconds, 3),
        "steps_per_s": round(received / seconds, 1),
        "per_processor_s": [round(f.last_ns / 1e9 - dev["start"], 3) for f in feeds],
        "ingest_seconds": round(dev["end"] - dev["start"], 3),
        "live_dropped": sum(f.dropped for f in feeds),
        "processors": [{"name": n, **counts(v)} for n, v in zip(names, after, strict=True)],
        "cpu": run["cpu"],
        "profile": run["profile"],
    }


def _saturated_row(n: int, run: dict[str, Any]) -> Row:
    dropped = sum(p["dropped"] for p in run["processors"])
    steps = [p["step_ms"]["p50"] or 0.0 for p in run["processors"]]
    return Row(
        f"{n} processors, saturated",
        measured=per_s(run["steps_per_s"], "steps") + " in all",
        value=run["steps_per_s"],
        cpu=run["cpu"],
        details=run,
        note=f"{run['received']} of {n * run['samples']} outputs {run['seconds']:.2f} s after "
        f"the first add ({per_s(run['steps_per_s'] / n, 'steps')} each); the device's last ack "
        f"after {run['ingest_seconds']:.2f} s; step time p50 {min(steps) * 1e3:.1f}-"
        f"{max(steps) * 1e3:.1f} us; workers {run['cpu']['workers_cpu_pct']:.0f}%"
        + (f"; DROPPED {dropped} in processors" if dropped else "")
        + (f"; {run['live_dropped']} dropped by the live queue" if run["live_dropped"] else ""),
    )
