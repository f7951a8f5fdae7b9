"""One FMU processor through the platform: throughput with a device pushing as fast as it can,
and the latency the processor adds at paced input rates.

The device is an SDK AsyncDevice in a client process of its own (_live_client.py `ingest` and
`paced` modes); the subscribers are in this process (_proc_watch.py). Each run has a twin and
a processor of its own, deleted afterwards."""

from __future__ import annotations

import asyncio
from typing import Any

from _live_procs import ClientGroup, ClientProc, CpuWindow, Profiler
from _live_report import Row, at_least, at_most, per_s, relative
from _proc_report import GOALS
from _proc_setup import ProcBench, WorkerCpu, fmu_processors, stat_ms, views
from _proc_watch import Watcher, added, diverged
from _report import RESULTS

DEVICE_TIMEOUT_S = 600.0
SAMPLE_S = 0.05


def pushing_device(bench: ProcBench, token: str, samples: int) -> ClientProc:
    """Adds `samples` samples as fast as the SDK takes them (batch_size, 16 in flight)."""
    opts = bench.opts
    config = {
        "mode": "ingest",
        "url": bench.server.url,
        "tokens": [token],
        "samples": samples,
        "batch_size": opts.batch_size,
        "signals": opts.signals,
    }
    return ClientProc("pushing device", config)


def paced_device(
    bench: ProcBench, token: str, rate: int, seconds: float, flush_s: float
) -> ClientProc:
    """Adds `rate` samples a second; the SDK sends what waited every `flush_s` (0: each
    sample as soon as it is added, one sample a message)."""
    opts = bench.opts
    config = {
        "mode": "paced",
        "url": bench.server.url,
        "token": token,
        "rate": rate,
        "seconds": seconds,
        "flush_interval": flush_s,
        "batch_size": 1000,
        "signals": opts.signals,
    }
    return ClientProc("paced device", config)


async def drive(
    bench: ProcBench,
    device: ClientProc,
    watcher: Watcher,
    pids: list[int],
    streams: list[str],
    profile: str = "",
) -> dict[str, Any]:
    """Start the device, wait for its result and then for every sample it sent to arrive on
    `streams`; the device's result, whether all arrived, and the CPU used (the server's main
    process apart from its processor workers `pids`). With --profile and a `profile` label,
    py-spy records the server's main process meanwhile."""
    svg = RESULTS / f"processors-profile-{bench.stamp}-{profile}.svg"
    async with ClientGroup([device]) as group:
        await group.all("ready", 60)
        async with Profiler(bench.opts.profile and bool(profile), bench.server.pid, svg) as spy:
            cpu = CpuWindow(bench.server.pid, group.pids, here=True)
            workers = WorkerCpu(pids)
            sampler = asyncio.create_task(_sample(cpu))
            device.send({"op": "go"})
            try:
                result = await device.event("result", DEVICE_TIMEOUT_S)
            finally:
                sampler.cancel()
            complete = await watcher.wait_for(result["sent"], streams)
            worker_pct = workers.stop()
            usage = cpu.stop()
    usage["server_cpu_pct"] = round(usage["server_cpu_pct"] - worker_pct, 1)
    usage["workers_cpu_pct"] = worker_pct
    flame = relative(svg) if spy.enabled else None
    return {"device": result, "complete": complete, "cpu": usage, "profile": flame}


async def _sample(cpu: CpuWindow) -> None:
    """Read the client processes' CPU while they run: the device exits soon after its result,
    and a process gone before the last reading would count as other work."""
    while True:
        cpu.sample()
        await asyncio.sleep(SAMPLE_S)


def counts(view: dict[str, Any]) -> dict[str, Any]:
    stats = view["stats"]
    keys = ("samples_in", "samples_out", "batches", "dropped", "restarts", "rss_bytes")
    return {k: stats[k] for k in keys} | {
        "step_ms": {q: stat_ms(view, "step_time_s", q) for q in ("p50", "p99")},
        "added_ms": {q: stat_ms(view, "added_latency_s", q) for q in ("p50", "p99")},
    }


# --- throughput -----------------------------------------------------------------------------


async def throughput(bench: ProcBench) -> list[Row]:
    samples = bench.opts.throughput_samples
    print(f"  one processor, {samples} samples as fast as possible ...", flush=True)
    slug, token = bench.next_twin()
    async with fmu_processors(bench, slug, ["fmu"]) as [view]:
        async with Watcher(bench, slug, ["fmu"], keep=False) as watcher:
            device = pushing_device(bench, token, samples)
            run = await drive(bench, device, watcher, [view["pid"]], ["fmu"], "throughput")
        [after] = await views(bench, slug, ["fmu"])
    feed, dev = watcher.feeds["fmu"], run["device"]
    seconds = feed.last_ns / 1e9 - dev["start"]
    rate = feed.samples / seconds
    stats = counts(after)
    details = {
        "samples": samples,
        "received": feed.samples,
        "seconds": round(seconds, 3),
        "steps_per_s": round(rate, 1),
        "ingest_seconds": round(dev["end"] - dev["start"], 3),
        "live_dropped": feed.dropped,
        "processor": stats,
        "cpu": run["cpu"],
        "profile": run["profile"],
    }
    row = Row(
        "FMU processor throughput, end to end",
        measured=per_s(rate, "steps"),
        value=rate,
        cpu=run["cpu"],
        details=details,
    )
    row.goal, met = at_least(rate, GOALS["steps_per_s"], "steps/s")
    row.met = met and feed.samples == samples
    row.note = (
        f"{feed.samples} of {samples} outputs at the subscriber {seconds:.2f} s after the first "
        f"add (batch {bench.opts.batch_size}); the device's last ack after "
        f"{details['ingest_seconds']:.2f} s; workers {run['cpu']['workers_cpu_pct']:.0f}%"
        + _lost(stats["dropped"], feed.dropped)
    )
    return [row, _step_row(stats)]


def _lost(dropped: int, live_dropped: int) -> str:
    text = f"; processor DROPPED {dropped}" if dropped else ""
    return text + (f"; live subscriber DROPPED {live_dropped}" if live_dropped else "")


def _step_row(stats: dict[str, Any]) -> Row:
    p50, p99 = stats["step_ms"]["p50"], stats["step_ms"]["p99"]
    implied = 1e3 / p50 if p50 else 0.0
    return Row(
        "server step time (same run)",
        measured=f"p50 {p50 * 1e3:.2f} / p99 {p99 * 1e3:.2f} us",
        value=implied,
        details={"step_ms": stats["step_ms"], "implied_steps_per_s": round(implied, 1)},
        note=f"blueprint time per input sample (stats.step_time_s over {stats['batches']} "
        f"batches): {per_s(implied, 'steps')} implied for process() alone",
    )


# --- latency --------------------------------------------------------------------------------


async def latency(bench: ProcBench) -> list[Row]:
    """The paced rates in 10 ms batches, then one sample a message (the thesis's messages)."""
    opts = bench.opts
    runs = [(rate, opts.flush_s) for rate in opts.rates]
    runs += [(opts.single_rate, 0.0)] if opts.single_rate else []
    rows = []
    for rate, flush_s in runs:
        case = f"added latency at {per_s(rate)}" + ("" if flush_s else ", 1 sample a message")
        print(f"  {case} for {opts.latency_seconds:g} s ...", flush=True)
        rows.append(_latency_row(case, await _latency_run(bench, rate, flush_s)))
    return rows


async def _latency_run(bench: ProcBench, rate: int, flush_s: float) -> dict[str, Any]:
    seconds = bench.opts.latency_seconds
    skip_s = min(1.0, seconds / 4)  # the first batches through a new worker: not counted
    slug, token = bench.next_twin()
    streams = ["telemetry", "fmu"]
    async with fmu_processors(bench, slug, ["fmu"]) as [view]:
        async with Watcher(bench, slug, streams, keep=True) as watcher:
            device = paced_device(bench, token, rate, seconds, flush_s)
            run = await drive(bench, device, watcher, [view["pid"]], streams)
        [after] = await views(bench, slug, ["fmu"])
    feeds = watcher.feeds
    client = added(feeds["telemetry"], feeds["fmu"], skip_s)
    return {
        "rate": rate,
        "flush_s": flush_s,
        "seconds": seconds,
        "skip_s": skip_s,
        "sent": run["device"]["sent"],
        "received": feeds["fmu"].samples,
        "messages": feeds["telemetry"].messages,
        "messages_per_s": round(feeds["telemetry"].messages / run["device"]["seconds"], 1),
        "live_dropped": feeds["fmu"].dropped + feeds["telemetry"].dropped,
        "client": client,
        "processor": counts(after),
        "cpu": run["cpu"],
        "diverged": diverged(client["first_ms"], client["last_ms"]),
    }


def _latency_row(case: str, run: dict[str, Any]) -> Row:
    client, proc = run["client"], run["processor"]
    ms, server = client["ms"], proc["added_ms"]
    trend = "DIVERGED" if run["diverged"] else "stable"
    row = Row(
        case,
        measured=f"p50 {ms['p50']:.2f} / p99 {ms['p99']:.2f} ms",
        value=ms["p99"],
        cpu=run["cpu"],
        details=run,
        note=f"server (bus in -> bus out) p50 {server['p50']:.2f} / p99 {server['p99']:.2f} ms; "
        f"{trend}: first 10% p50 {client['first_ms']:.2f} ms, last 10% {client['last_ms']:.2f}"
        f" ms; {run['received']} of {run['sent']} outputs; {run['messages']} input messages "
        f"({per_s(run['messages_per_s'])}); "
        f"workers {run['cpu']['workers_cpu_pct']:.0f}%"
        + _lost(proc["dropped"], run["live_dropped"]),
    )
    if run["rate"] == 1000 and run["flush_s"]:
        row.goal, row.met = at_most(ms["p99"], GOALS["latency_p99_ms"], "ms p99")
    return row
