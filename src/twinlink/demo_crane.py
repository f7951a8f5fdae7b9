"""What `twinlink demo` adds for the Ilmatar crane: its services running beside the server
(on the ports its DT document names) and their credentials set in the gateway, so each can be
tried through `/twins/ilmatar-k16052/services/...` at once."""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from typing import Any

import click

from twinlink.app import Services
from twinlink.auth.rights import Principal

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


async def start_demo_crane(
    services: Services, host: str = "127.0.0.1"
) -> tuple[str | None, Callable[[], Awaitable[None]] | None]:
    """Start the crane's services and configure their gateway credentials; a line for the
    welcome text and the function that stops them (both None when they cannot run)."""
    from twinlink.crane.gateway_auth import HEALTH_PATHS, gateway_auth
    from twinlink.crane.runner import start_crane

    admin = await services.store.get_user_by_name("admin")
    twin = await services.registry.get_twin(CRANE_SLUG)
    if admin is None or twin is None:
        return None, None
    try:
        crane = await start_crane(host)
    except OSError as err:
        click.echo(f"the crane's services did not start: {err}", err=True)
        return None, None
    principal = Principal(user=admin)
    for name, auth in gateway_auth(crane).items():
        patch = {"auth": auth, "health_path": HEALTH_PATHS.get(name)}
        await services.gateway.update(principal, CRANE_SLUG, name, patch)
    names = ",".join(sorted(HEALTH_PATHS))
    note = (
        f"The Ilmatar crane's services run through the gateway: /twins/{CRANE_SLUG}/services/"
        f"{{{names}}}/..."
    )
    if await _plc(services, principal, crane.opcua.url):
        note += "\n  Its OPC UA server feeds the twin through the connector plc (stream telemetry)."

    async def stop() -> None:
        # The gateway's kept-alive connections to the services would each hold their
        # servers' graceful shutdown until it times out: close them first.
        services.gateway.pool.close()
        await crane.stop()

    return note, stop


async def _plc(services: Services, principal: Principal, url: str) -> bool:
    """Create the crane's OPC UA connector, or point the existing one at this run's server."""
    from twinlink.domain.errors import ConflictError, InvalidInputError

    body = plc_connector(url)
    try:
        try:
            await services.connectors.create(principal, CRANE_SLUG, body)
        except ConflictError:
            await services.connectors.update(
                principal, CRANE_SLUG, "plc", {"config": body["config"], "enabled": True}
            )
    except InvalidInputError as err:
        click.echo(f"the crane's OPC UA connector did not start: {err}", err=True)
        return False
    return True
