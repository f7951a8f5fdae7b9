"""A service's credentials made ready, or renewed after a 401, as the proxy needs them: a
failure becomes the 502 problem `refresh_failed`, with every secret scrubbed from its text."""

from __future__ import annotations

from twinlink.gateway.credentials.base import RefreshError, scrub
from twinlink.gateway.exchange import GatewayProblem
from twinlink.gateway.services import Service


async def sign_in(service: Service) -> int:
    """Credentials usable now; the generation to report if the service refuses them."""
    try:
        return await service.credentials.ready()
    except RefreshError as err:
        raise _problem(service, "the gateway could not sign in to the service", err) from None


async def renew(service: Service, refused_generation: int) -> None:
    """New credentials after the service refused those of `refused_generation`."""
    try:
        await service.credentials.refresh(refused_generation)
    except RefreshError as err:
        raise _problem(
            service, "the service refused the gateway's credentials and renewing them failed", err
        ) from None


def _problem(service: Service, what: str, err: RefreshError) -> GatewayProblem:
    detail = scrub(str(err), service.credentials.secrets())
    return GatewayProblem(502, f"{what} ({service.name!r}): {detail}", outcome="refresh_failed")
