"""Shared by the OPC UA connector tests (test_opcua_connector.py, test_opcua_commands.py,
test_opcua_security.py): the simulated crane's real asyncua server on a free loopback port,
the platform's real services in-process, and waiting on their state."""

from __future__ import annotations

import asyncio
import itertools
from collections.abc import AsyncIterator, Awaitable, Callable
from contextlib import asynccontextmanager
from dataclasses import dataclass, field
from datetime import UTC, datetime, timedelta
from pathlib import Path
from typing import Any

import pytest
import pytest_asyncio

from ilmatar_crane.opcua import CraneOpcUaServer, OpcUaAccess
from ilmatar_crane.plant import AXES, CranePlant
from tests.integration._util import twin_doc
from twinlink.app import Services, build_services, start_services, stop_services
from twinlink.auth.rights import Principal
from twinlink.bus import samples_subject
from twinlink.config import Settings
from twinlink.connectors.base import LinkHost
from twinlink.connectors.opcua.connector import OpcUaConnector
from twinlink.domain.commands import CommandRecord
from twinlink.domain.records import Device, TwinRecord
from twinlink.domain.samples import SampleBatch
from twinlink.registry.documents import parse_documents

# One crane server per test module (it takes a second to start and one to stop); each test
# has its own platform, and its own source times (`stamp()`).
DEADLINE_S = 15.0
T0 = datetime(2025, 3, 4, 5, 6, 7, 123456, tzinfo=UTC)
_STAMPS = itertools.count(1)
NS = "ns=2;s=Ilmatar"  # the crane's namespace is the first one it registers
FAST = {  # small intervals and backoffs, so the tests run quickly
    "publishing_interval_ms": 20,
    "sampling_interval_ms": 0,
    "batch_window_ms": 20,
    "reconnect_initial_s": 0.05,
    "reconnect_max_s": 0.2,
    "watchdog_interval_s": 0.2,
    "request_timeout_s": 2,
}
SIGNALS = [
    {"node": f"{NS}.Bridge.Position", "signal": "bridge_position"},
    {"node": "nsu=http://twinlink.example/ilmatar;s=Ilmatar.Trolley.Position",
     "signal": "trolley_position"},
    {"node": "/2:Ilmatar/2:Hoist/2:Position", "signal": "hoist_position"},
    {"node": f"{NS}.Bridge.Speed", "signal": "bridge_speed"},
    {"node": f"{NS}.Running", "signal": "running"},
]  # fmt: skip
COMMANDS = {
    "set_bridge_speed": {"node": f"{NS}.Bridge.SpeedSetpoint"},
    "set_hoist_speed": {"node": "/2:Ilmatar/2:Hoist/2:SpeedSetpoint", "arg": "speed"},
    "stop": {"object": NS, "method": f"{NS}.Stop"},
    "start": {"object": NS, "method": f"{NS}.Start"},
    "set_speeds": {"object": NS, "method": f"{NS}.SetSpeeds", "args": ["b", "t", "h"]},
}


def stamp() -> datetime:
    """A source time no other test uses."""
    return T0 + timedelta(seconds=next(_STAMPS))


def ns(when: datetime) -> int:
    return (when - datetime(1970, 1, 1, tzinfo=UTC)) // timedelta(microseconds=1) * 1000


def crane_config(url: str, **extra: Any) -> dict[str, Any]:
    return {"url": url, "signals": SIGNALS, "commands": COMMANDS, **FAST, **extra}


async def eventually(check: Callable[[], bool | Awaitable[bool]], what: str) -> None:
    """Wait until `check` holds on the real state; fail after DEADLINE_S."""
    loop = asyncio.get_running_loop()
    deadline = loop.time() + DEADLINE_S
    while True:
        result = check()
        if await result if isinstance(result, Awaitable) else result:
            return
        if loop.time() > deadline:
            raise AssertionError(f"gave up waiting for {what}")
        await asyncio.sleep(0.01)


# -- the platform --------------------------------------------------------------------------


@dataclass
class Platform:
    services: Services
    principal: Principal
    twin: TwinRecord
    device: Device
    batches: list[SampleBatch] = field(default_factory=list)

    def connector(self, config: dict[str, Any]) -> OpcUaConnector:
        host = LinkHost(self.services.device_hub, self.services.ingest, self.device)
        return OpcUaConnector("plc", OpcUaConnector.Config.model_validate(config), host)

    def samples(self) -> dict[int, dict[str, Any]]:
        """Every sample that reached the bus, by time (values of one time merged)."""
        out: dict[int, dict[str, Any]] = {}
        for batch in self.batches:
            for time_ns, values in zip(batch.times, batch.values, strict=True):
                out.setdefault(time_ns, {}).update(values)
        return out

    async def command(self, name: str, **args: Any) -> CommandRecord:
        return await self.services.commands.send(
            self.principal, self.twin.slug, name, args, timeout_s=10
        )


@asynccontextmanager
async def running_platform(data_dir: Path) -> AsyncIterator[Platform]:
    """The platform's services in-process, with a twin and its device `plc`; every sample
    batch published on the bus for the twin is collected in `batches`."""
    settings = Settings(data_dir=data_dir, log_level="warning", mqtt_mode="off")
    services = build_services(settings)
    await start_services(services, settings)
    try:
        admin = await services.store.get_user_by_name("admin")
        assert admin is not None
        principal = Principal(user=admin)
        doc = twin_doc("http://example.org/crane-under-test", name="Crane")
        docs = parse_documents(doc.encode(), "application/yaml", 1 << 20)
        [applied] = await services.registry.apply(principal, docs)
        device, _ = await services.devices.create(principal, applied.twin.slug, "plc", "PLC")
        platform = Platform(services, principal, applied.twin, device)
        unsubscribe = services.bus.subscribe(
            samples_subject(applied.twin.id, "telemetry"),
            lambda _, batch: platform.batches.append(batch),  # type: ignore[arg-type]
        )
        try:
            yield platform
        finally:
            unsubscribe()
    finally:
        await stop_services(services)


@asynccontextmanager
async def crane_server(
    plant: CranePlant, port: int = 0, access: OpcUaAccess | None = None
) -> AsyncIterator[CraneOpcUaServer]:
    server = CraneOpcUaServer(plant, access)
    await server.start("127.0.0.1", port)
    try:
        yield server
    finally:
        await server.stop()
        await _close_detached_sessions(server)


async def _close_detached_sessions(server: CraneOpcUaServer) -> None:
    """asyncua (2.1) keeps the session of a client whose connection is lost open while it has
    subscriptions, for the client to take back on a new connection (OPC UA Part 4, 6.7), until
    the session times out; its Server.stop() closes the connections (which detaches the
    sessions) but not those sessions, so their timeout and publishing tasks go on running in
    the test's loop. Stopping the server under a connected client (the reconnection tests) ends
    them here; asyncua keeps them in a private table, read only here."""
    iserver = server._server.iserver
    for session in list(iserver._external_sessions.values()):
        await session.close_session(delete_subs=True)


@asynccontextmanager
async def running(connector: OpcUaConnector) -> AsyncIterator[OpcUaConnector]:
    await connector.start()
    try:
        yield connector
    finally:
        await connector.stop()


@pytest_asyncio.fixture(loop_scope="module")
async def platform(tmp_path: Path) -> AsyncIterator[Platform]:
    async with running_platform(tmp_path) as platform:
        yield platform


@pytest.fixture(scope="module")
def plant() -> CranePlant:
    return CranePlant()


@pytest_asyncio.fixture(loop_scope="module", scope="module")
async def crane_module(plant: CranePlant) -> AsyncIterator[CraneOpcUaServer]:
    async with crane_server(plant) as server:
        yield server


@pytest_asyncio.fixture(loop_scope="module")
async def crane(crane_module: CraneOpcUaServer, plant: CranePlant) -> CraneOpcUaServer:
    return await standing_still(crane_module, plant)


async def standing_still(crane: CraneOpcUaServer, plant: CranePlant) -> CraneOpcUaServer:
    """The crane server with its plant's set-points at zero, published."""
    for axis in AXES:
        plant.set_speed_setpoint(axis, 0.0, manual=False)
    await crane.publish(at=stamp())
    return crane


async def connected(connector: OpcUaConnector) -> None:
    await eventually(lambda: connector.status.state == "connected", "the connector to connect")


def move(plant: CranePlant) -> None:
    """Drive every axis for a second, so every position changes."""
    for axis, speed in (("bridge", 0.5), ("trolley", -0.4), ("hoist", 0.15)):
        plant.set_speed_setpoint(axis, speed)
    plant.step(1.0)


# -- values ------------------------------------------------------------------------------
