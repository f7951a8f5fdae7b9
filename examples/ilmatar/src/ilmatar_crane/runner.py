"""Starting and stopping all crane services together in the caller's event loop."""

from __future__ import annotations

import asyncio
import contextlib
import logging
import tempfile
from collections.abc import Coroutine
from contextlib import AsyncExitStack
from dataclasses import dataclass, field
from pathlib import Path

from starlette.types import ASGIApp

from ilmatar_crane._http import HttpService, url_host
from ilmatar_crane.autopilot import Autopilot
from ilmatar_crane.bridge import OpcUaBridge
from ilmatar_crane.cadfiles import write_cad_files
from ilmatar_crane.cadstore import CadStore
from ilmatar_crane.historian import Historian
from ilmatar_crane.opcua import CraneOpcUaServer
from ilmatar_crane.plant import CranePlant
from ilmatar_crane.sensors import SensorManager
from ilmatar_crane.settings import CranePorts, CraneSettings, DemoCredentials

log = logging.getLogger(__name__)
MAX_STEP_S = 1.0  # after a stalled loop, do not let the crane jump across the hall


@dataclass
class Crane:
    """The running services. `ports` holds the ports really in use (port 0 resolved)."""

    host: str
    ports: CranePorts
    settings: CraneSettings
    plant: CranePlant
    opcua: CraneOpcUaServer
    bridge: OpcUaBridge
    historian: Historian
    cad: CadStore
    sensors: SensorManager
    _stack: AsyncExitStack = field(repr=False)

    @property
    def credentials(self) -> DemoCredentials:
        return self.settings.credentials

    def root_url(self, service: str) -> str:
        """`http://host:port/` of "historian", "bridge", "cad" or "sensors"."""
        port: int = getattr(self.ports, service)
        return f"http://{url_host(self.host)}:{port}/"

    @property
    def urls(self) -> dict[str, str]:
        """The OPC UA endpoint and each HTTP service's API base URL."""
        http = {name: self.root_url(name) + "api/" for name in HTTP_SERVICES}
        return {"opcua": self.opcua.url, **http}

    async def stop(self) -> None:
        await self._stack.aclose()


HTTP_SERVICES = ("historian", "bridge", "cad", "sensors")


async def start_crane(
    host: str = "127.0.0.1",
    ports: CranePorts = CranePorts(),
    settings: CraneSettings = CraneSettings(),
) -> Crane:
    """Start the plant, the OPC UA server, the bridge, the historian, the CAD store and the
    sensor manager; on any failure everything already started is stopped again."""
    stack = AsyncExitStack()
    try:
        return await _start(stack, host, ports, settings)
    except BaseException:
        await stack.aclose()
        raise


async def _start(
    stack: AsyncExitStack, host: str, ports: CranePorts, settings: CraneSettings
) -> Crane:
    creds = settings.credentials
    plant = CranePlant(seed=settings.seed)
    opcua = CraneOpcUaServer(plant)
    await opcua.start(host, ports.opcua)
    stack.push_async_callback(opcua.stop)
    bridge = OpcUaBridge(opcua.url, creds.bridge_api_key)
    await bridge.connect()
    stack.push_async_callback(bridge.disconnect)
    historian = Historian(
        plant,
        users={creds.historian_username: creds.historian_password},
        token_ttl_s=settings.token_ttl_s,
        period_s=settings.historian_period_s,
        retention_s=settings.historian_retention_s,
    )
    cad = CadStore(_cad_folder(stack, settings.cad_dir), creds.cad_token)
    sensors = SensorManager(
        plant,
        clients={creds.sensors_client_id: creds.sensors_client_secret},
        users={creds.sensors_username: creds.sensors_password},
        token_ttl_s=settings.token_ttl_s,
    )
    apps: dict[str, ASGIApp] = {"historian": historian.app, "bridge": bridge.app}
    apps |= {"cad": cad.app, "sensors": sensors.app}
    real_ports = await _serve_http(stack, host, ports, apps)
    autopilot = Autopilot(hold_s=settings.autopilot_hold_s) if settings.autopilot else None
    _background(stack, run_plant(plant, opcua, autopilot, settings.plant_period_s), "plant")
    _background(stack, historian.run(), "historian-sampler")
    return Crane(
        host=host,
        ports=CranePorts(opcua=opcua.port, **real_ports),
        settings=settings,
        plant=plant,
        opcua=opcua,
        bridge=bridge,
        historian=historian,
        cad=cad,
        sensors=sensors,
        _stack=stack,
    )


async def _serve_http(
    stack: AsyncExitStack, host: str, ports: CranePorts, apps: dict[str, ASGIApp]
) -> dict[str, int]:
    """Serve each app on its port; returns the ports really used, by service."""
    started: list[HttpService] = []
    stack.push_async_callback(_stop_all, started)
    for name in HTTP_SERVICES:
        service = HttpService(apps[name], f"crane-{name}")
        await service.start(host, getattr(ports, name))
        started.append(service)
    return {s.name.removeprefix("crane-"): s.port for s in started}


def _cad_folder(stack: AsyncExitStack, folder: Path | None) -> Path:
    """The folder to serve: the given one (given the crane models if it has no files yet), or
    a temporary one with the models, removed again at stop."""
    if folder is None:
        folder = Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="twinlink-cad-")))
    if not folder.is_dir() or not any(folder.iterdir()):
        write_cad_files(folder)
    return folder


async def _stop_all(services: list[HttpService]) -> None:
    # Together: each uvicorn server takes a few tenths of a second to wind down.
    results = await asyncio.gather(*(s.stop() for s in services), return_exceptions=True)
    for result in results:
        if isinstance(result, BaseException):
            raise result


def _background(stack: AsyncExitStack, coro: Coroutine[None, None, None], name: str) -> None:
    task = asyncio.create_task(coro, name=f"crane-{name}")

    async def cancel() -> None:
        task.cancel()
        with contextlib.suppress(asyncio.CancelledError):
            await task

    stack.push_async_callback(cancel)


async def run_plant(
    plant: CranePlant, opcua: CraneOpcUaServer, autopilot: Autopilot | None, period_s: float
) -> None:
    """Step the plant and publish it over OPC UA every `period_s`, for ever."""
    loop = asyncio.get_running_loop()
    last = loop.time()
    while True:
        await asyncio.sleep(period_s)
        now = loop.time()
        dt, last = min(now - last, MAX_STEP_S), now
        if autopilot is not None:
            autopilot.drive(plant)
        if dt > 0:
            plant.step(dt)
        try:
            await opcua.publish()
        except Exception:
            # One failed update must not stop the crane; the next tick tries again.
            log.exception("publishing the crane's values over OPC UA failed")
