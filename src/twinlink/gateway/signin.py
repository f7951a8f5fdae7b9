"""A service's credentials made ready, or renewed after a 401, as the proxy needs them: a
failure becomes the 502 problem `refresh_failed`, with every secret scrubbed from its text.

A credential method may be a third party's plug-in: an error of its own code (anything but
RefreshError) is logged with its traceback and fails that sign-in like a refused login, never
the request loop or the health checks of the other services.
"""

from __future__ import annotations

import logging
from typing import Any

from twinlink.gateway.credentials.base import Credentials, RefreshError, scrub
from twinlink.gateway.exchange import GatewayProblem
from twinlink.gateway.table import Service

log = logging.getLogger("twinlink.gateway")


async def ready(credentials: Credentials[Any]) -> int:
    """`credentials.ready()`; RefreshError whatever went wrong."""
    try:
        return await credentials.ready()
    except RefreshError:
        raise
    except Exception as err:
        raise _failed(credentials, err) from err


async def refresh(credentials: Credentials[Any], refused_generation: int) -> None:
    """`credentials.refresh(...)`; RefreshError whatever went wrong."""
    try:
        await credentials.refresh(refused_generation)
    except RefreshError:
        raise
    except Exception as err:
        raise _failed(credentials, err) from err


def _failed(credentials: Credentials[Any], err: Exception) -> RefreshError:
    # The error's text is left out of the answer: it could hold a secret.
    log.exception("the %s credential method failed", credentials.method,
                  extra={"event": "credentials_failed"})  # fmt: skip
    return RefreshError(
        f"the {credentials.method} credential method failed ({type(err).__name__}); "
        "see the server's log"
    )


async def sign_in(service: Service) -> int:
    """Credentials usable now; the generation to report if the service refuses them."""
    try:
        return await ready(service.credentials)
    except RefreshError as err:
        raise _problem(service, "the gateway could not sign in to the service", err) from err


async def renew(service: Service, refused_generation: int) -> None:
    """New credentials after the service refused those of `refused_generation`."""
    try:
        await refresh(service.credentials, refused_generation)
    except RefreshError as err:
        raise _problem(
            service, "the service refused the gateway's credentials and renewing them failed", err
        ) from err


def _problem(service: Service, what: str, err: RefreshError) -> GatewayProblem:
    detail = scrub(str(err), service.credentials.secrets())
    return GatewayProblem(502, f"{what} ({service.name!r}): {detail}", outcome="refresh_failed")
