"""What `twinlink demo` adds for the Ilmatar crane: its services running beside the server
(on the ports its DT document names) and their credentials set in the gateway, so each can be
tried through `/twins/ilmatar-k16052/services/...` at once."""

from __future__ import annotations

from collections.abc import Awaitable, Callable

import click

from twinlink.app import Services
from twinlink.auth.rights import Principal

CRANE_SLUG = "ilmatar-k16052"


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

    async def stop() -> None:
        # The gateway's kept-alive connections to the services would each hold their
        # servers' graceful shutdown until it times out: close them first.
        services.gateway.pool.close()
        await crane.stop()

    return note, stop
