"""What the processor benchmark runs against: its options, the Tingen FMU, and FMU processors
made, watched and deleted through the HTTP API as an operator would."""

from __future__ import annotations

import asyncio
import contextlib
import time
from collections.abc import AsyncIterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import psutil

from _live_fleet import Fleet, admin_client
from _load import _own_cpu
from _server import Twinlink

FMU_SOURCE = Path(__file__).resolve().parents[1] / "examples" / "tingen" / "fmu"
FMU_NAME = "Tingen.fmu"
START_TIMEOUT_S = 90.0  # eight workers importing numpy and FMPy at once on two cores


@dataclass
class ProcOptions:
    quick: bool
    cases: list[str]
    signals: int  # float signals in a device sample; the processor reads `force`
    reference_steps: int  # raw FMPy steps
    reference_batch: int  # samples per process() call of the blueprint alone
    throughput_samples: int
    batch_size: int  # SDK batch_size when pushing as fast as possible
    rates: list[int]
    latency_seconds: float
    flush_s: float  # SDK flush_interval of the paced device: a batch every 10 ms
    single_rate: int  # paced samples/s sent one sample a message (0: not run)
    processors: int  # processors on one stream in the multi-processor case
    many_rate: int
    many_seconds: float
    saturation_samples: int
    profile: bool  # py-spy the server's main process in the runs that push as fast as possible


@dataclass
class ProcBench:
    """What every case runs against. Each case takes twins of its own (`next_twin`), so the
    processors' figures (windows of their last 4 096 batches) hold that case alone."""

    server: Twinlink
    opts: ProcOptions
    fleet: Fleet
    fmu: Path  # the built FMU
    stamp: str  # of the run, for the names of flame graphs
    used: int = 0
    uploaded: set[str] = field(default_factory=set)

    @property
    def ws_url(self) -> str:
        return self.server.url.replace("http://", "ws://", 1)

    def next_twin(self) -> tuple[str, str]:
        """A twin no case has used yet, and its device token."""
        if self.used >= len(self.fleet):
            raise RuntimeError(f"all {len(self.fleet)} twins are used")
        self.used += 1
        return self.fleet.slugs[self.used - 1], self.fleet.tokens[self.used - 1]


def build_tingen(folder: Path) -> Path:
    """The Tingen cantilever FMU (FMI 2.0 co-simulation) compiled from examples/tingen/fmu."""
    from twinlink.processors.fmubuild import build_fmu

    folder.mkdir(parents=True, exist_ok=True)
    return build_fmu(FMU_SOURCE, folder / FMU_NAME)


def processor_body(name: str) -> dict[str, Any]:
    return {
        "name": name,
        "blueprint": "fmu",
        "source": "telemetry",
        "output": name,
        "inputs": {"F": {"signal": "force"}},
        "params": {"fmu": FMU_NAME, "outputs": ["theta", "sigma"]},
    }


async def _upload(bench: ProcBench, slug: str) -> None:
    if slug in bench.uploaded:
        return
    async with admin_client(bench.server) as admin:
        r = await admin.put(
            f"/api/v1/twins/{slug}/fmus/{FMU_NAME}",
            content=bench.fmu.read_bytes(),
            headers={"Content-Type": "application/octet-stream"},
        )
    if r.status_code != 201:
        raise RuntimeError(f"uploading the FMU failed: HTTP {r.status_code}: {r.text[:300]}")
    bench.uploaded.add(slug)


async def views(bench: ProcBench, slug: str, names: list[str]) -> list[dict[str, Any]]:
    """GET of each processor: state, pid and `stats`."""
    async with admin_client(bench.server) as admin:
        answers = await asyncio.gather(
            *(admin.get(f"/api/v1/twins/{slug}/processors/{n}") for n in names)
        )
    for r in answers:
        if r.status_code != 200:
            raise RuntimeError(f"GET processor: HTTP {r.status_code}: {r.text[:300]}")
    return [r.json() for r in answers]


async def _wait_running(bench: ProcBench, slug: str, names: list[str]) -> list[dict[str, Any]]:
    deadline = time.perf_counter() + START_TIMEOUT_S
    while True:
        seen = await views(bench, slug, names)
        if all(v["state"] == "running" for v in seen):
            return seen
        broken = [v for v in seen if v["last_error"]]
        if broken or time.perf_counter() > deadline:
            v = (broken or [p for p in seen if p["state"] != "running"])[0]
            raise RuntimeError(f"processor {v['name']} is {v['state']}: {v['last_error']}")
        await asyncio.sleep(0.1)


@contextlib.asynccontextmanager
async def fmu_processors(
    bench: ProcBench, slug: str, names: list[str]
) -> AsyncIterator[list[dict[str, Any]]]:
    """FMU processors `names` on the twin's telemetry, each writing the stream of its name,
    running when the block starts (their views are yielded) and deleted after it."""
    await _upload(bench, slug)
    try:
        async with admin_client(bench.server) as admin:
            for name in names:
                r = await admin.post(f"/api/v1/twins/{slug}/processors", json=processor_body(name))
                if r.status_code != 201:
                    raise RuntimeError(
                        f"creating processor {name}: HTTP {r.status_code}: {r.text[:300]}"
                    )
        yield await _wait_running(bench, slug, names)
    finally:
        if bench.server.alive():
            async with admin_client(bench.server) as admin:
                await asyncio.gather(
                    *(admin.delete(f"/api/v1/twins/{slug}/processors/{n}") for n in names),
                    return_exceptions=True,
                )


class WorkerCpu:
    """CPU seconds of the processors' worker processes (children of the server) from its
    creation to `stop()`, in % of one core."""

    def __init__(self, pids: list[int]) -> None:
        self.procs = [psutil.Process(p) for p in pids]
        self.t0 = time.perf_counter()
        self.cpu0 = self._cpu()

    def _cpu(self) -> float:
        total = 0.0
        for p in self.procs:
            with contextlib.suppress(psutil.NoSuchProcess):
                total += _own_cpu(p)
        return total

    def stop(self) -> float:
        wall = max(1e-9, time.perf_counter() - self.t0)
        return round(100 * (self._cpu() - self.cpu0) / wall, 1)


def stat_ms(view: dict[str, Any], key: str, q: str) -> float | None:
    """A percentile of the processor's `stats[key]` (seconds) in milliseconds."""
    value = (view.get("stats") or {}).get(key, {}).get(q)
    return None if value is None else round(value * 1e3, 6)
