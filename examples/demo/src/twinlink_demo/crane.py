"""What `twinlink demo` adds for the Ilmatar crane: its services running beside the server and
their credentials set in the gateway, so each can be tried through
`/twins/ilmatar-k16052/services/...` at once.

The services listen on the ports the crane's DT document names (4840, 8701, 8703-8705). A port
something else already listens on is replaced by a free one, and the documents the demo applies
and the connector it makes name the ports really used: the gateway and the connector then
reach the demo's own services, never whatever holds the usual port.
"""

from __future__ import annotations

import contextlib
import dataclasses
import re
from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from typing import Any

import click

from ilmatar_crane import Crane, CranePorts, start_crane
from ilmatar_crane._http import can_listen
from ilmatar_crane.settings import PORT_NAMES
from twinlink.app import Services
from twinlink.auth.rights import Principal
from twinlink.domain.errors import ConflictError, InvalidInputError, NotFoundError
from twinlink_demo.crane_gateway import HEALTH_PATHS, gateway_auth

CRANE_SLUG = "ilmatar-k16052"
_NODE = "nsu=http://twinlink.example/ilmatar;s=Ilmatar"


def plc_connector(url: str) -> dict[str, Any]:
    """The crane's OPC UA connector: positions, speeds and load in, set-points and start/stop
    out, as a new user would connect a real crane's PLC (docs/opcua.md)."""
    signals = [
        {"node": f"{_NODE}.{axis}.{name}", "signal": f"{axis.lower()}_{name.lower()}"}
        for axis in ("Bridge", "Trolley", "Hoist")
        for name in ("Position", "Speed")
    ]
    signals.append({"node": f"{_NODE}.Hook.Load", "signal": "load"})
    commands: dict[str, Any] = {
        f"set_{axis.lower()}_speed": {"node": f"{_NODE}.{axis}.SpeedSetpoint"}
        for axis in ("Bridge", "Trolley", "Hoist")
    }
    commands["start"] = {"object": _NODE, "method": f"{_NODE}.Start"}
    commands["stop"] = {"object": _NODE, "method": f"{_NODE}.Stop"}
    return {
        "name": "plc",
        "kind": "opcua",
        "config": {"url": url, "signals": signals, "commands": commands},
    }


def usual_or_free(host: str, usual: CranePorts = CranePorts()) -> CranePorts:
    """The usual ports, each one something else listens on replaced by 0 (any free one)."""
    ports = dataclasses.asdict(usual)
    return CranePorts(**{name: p if can_listen(host, p) else 0 for name, p in ports.items()})


@dataclass(frozen=True)
class DemoCrane:
    """The crane's running services and, by service, the usual ports they could not have."""

    crane: Crane
    moved: dict[str, tuple[int, int]]  # service -> (usual port, port used instead)

    def documents(self, text: str) -> str:
        """A DT document's text with each moved port replaced by the one really used."""
        for usual, used in self.moved.values():
            text = re.sub(rf"(?<=127\.0\.0\.1:){usual}(?!\d)", str(used), text)
        return text

    def moved_note(self) -> str | None:
        """One line naming the usual ports that were taken and what was used instead."""
        if not self.moved:
            return None
        moves = [
            f"{usual} ({PORT_NAMES[name]}) -> {used}" for name, (usual, used) in self.moved.items()
        ]
        return (
            f"Ports in use elsewhere, replaced for the crane (in its documents too): "
            f"{', '.join(moves)}."
        )


async def start_crane_services(host: str = "127.0.0.1") -> DemoCrane | None:
    """Start the crane's services on their usual ports, or free ones where those are taken;
    None (said in one line) when they cannot start."""
    usual = CranePorts()
    try:
        crane = await start_crane(host, usual_or_free(host, usual))
    except OSError as err:
        click.echo(f"The crane's services did not start: {err}", err=True)
        return None
    moved = {
        name: (port, getattr(crane.ports, name))
        for name, port in dataclasses.asdict(usual).items()
        if getattr(crane.ports, name) != port
    }
    return DemoCrane(crane, moved)


async def start_demo_crane(
    services: Services, demo: DemoCrane
) -> tuple[str | None, Callable[[], Awaitable[None]] | None]:
    """Configure the gateway's credentials for the crane's services and its OPC UA connector;
    a line for the welcome text and the function that stops the services. Without the crane's
    twin (examples without it) the services are stopped at once: (None, None)."""
    crane = demo.crane
    admin = await services.store.get_user_by_name("admin")
    twin = await services.registry.get_twin(CRANE_SLUG)
    if admin is None or twin is None:
        await crane.stop()
        return None, None
    principal = Principal(user=admin)

    async def stop() -> None:
        await _disable_plc(services, principal)
        # The gateway's kept-alive connections to the services would each hold their
        # servers' graceful shutdown until it times out: close them first.
        services.gateway.pool.close()
        await crane.stop()

    for name, auth in gateway_auth(crane).items():
        patch = {"auth": auth, "health_path": HEALTH_PATHS.get(name)}
        await services.gateway.update(principal, CRANE_SLUG, name, patch)
    names = ",".join(sorted(HEALTH_PATHS))
    note = (
        f"The Ilmatar crane's services run through the gateway: /twins/{CRANE_SLUG}/services/"
        f"{{{names}}}/..."
    )
    if await _plc(services, principal, crane.opcua.url):
        note += (
            f"\n  Its OPC UA server ({crane.opcua.url}) feeds the twin through the connector plc."
        )
    moved = demo.moved_note()
    if moved:
        note += f"\n  {moved}"
    return note, stop


async def _disable_plc(services: Services, principal: Principal) -> None:
    """Stop the connector before its server, and keep it stopped: running, it would say its
    server vanished; enabled, the next start would start it (and have it fail to connect)
    before the crane's services are up, which then enable it again (`_plc`)."""
    # Deleted, or changed by hand into something that cannot run: nothing to stop.
    with contextlib.suppress(NotFoundError, InvalidInputError):
        await services.connectors.update(principal, CRANE_SLUG, "plc", {"enabled": False})


async def _plc(services: Services, principal: Principal, url: str) -> bool:
    """Create the crane's OPC UA connector, or point the existing one at this run's server."""
    body = plc_connector(url)
    try:
        try:
            await services.connectors.create(principal, CRANE_SLUG, body)
        except ConflictError:
            await services.connectors.update(
                principal, CRANE_SLUG, "plc", {"config": body["config"], "enabled": True}
            )
    except InvalidInputError as err:
        click.echo(f"The crane's OPC UA connector did not start: {err}", err=True)
        return False
    return True
