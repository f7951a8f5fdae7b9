"""The measurements of the cluster benchmark, for one setup (embedded, single, cluster):

- **throughput**: the devices post batches over HTTP for `seconds` (`_cluster_client.py`, in
  client processes of their own), then every twin's stored sample count is compared with
  what its device had acknowledged (read through the API, so the same check for every
  backend; polled until it matches or a deadline passes, which also shows any lag between
  the ack and the count);
- **live delay**: a paced SDK device at 1 000 samples/s on one node, a live subscriber on the
  other (`_live_client.py` modes `paced` and `subscribe`); per sample, arrival - sample time;
- **commands**: an SDK device answering `ping` on one node, `POST .../commands` with `wait`
  on the other, one at a time; per command, the round trip.

In the embedded and single setups "one node" and "the other" are the same server: the
reference for what crossing nodes adds.
"""

from __future__ import annotations

import asyncio
import contextlib
import sys
import time
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import httpx
import orjson
import psutil

from _cluster_infra import Setup
from _cluster_profile import NodeProfile
from _live_http import closed_loop
from _live_procs import ClientGroup, ClientProc
from _load import _busy_cpu, _own_cpu, _tree_cpu

LOAD_CLIENT = Path(__file__).resolve().parent / "_cluster_client.py"
COUNT_DEADLINE_S = 120.0  # for the stored counts to reach the acknowledged ones
SETTLE_S = 5.0  # after the paced device's last ack, for its samples to reach the subscriber


@dataclass
class Plan:
    seconds: float
    devices: int
    batch_size: int
    signals: int
    client_procs: int
    live_rate: int
    live_seconds: float
    live_flush_s: float  # the paced device's SDK flush_interval
    commands: int  # most sequential commands
    command_seconds: float
    profile_s: float  # 0: no profile


class LoadClient(ClientProc):
    """A `_cluster_client.py` process (ClientProc runs `_live_client.py`)."""

    async def start(self) -> None:
        self.proc = await asyncio.create_subprocess_exec(
            sys.executable, str(LOAD_CLIENT),
            stdin=asyncio.subprocess.PIPE, stdout=asyncio.subprocess.PIPE,
            stderr=asyncio.subprocess.PIPE, limit=2**24,
        )  # fmt: skip
        self._drain = asyncio.create_task(self._keep_stderr())
        self.send(self.config)


class Cpu:
    """CPU seconds of each component (a process and its children) and of the clients over a
    window, in % of one core; `other` is the rest of the machine."""

    def __init__(self, components: dict[str, int], clients: list[int], here: bool = False):
        self.procs = {name: psutil.Process(pid) for name, pid in components.items()}
        self.clients = [psutil.Process(p) for p in clients]
        self.me = psutil.Process() if here else None
        self.t0 = time.perf_counter()
        self.start = {name: _tree_cpu(p) for name, p in self.procs.items()}
        self.cli0 = self._clients()
        self.busy0 = _busy_cpu()
        self.last_cli = self.cli0

    def _clients(self) -> float:
        total = _own_cpu(self.me) if self.me is not None else 0.0
        for p in self.clients:
            with contextlib.suppress(psutil.NoSuchProcess):
                total += _tree_cpu(p)
        return total

    def sample_clients(self) -> None:
        """Before client processes exit: what they used so far."""
        self.last_cli = self._clients()

    def stop(self) -> dict[str, float]:
        wall = max(1e-9, time.perf_counter() - self.t0)
        used = {name: _tree_cpu(p) - self.start[name] for name, p in self.procs.items()}
        cli = max(self.last_cli, self._clients()) - self.cli0
        busy = _busy_cpu() - self.busy0
        pct = {f"{name}_cpu_pct": round(100 * s / wall, 1) for name, s in used.items()}
        pct["clients_cpu_pct"] = round(100 * cli / wall, 1)
        pct["other_cpu_pct"] = round(max(0.0, 100 * (busy - sum(used.values()) - cli) / wall), 1)
        return {"seconds": round(wall, 2), **pct}


# --- throughput and nothing lost ------------------------------------------------------------


async def throughput(
    setup: Setup, slugs: list[str], tokens: list[str], plan: Plan, profile_path: Path
) -> dict[str, Any]:
    procs = min(plan.client_procs, len(tokens))
    clients = [
        LoadClient(
            f"load client {i}",
            {
                "url": setup.entry,
                "tokens": tokens[i::procs],
                "batch_size": plan.batch_size,
                "seconds": plan.seconds,
                "signals": plan.signals,
            },
        )
        for i in range(procs)
    ]
    profile = NodeProfile(
        setup.nodes[0].pid,
        profile_path,
        plan.profile_s,
        max(0.0, plan.seconds / 2 - plan.profile_s / 2),
    )
    async with ClientGroup(clients) as group:
        ready = await group.all("ready", 180)
        cpu = Cpu(setup.pids(), group.pids)
        group.send("go")
        if plan.profile_s:
            profile.start()
        results = await group.all("result", plan.seconds + 600)
        cpu.sample_clients()
        usage = cpu.stop()
    acked = {t: n for r in results for t, n in zip(r["tokens"], r["acked"], strict=True)}
    run = _merge(results, plan)
    run["cpu"] = usage
    run["warmup_errors"] = [r["warmup_errors"] for r in ready if r["warmup_errors"]]
    run["stored"] = await stored_matches(setup, slugs, [acked[t] for t in tokens])
    run["profile"] = await profile.summary() if plan.profile_s else {"status": "off"}
    return run


def _merge(results: list[dict[str, Any]], plan: Plan) -> dict[str, Any]:
    """Samples acknowledged after `go` (not the warm-up batch), per second and in all."""
    per_second: dict[int, int] = {}
    nodes: dict[str, int] = {}
    for r in results:
        for second, n in r["per_second"]:
            per_second[second] = per_second.get(second, 0) + n
        for node, n in r["nodes"].items():
            nodes[node] = nodes.get(node, 0) + n
    whole = [per_second.get(s, 0) for s in range(int(plan.seconds))]  # full seconds only
    total = sum(per_second.values())
    seconds = max(r["end"] for r in results) - min(r["start"] for r in results)
    worst = max(r["ack_ms"]["p99"] or 0 for r in results)
    return {
        "samples": total,
        "seconds": round(seconds, 2),
        "samples_per_s": round(total / seconds),
        "worst_second": min(whole) if whole else 0,
        "best_second": max(whole) if whole else 0,
        "per_second": whole,
        "batches": sum(r["batches"] for r in results),
        "ack_ms_p50": max(r["ack_ms"]["p50"] or 0 for r in results),  # the slower process
        "ack_ms_p99": worst,
        "nodes": nodes,
        "resent": sum(r["resent"] for r in results),
        "duplicates": sum(r["duplicates"] for r in results),
        "errors": dict(sum((Counter(r["errors"]) for r in results), Counter())),
    }


async def stored_matches(setup: Setup, slugs: list[str], acked: list[int]) -> dict[str, Any]:
    """Poll every twin's stored sample count (GET /api/v1/twins/{slug}/streams, on the first
    node) until each equals what its device had acknowledged, or the deadline passes."""
    node = setup.nodes[0]
    t0 = time.perf_counter()
    headers = {"Authorization": f"Bearer {node.admin_token}"}
    async with httpx.AsyncClient(base_url=node.url, headers=headers, timeout=60) as client:
        while True:
            counts = await asyncio.gather(*(_count(client, s) for s in slugs))
            lost = sum(max(0, a - c) for a, c in zip(acked, counts, strict=True))
            extra = sum(max(0, c - a) for a, c in zip(acked, counts, strict=True))
            if (lost == 0 and extra == 0) or time.perf_counter() - t0 > COUNT_DEADLINE_S:
                break
            await asyncio.sleep(0.5)  # polling the real counts, with a deadline
    return {
        "acknowledged": sum(acked),
        "stored": sum(counts),
        "lost": lost,
        "extra": extra,
        "devices_short": sum(c < a for a, c in zip(acked, counts, strict=True)),
        "matched_after_s": round(time.perf_counter() - t0, 1),
    }


async def _count(client: httpx.AsyncClient, slug: str) -> int:
    answer = await client.get(f"/api/v1/twins/{slug}/streams")
    answer.raise_for_status()
    streams = {s["name"]: s for s in answer.json()["streams"]}
    samples = streams.get("telemetry", {}).get("samples")
    if samples is None and "telemetry" in streams:
        raise RuntimeError(f"{slug}: the store gave no sample count ({streams['telemetry']})")
    return int(samples or 0)


# --- across nodes ---------------------------------------------------------------------------


async def live_delay(setup: Setup, slug: str, token: str, plan: Plan) -> dict[str, Any]:
    """A paced device on the last node, a subscriber on the first."""
    watch, send = setup.nodes[0], setup.nodes[-1]
    skip_s = min(1.0, plan.live_seconds / 4)
    subscriber = ClientProc(
        "subscriber",
        {"mode": "subscribe", "live_url": watch.url.replace("http", "ws", 1) + "/api/v1/live",
         "token": watch.admin_token, "twin": slug, "skip_s": skip_s},
    )  # fmt: skip
    device = ClientProc(
        "paced device",
        {"mode": "paced", "url": send.url, "token": token, "rate": plan.live_rate,
         "seconds": plan.live_seconds, "flush_interval": plan.live_flush_s, "batch_size": 1000,
         "signals": plan.signals},
    )  # fmt: skip
    async with ClientGroup([subscriber, device]) as group:
        await group.all("ready", 60)
        cpu = Cpu(setup.pids(), group.pids)
        device.send({"op": "go"})
        sent = await device.event("result", plan.live_seconds + 120)
        cpu.sample_clients()
        got = await _until_received(subscriber, sent["accepted"], skip_s, plan)
        usage = cpu.stop()
    return {"sent": sent["sent"], "accepted": sent["accepted"], **got, "cpu": usage}


async def _until_received(
    subscriber: ClientProc, accepted: int, skip_s: float, plan: Plan
) -> dict[str, Any]:
    """The subscriber's figures once the device's last samples had time to cross (the
    subscriber counts only what came after its skip). It reports only when stopped: what had
    not arrived SETTLE_S after the device's last ack is counted as `missing_about`, and the
    percentiles leave it out (the table says so)."""
    await asyncio.sleep(SETTLE_S)
    subscriber.send({"op": "stop"})
    got = await subscriber.event("result", 30)
    expected = accepted - int(skip_s * plan.live_rate)
    got["missing_about"] = max(0, expected - got["samples"])
    return got


async def command_round_trips(setup: Setup, slug: str, token: str, plan: Plan) -> dict[str, Any]:
    """A device answering `ping` on the last node, commands posted one at a time on the
    first (warm-up of 20 not counted)."""
    post, hold = setup.nodes[0], setup.nodes[-1]
    device = ClientProc(
        "command device", {"mode": "command_device", "url": hold.url, "token": token}
    )
    headers = {"Authorization": f"Bearer {post.admin_token}", "Content-Type": "application/json"}
    path = f"/api/v1/twins/{slug}/commands"

    def make(i: int) -> tuple[str, str, bytes]:
        return "POST", path, orjson.dumps({"name": "ping", "args": {"n": i}, "wait": True})

    def check(status: int, body: bytes) -> str | None:
        state = orjson.loads(body).get("state") if status == 200 else None
        return None if state == "succeeded" else f"HTTP {status}: {body[:300]!r}"

    async with ClientGroup([device]) as group:
        await group.all("ready", 60)
        cpu = Cpu(setup.pids(), group.pids, here=True)
        result = await closed_loop(
            post.url, headers, make, check, 1, plan.commands, plan.command_seconds, warmup=20
        )
        cpu.sample_clients()
        usage = cpu.stop()
        device.send({"op": "stop"})
        answered = (await device.event("result", 30))["answered"]
    return {**result.summary(), "device_answered": answered, "cpu": usage}
