"""Health checks: a GET of the service's `health_path` (with its credentials), on request and
every `INTERVAL_S` for the services of twins in use."""

from __future__ import annotations

import asyncio
import contextlib
import time
from typing import Any, Protocol

from twinlink.gateway import paths, signin
from twinlink.gateway.credentials.base import RefreshError
from twinlink.gateway.table import Service
from twinlink.gateway.upstream import Pool, UpstreamError, request_head

INTERVAL_S = 30.0
CHECK_TIMEOUT_S = 5.0


class Gateway(Protocol):
    """What the checks use of the gateway's service (service.py, which starts the loop): a
    protocol, so this module does not import the one that imports it."""

    pool: Pool

    def cached(self) -> list[tuple[int, dict[str, Service]]]: ...


async def check(gateway: Gateway, service: Service) -> dict[str, Any]:
    """Check `service` now; the result is also kept for the list and /metrics."""
    started = time.perf_counter()
    result: dict[str, Any] = {"checked_at": time.time(), "path": service.settings.health_path}
    try:
        status = await _probe(gateway, service)
        result.update(status="up" if status < 400 else "down", http_status=status)
        if status >= 400:
            result["error"] = f"the health path answered {status}"
    except (UpstreamError, RefreshError) as err:
        result.update(status="down", http_status=None, error=str(err))
    result["ms"] = round((time.perf_counter() - started) * 1000, 2)
    service.stats.health = result
    return result


async def _probe(gateway: Gateway, service: Service) -> int:
    if service.blocked or service.origin is None:
        raise UpstreamError("connect", service.blocked or "no address")
    rest = (service.settings.health_path or "").lstrip("/").encode()
    for attempt in (0, 1):
        generation = await signin.ready(service.credentials)
        headers: list[tuple[bytes, bytes]] = [(b"host", service.host_header)]
        query: list[str] = []
        service.credentials.apply(headers, query)
        target = paths.target(service.base_path, rest, b"", query)
        conn, _ = await gateway.pool.connect(service.origin, CHECK_TIMEOUT_S)
        conn.begin(head_only=False)
        await conn.write(request_head("GET", target, headers))
        status, _ = await conn.head(CHECK_TIMEOUT_S)
        async for _chunk in conn.body(CHECK_TIMEOUT_S):
            pass
        gateway.pool.release(conn)
        if status == 401 and attempt == 0 and service.credentials.can_refresh:
            await signin.refresh(service.credentials, generation)
            continue
        return status
    return 401


class HealthLoop:
    def __init__(self, gateway: Gateway) -> None:
        self.gateway = gateway
        self._task: asyncio.Task[None] | None = None

    def start(self) -> None:
        self._task = asyncio.create_task(self._run(), name="gateway-health")

    async def stop(self) -> None:
        if self._task is not None:
            self._task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._task

    async def _run(self) -> None:
        while True:
            await asyncio.sleep(INTERVAL_S)
            self.gateway.pool.prune()
            services = [
                s
                for _, cached in list(self.gateway.cached())
                for s in cached.values()
                if s.settings.health_path is not None
            ]
            await asyncio.gather(*(check(self.gateway, s) for s in services))
