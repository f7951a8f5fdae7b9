"""The composition root: reads settings, picks implementations, wires services and routes."""

from __future__ import annotations

import gc
import logging
from collections.abc import AsyncIterator, Awaitable, Callable
from contextlib import AbstractAsyncContextManager, asynccontextmanager
from dataclasses import dataclass
from typing import Any

from fastapi import FastAPI

from twinlink import __version__
from twinlink.api import (
    apidocs,
    app_ui,
    auth,
    commands,
    device_ws,
    devices,
    exports,
    live,
    pages,
    problems,
    processors,
    properties,
    remote,
    search,
    system,
    twins,
)
from twinlink.api import connectors as connectors_api
from twinlink.api import cosims as cosims_api
from twinlink.api import deployments as deployments_api
from twinlink.api import federation as federation_api
from twinlink.api import gateway as gateway_api
from twinlink.api import history as history_api
from twinlink.api import library as library_api
from twinlink.api import mqtt as mqtt_api
from twinlink.api import runs as runs_api
from twinlink.api import workspaces as workspaces_api
from twinlink.api.readiness import Readiness
from twinlink.auth.last_used import LastUsed
from twinlink.auth.service import AuthService, Bootstrap
from twinlink.auth.vault import Vault
from twinlink.backends import Shared, Storage, pick_bus, pick_storage
from twinlink.bus import Bus
from twinlink.cluster import CacheSync
from twinlink.commands import CommandService, PropertyService
from twinlink.config import Settings
from twinlink.connectors.metrics import ConnectorCollector
from twinlink.connectors.service import ConnectorService
from twinlink.cosim.service import CosimService, CosimSettings
from twinlink.deploy.apply import Parts
from twinlink.deploy.runs import RunService
from twinlink.deploy.service import DeploymentService
from twinlink.federation.service import Federation
from twinlink.gateway.metrics import GatewayCollector
from twinlink.gateway.proxy import GatewayApp
from twinlink.gateway.service import GatewayService
from twinlink.history.maintenance import HistoryMaintenance
from twinlink.history.service import HistoryService
from twinlink.ingest.mqtt import MqttService
from twinlink.ingest.mqtt.metrics import MqttCollector
from twinlink.ingest.service import IngestService
from twinlink.ingest.sessions import DeviceHub
from twinlink.library.service import LibraryService
from twinlink.live import LiveHub
from twinlink.metrics import DataPlaneCollector, Metrics, MetricsMiddleware
from twinlink.processors.fmus import FmuService, inspect_upload
from twinlink.processors.metrics import ProcessorCollector
from twinlink.processors.service import ProcessorService
from twinlink.registry.devices import DeviceService
from twinlink.registry.service import RegistryService
from twinlink.search import SearchService
from twinlink.store.base import MetadataStore
from twinlink.store.commands import CommandStore, PropertyStore
from twinlink.store.history import HistoryStore
from twinlink.workspaces.library import materializer
from twinlink.workspaces.proxy import WorkspaceProxy
from twinlink.workspaces.service import WorkspaceService, WorkspaceSettings

log = logging.getLogger("twinlink.app")

# The collector's young generation at 10 000 objects instead of 700, and a full collection
# after 100 middle ones instead of 10: a server with thousands of device connections holds
# hundreds of thousands of objects, and with Python's defaults their scans took a third of
# the event loop under 4 000 small batches a second, growing with the backlog they caused
# (bench/live.py, steady fleet; docs/decisions/0010-gc-and-small-batches.md).
GC_THRESHOLDS = (10_000, 10, 100)


@dataclass(slots=True)
class Services:
    store: MetadataStore
    auth: AuthService
    registry: RegistryService
    search: SearchService
    devices: DeviceService
    bus: Bus
    history: HistoryStore
    command_store: CommandStore
    property_store: PropertyStore
    storage_figures: Callable[[], dict[str, int]]
    storage_shared: Shared | None
    ingest: IngestService
    device_hub: DeviceHub
    commands: CommandService
    properties: PropertyService
    live: LiveHub
    history_service: HistoryService
    history_maintenance: HistoryMaintenance
    processors: ProcessorService
    fmus: FmuService
    gateway: GatewayService
    connectors: ConnectorService
    mqtt: MqttService
    # Tells the other nodes of changes to what their caches hold (on a shared bus only).
    cache_sync: CacheSync | None = None
    library: LibraryService | None = None
    deployments: DeploymentService | None = None  # twin packages deployed (deploy/)
    workspaces: WorkspaceService | None = None  # each user's JupyterLab (workspaces/)
    runs: RunService | None = None  # deployments' lifecycle runs (deploy/runs.py)
    cosims: CosimService | None = None  # co-simulations made through the API (cosim/)
    federation: Federation | None = None  # other instances' twins (federation/)


def build_services(settings: Settings) -> Services:
    stores = pick_storage(settings)
    store, history = stores.metadata, stores.history
    registry = RegistryService(store, settings.base_url)
    bus = pick_bus(settings)
    hub = DeviceHub()
    maintenance = HistoryMaintenance(history, settings.history_retention_days)
    registry.deleted_listeners.append(maintenance.twins_deleted)
    ingest = IngestService(registry, history, bus)
    # On a shared bus, commands reach devices connected to other nodes (commands/relay.py).
    relay_bus = bus if settings.bus_url else None
    commands = CommandService(registry, stores.commands, hub, settings.command_timeout_s, relay_bus)
    vault = Vault.configured(settings)
    gateway = GatewayService(store, registry, vault, settings.gateway_default_twin,
                             settings.gateway_audit_days, stores.tokens)  # fmt: skip
    last_used = LastUsed(store)  # of tokens and devices, written behind the requests
    devices = DeviceService(store, registry, last_used, settings.device_token_recheck_s)
    auth = AuthService(store, settings.session_ttl_s, last_used)
    shared_bus = bool(settings.bus_url)  # other nodes may share the store: tell them of changes
    services = Services(
        store=store,
        auth=auth,
        registry=registry,
        search=SearchService(store),
        devices=devices,
        bus=bus,
        history=history,
        command_store=stores.commands,
        property_store=stores.properties,
        storage_figures=stores.figures,
        storage_shared=stores.shared,
        ingest=ingest,
        device_hub=hub,
        commands=commands,
        properties=PropertyService(registry, stores.properties, hub, relay_bus),
        live=LiveHub(bus),
        history_service=HistoryService(registry, history),
        history_maintenance=maintenance,
        processors=_processor_service(settings, stores, registry, bus, ingest, commands),
        fmus=FmuService(
            store, registry, settings.data_dir, settings.fmu_max_mb * 2**20, settings.fmu_uploaders
        ),
        gateway=gateway,
        connectors=ConnectorService(
            store, registry, devices, hub, ingest, vault, stores.claims("connector")
        ),
        mqtt=MqttService(settings, devices, hub, ingest, stores.claims("mqtt-broker")),
        cache_sync=CacheSync(bus, registry, auth, gateway) if shared_bus else None,
        library=LibraryService.configured(settings, store, inspect_upload),
    )
    services.processors.lib.library = services.library  # for `fmu: lib:...` (libref.py)
    services.search.library = services.library  # assets are found beside twins
    _add_dtaas_services(settings, services, vault, stores.holder)
    services.federation = Federation.configured(settings, store, vault)
    return services


def _add_dtaas_services(settings: Settings, services: Services, vault: Vault, node: str) -> None:
    """Deployments, their lifecycle runs, workspaces and co-simulations, on the rest."""
    shared = services.storage_shared is not None  # other nodes share the store (PostgreSQL)
    services.deployments = _deployment_service(settings, services, vault)
    services.runs = RunService.configured(settings, services.store, services.auth, node, shared)
    services.runs.serve(services.deployments)
    services.workspaces = _workspace_service(settings, services)
    config = CosimSettings.of(settings, node, shared)
    services.cosims = CosimService(services.store, services.registry, services.ingest,
                                   services.fmus, services.library, config)  # fmt: skip


def _deployment_service(settings: Settings, services: Services, vault: Vault) -> DeploymentService:
    parts = Parts(services.registry, services.devices, services.gateway, services.processors,
                  services.connectors, vault.fingerprint)  # fmt: skip
    # The lifecycle runs are set on it by RunService.serve, once both exist.
    shared = services.storage_shared is not None  # other nodes may be applying (PostgreSQL)
    return DeploymentService(services.store, parts, services.library, vault, settings.base_url,
                             shared_store=shared)  # fmt: skip


def _processor_service(
    settings: Settings,
    stores: Storage,
    registry: RegistryService,
    bus: Bus,
    ingest: IngestService,
    commands: CommandService,
) -> ProcessorService:
    return ProcessorService(
        stores.metadata,
        registry,
        bus,
        ingest,
        commands,
        settings.data_dir,
        settings.blueprints_dir,
        settings.max_processors,
        stores.claims("processor"),
        stores.history,  # a processor starting on a shared store catches up from it
        env_build_timeout_s=settings.fmu_env_build_timeout_s,
    )


def _workspace_service(settings: Settings, services: Services) -> WorkspaceService:
    fill = materializer(services.library) if services.library is not None else None
    config, shared = WorkspaceSettings.of(settings), services.storage_shared is not None
    return WorkspaceService(config, services.auth, fill, shared_store=shared)


def data_plane_figures(services: Services) -> dict[str, Any]:
    return {
        "samples_accepted": services.ingest.samples_accepted,
        "samples_rejected": services.ingest.samples_rejected,
        "batches_duplicate": services.ingest.batches_duplicate,
        **services.storage_figures(),
        "outputs_not_stored": services.ingest.outputs_not_stored,
        "devices_connected": len(services.device_hub.sessions),
    }


async def start_services(services: Services, settings: Settings) -> Bootstrap | None:
    """Open the stores and start the background work; the first admin if one was made. When a
    step fails (a broker that refuses, a port in use), what the steps before it started is
    stopped, in reverse order, and its error raised: a failed start leaves nothing running
    (a step that fails stops what it started itself)."""
    started: list[Callable[[], Awaitable[object]]] = []  # how to stop each, in start order
    try:
        if services.storage_shared is not None:  # PostgreSQL's pool, migrated, first
            await services.storage_shared.open()
            started.append(services.storage_shared.close)
        await services.store.open()
        started.append(services.store.close)
        services.auth.last_used.start()
        started.append(services.auth.last_used.close)
        await services.history.open()
        started.append(services.history.close)
        await services.command_store.open()
        started.append(services.command_store.close)
        await services.property_store.open()
        started.append(services.property_store.close)
        await services.commands.open()
        started += [services.commands.close, services.properties.close]
        await services.bus.start()
        started.append(services.bus.stop)
        if services.cache_sync is not None:
            services.cache_sync.start()
            started.append(services.cache_sync.stop)
        await services.history_maintenance.sweep_orphans(await services.store.twin_ids())
        services.history_maintenance.start()
        started.append(services.history_maintenance.stop)
        await services.processors.open()
        started.append(services.processors.close)
        await services.gateway.open()
        started.append(services.gateway.close)
        await services.connectors.open()
        started.append(services.connectors.close)
        await services.mqtt.open()
        started.append(services.mqtt.close)
        if services.runs is not None:  # runs a stop cut off are failed, their tokens revoked
            await services.runs.open()
            started.append(services.runs.close)
        if services.deployments is not None:  # creates a crash cut off are undone
            await services.deployments.open()
        if services.workspaces is not None:  # tokens a crash left are revoked
            await services.workspaces.open()
            started.append(services.workspaces.close)
        if services.cosims is not None:  # runs a stop cut off are failed
            await services.cosims.open()
            started.append(services.cosims.close)
        return await services.auth.bootstrap(
            settings.admin_token.get_secret_value() if settings.admin_token else None,
            settings.admin_password.get_secret_value() if settings.admin_password else None,
        )
    except BaseException:
        await _stop_started(started)
        raise


async def _stop_started(started: list[Callable[[], Awaitable[object]]]) -> None:
    """Stop what a failed start started, last first. An error stopping one is logged, not
    raised: the error to see is the one that failed the start, raised after this."""
    for stop in reversed(started):
        try:
            await stop()
        except Exception:
            log.exception("stopping after a failed start", extra={"event": "start_undo_failed"})


async def stop_services(services: Services) -> None:
    """The reverse of start_services: nothing accepted before this is lost."""
    if services.cosims is not None:  # their runs stopped, their rows so far stored
        await services.cosims.close()
    if services.federation is not None:  # fetches in flight cancelled, connections closed
        await services.federation.aclose()
    if services.deployments is not None:  # terminate/clean phases no longer waited for
        await services.deployments.close()
    if services.runs is not None:  # their process groups killed, the runs cancelled
        await services.runs.close()
    if services.workspaces is not None:  # their JupyterLabs stop, their tokens are revoked
        await services.workspaces.close()
    await services.mqtt.close()  # waits for batches in flight and sends their PUBACKs
    await services.connectors.close()
    await services.gateway.close()
    await services.processors.close()
    services.live.close()
    if services.cache_sync is not None:
        await services.cache_sync.stop()
    await services.bus.stop()
    await services.properties.close()
    await services.commands.close()
    await services.property_store.close()
    await services.command_store.close()
    await services.history_maintenance.stop()
    await services.history.close()
    await services.auth.last_used.close()  # best effort: a full disk does not stop shutdown
    await services.store.close()
    if services.storage_shared is not None:
        await services.storage_shared.close()


def create_app(
    settings: Settings,
    on_bootstrap: Callable[[Bootstrap], None] | None = None,
    on_ready: Callable[[Services], object] | None = None,
) -> FastAPI:
    services = build_services(settings)
    metrics = _metrics(services)
    app = FastAPI(
        title="twinlink",
        version=__version__,
        description="An open-source digital twin platform: DT documents, a twin registry with "
        "search, live data, processors and an API gateway (the Data Link). "
        "Every endpoint needs `Authorization: Bearer <token>` except /healthz, /readyz, "
        "login and public DT documents.",
        lifespan=_lifespan(services, settings, on_bootstrap, on_ready),
        docs_url=None,
        redoc_url=None,
        openapi_url=None,  # served by api.apidocs, behind a token
    )
    app.state.settings = settings
    app.state.services = services
    app.state.metrics = metrics
    # /readyz and /healthz: the store's ping and the bus, bounded, one check in flight
    app.state.readiness = Readiness(services.store, services.bus, settings.ready_timeout_s)
    problems.install(app)
    routers = (system, auth, twins, devices, device_ws, live, history_api, commands, properties)
    routers_more = (processors, gateway_api, connectors_api, mqtt_api, deployments_api, runs_api,
                    cosims_api, federation_api, exports)  # fmt: skip
    app.include_router(library_api.router)  # /api/v1/library
    for module in (*routers, *routers_more, workspaces_api, search, remote, pages, app_ui):
        app.include_router(module.router)
    apidocs.install(app)
    app.add_middleware(MetricsMiddleware, metrics=metrics)
    return app


def _metrics(services: Services) -> Metrics:
    """/metrics: the HTTP figures, and what each part counts itself, read at scrape time."""
    metrics = Metrics()
    metrics.registry.register(DataPlaneCollector(lambda: data_plane_figures(services)))
    metrics.registry.register(ProcessorCollector(services.processors))
    metrics.registry.register(ConnectorCollector(services.connectors))
    metrics.registry.register(MqttCollector(services.mqtt))
    metrics.registry.register(GatewayCollector(services.gateway))
    return metrics


def _lifespan(
    services: Services,
    settings: Settings,
    on_bootstrap: Callable[[Bootstrap], None] | None,
    on_ready: Callable[[Services], object] | None,
) -> Callable[[FastAPI], AbstractAsyncContextManager[None]]:
    """The app's life: the services start before the first request and stop after the last;
    `on_ready` runs in between (the demo starts its devices there)."""

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        created = await start_services(services, settings)
        cleanup = None
        try:  # from here on, whatever fails stops what started (the demo's devices too)
            if created is not None and on_bootstrap is not None:
                on_bootstrap(created)
            if on_ready is not None:
                # on_ready may return (or resolve to) a coroutine function run at shutdown.
                result = on_ready(services)
                if hasattr(result, "__await__"):
                    result = await result
                if callable(result):
                    cleanup = result
            # What was made while starting lives as long as the server: keep it out of the
            # collector's scans, which cost the hot paths (orjson.loads of a device batch took
            # 2.6 us a sample with a server-sized heap, 1.1 us frozen; bench/processors.py).
            gc.freeze()
            gc.set_threshold(*GC_THRESHOLDS)
            # the store without its password, the bus as named (it holds no credentials)
            where = {"store": settings.store_shown, "bus": settings.bus_url or "memory"}
            log.info("ready", extra={"event": "ready", "url": settings.base_url, **where})
            yield
        finally:
            if cleanup is not None:
                await cleanup()
            await app.state.readiness.close()  # a probe's ping still in flight
            await stop_services(services)

    return lifespan


def outermost(app: FastAPI) -> WorkspaceProxy:
    """The app to serve: gateway paths go straight to the proxy, in front of FastAPI's own
    middleware stack (error pages, body limits, telemetry), which cost a forwarded request
    about 60 us for nothing it uses; everything else goes to `app`."""
    services: Services = app.state.services
    gateway = GatewayApp(app, services.gateway, services.auth)
    assert services.workspaces is not None
    return WorkspaceProxy(gateway, services.workspaces, services.auth)  # /workspaces/{user}/
