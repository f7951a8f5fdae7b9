"""The composition root: reads settings, picks implementations, wires services and routes."""

from __future__ import annotations

import logging
from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager
from dataclasses import dataclass

from fastapi import FastAPI

from twinlink import __version__
from twinlink.api import (
    apidocs,
    auth,
    device_ws,
    devices,
    pages,
    problems,
    search,
    system,
    twins,
)
from twinlink.auth.devices import DeviceService
from twinlink.auth.service import AuthService, Bootstrap
from twinlink.bus import Bus, MemoryBus
from twinlink.config import Settings
from twinlink.ingest.service import IngestService
from twinlink.ingest.sessions import DeviceHub
from twinlink.metrics import Metrics, MetricsMiddleware
from twinlink.registry.service import RegistryService
from twinlink.search import SearchService
from twinlink.store.base import MetadataStore
from twinlink.store.sqlite import SqliteStore
from twinlink.store.sqlite.history import SqliteHistory

log = logging.getLogger("twinlink.app")


@dataclass(slots=True)
class Services:
    store: MetadataStore
    auth: AuthService
    registry: RegistryService
    search: SearchService
    devices: DeviceService
    bus: Bus
    history: SqliteHistory
    ingest: IngestService
    device_hub: DeviceHub


def build_services(settings: Settings) -> Services:
    store: MetadataStore = SqliteStore(settings.data_dir)
    registry = RegistryService(store, settings.base_url)
    bus = MemoryBus()
    history = SqliteHistory(settings.data_dir, settings.history_sync)
    return Services(
        store=store,
        auth=AuthService(store, settings.session_ttl_s),
        registry=registry,
        search=SearchService(store),
        devices=DeviceService(store, registry),
        bus=bus,
        history=history,
        ingest=IngestService(registry, history, bus),
        device_hub=DeviceHub(),
    )


def create_app(
    settings: Settings,
    on_bootstrap: Callable[[Bootstrap], None] | None = None,
    on_ready: Callable[[Services], object] | None = None,
) -> FastAPI:
    services = build_services(settings)
    metrics = Metrics()

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        await services.store.open()
        await services.history.open()
        await services.bus.start()
        created = await services.auth.bootstrap(
            settings.admin_token.get_secret_value() if settings.admin_token else None,
            settings.admin_password.get_secret_value() if settings.admin_password else None,
        )
        if created is not None and on_bootstrap is not None:
            on_bootstrap(created)
        if on_ready is not None:
            result = on_ready(services)
            if hasattr(result, "__await__"):
                await result
        log.info("ready", extra={"event": "ready", "url": settings.base_url})
        try:
            yield
        finally:
            await services.bus.stop()
            await services.history.close()
            await services.store.close()

    app = FastAPI(
        title="twinlink",
        version=__version__,
        description="An open-source digital twin platform: DT documents, a twin registry with "
        "search, and (in later versions) live data, processors and an API gateway. "
        "Every endpoint needs `Authorization: Bearer <token>` except /healthz, login and "
        "public DT documents.",
        lifespan=lifespan,
        docs_url=None,
        redoc_url=None,
        openapi_url=None,  # served by api.apidocs, behind a token
    )
    app.state.settings = settings
    app.state.services = services
    app.state.metrics = metrics
    problems.install(app)
    for module in (system, auth, twins, devices, device_ws, search, pages):
        app.include_router(module.router)
    apidocs.install(app)
    app.add_middleware(MetricsMiddleware, metrics=metrics)
    return app
