"""The twins and device tokens the live benchmark needs, made through the HTTP API as an
operator would: twins with POST /api/v1/apply, devices with POST /api/v1/twins/{slug}/devices
(concurrently: a thousand devices are a thousand requests)."""

from __future__ import annotations

import asyncio
import json
import time
from dataclasses import dataclass, field
from pathlib import Path

import httpx

from _server import Twinlink

APPLY_BATCH = 100  # twins per apply request
CONCURRENCY = 16  # device creations in flight


@dataclass
class Fleet:
    """Twins, each with one device, and the devices' tokens in the same order."""

    slugs: list[str] = field(default_factory=list)
    tokens: list[str] = field(default_factory=list)
    seconds: float = 0.0

    def __len__(self) -> int:
        return len(self.slugs)


def admin_client(server: Twinlink, timeout: float = 60) -> httpx.AsyncClient:
    headers = {"Authorization": f"Bearer {server.admin_token}"}
    return httpx.AsyncClient(base_url=server.url, headers=headers, timeout=timeout)


def twin_doc(slug: str, name: str) -> dict[str, object]:
    return {
        "version": "1.0",
        "privacy": "public",
        "id": f"urn:bench:{slug}",
        "slug": slug,
        "name": name,
        "description": "A twin the live benchmark streams to.",
    }


async def make_fleet(server: Twinlink, prefix: str, count: int) -> Fleet:
    """`count` twins `<prefix>-0000`... with one device `dev` each."""
    fleet = Fleet(slugs=[f"{prefix}-{i:04d}" for i in range(count)])
    start = time.perf_counter()
    async with admin_client(server) as admin:
        for i in range(0, count, APPLY_BATCH):
            docs = [twin_doc(s, f"Bench device {s}") for s in fleet.slugs[i : i + APPLY_BATCH]]
            r = await admin.post(
                "/api/v1/apply",
                content=json.dumps(docs).encode(),
                headers={"Content-Type": "application/json"},
            )
            if r.status_code != 200:
                raise RuntimeError(f"creating twins failed: HTTP {r.status_code}: {r.text[:500]}")
        fleet.tokens = await _create_devices(admin, fleet.slugs)
    fleet.seconds = time.perf_counter() - start
    return fleet


async def _create_devices(admin: httpx.AsyncClient, slugs: list[str]) -> list[str]:
    tokens: list[str] = [""] * len(slugs)
    queue = iter(range(len(slugs)))

    async def worker() -> None:
        for i in queue:
            r = await admin.post(f"/api/v1/twins/{slugs[i]}/devices", json={"name": "dev"})
            if r.status_code != 201:
                raise RuntimeError(
                    f"creating a device failed: HTTP {r.status_code}: {r.text[:500]}"
                )
            tokens[i] = r.json()["token"]

    await asyncio.gather(*(worker() for _ in range(min(CONCURRENCY, len(slugs)))))
    return tokens


@dataclass
class Options:
    quick: bool
    cases: list[str]
    signals: int  # float signals in a sample
    one_samples: int  # samples the single device sends, per batch size
    batch_sizes: list[int]
    many_devices: list[int]
    many_samples: int  # samples in all per many-device case
    client_procs: int
    rates: list[int]
    latency_seconds: float
    latency_flush_s: float
    command_requests: int
    command_seconds: float
    command_concurrency: int
    history_samples: int
    history_batch: int  # samples per stored block
    history_span_s: float
    history_requests: int
    connections: int
    steady_devices: int  # the steady fleet: devices sending one sample a batch
    steady_rate: float  # samples/s a device
    steady_seconds: float
    history_sync: str
    profile: bool


@dataclass
class Bench:
    """What every case runs against: the server, the options and the fleet of devices."""

    server: Twinlink
    opts: Options
    fleet: Fleet
    results_dir: Path
    stamp: str

    @property
    def ws_url(self) -> str:
        return self.server.url.replace("http://", "ws://", 1)
