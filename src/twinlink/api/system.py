"""/healthz, /readyz and /metrics."""

from __future__ import annotations

import hashlib
import hmac

from fastapi import APIRouter, Depends, Request
from prometheus_client import CONTENT_TYPE_LATEST, generate_latest
from starlette.responses import Response

from twinlink.api.deps import Bearer, optional_principal
from twinlink.api.models.problem import problems
from twinlink.api.models.system import Healthy, Ready
from twinlink.api.problems import problem
from twinlink.api.readiness import Readiness
from twinlink.api.responses import JSONAnswer
from twinlink.auth.service import AuthError
from twinlink.domain.errors import ForbiddenError

router = APIRouter(tags=["system"])


@router.get(
    "/healthz",
    summary="Liveness and store health (no token needed)",
    response_model=Healthy,
    responses=problems(503),
)
async def healthz(request: Request) -> Response:
    readiness: Readiness = request.app.state.readiness
    # Bounded (TWINLINK_READY_TIMEOUT_S): a database that stopped answering makes this
    # answer 503, not wait for ever.
    if not await readiness.store_answers():
        return problem(503, f"the store does not answer within {readiness.timeout_s:g} s")
    return JSONAnswer({"status": "ok", "version": request.app.version})


@router.get(
    "/readyz",
    summary="Readiness for a load balancer: the store and the bus answer (no token needed)",
    response_model=Ready,
    responses=problems(503),
)
async def readyz(request: Request) -> Response:
    """503 names what does not answer within TWINLINK_READY_TIMEOUT_S; never waits longer."""
    verdict = await request.app.state.readiness.check()
    if not verdict.ready:
        return problem(503, "; ".join(verdict.failures))
    return JSONAnswer({"status": "ready", "version": request.app.version})


async def metrics_reader(request: Request, credentials: Bearer) -> None:
    """Admins, or whoever sends the metrics token (TWINLINK_METRICS_TOKEN, for Prometheus's
    `bearer_token_file`). The metrics name twins, processors, services and connectors of
    every user, so a signed-in user who is not an admin gets 403."""
    expected = request.app.state.settings.metrics_token
    if expected is not None and credentials is not None:
        # Compared as digests, so the time taken says nothing about the token, not even
        # its length.
        sent = hashlib.sha256(credentials.credentials.encode()).digest()
        wanted = hashlib.sha256(expected.get_secret_value().encode()).digest()
        if hmac.compare_digest(sent, wanted):
            return
    caller = await optional_principal(request, credentials)
    if caller.user is None:
        raise AuthError("a token is required (an admin's, or the metrics token)")
    if not caller.is_admin:
        raise ForbiddenError(
            "the metrics are for admins, or for the metrics token (TWINLINK_METRICS_TOKEN)"
        )


@router.get(
    "/metrics",
    summary="Prometheus metrics (text format): admins, or the metrics token "
    "(TWINLINK_METRICS_TOKEN)",
    dependencies=[Depends(metrics_reader)],
    response_class=Response,
    responses={
        200: {"content": {"text/plain": {"schema": {"type": "string"}}}},  # Prometheus text
        **problems(401, 403, 503),
    },
)
async def metrics(request: Request) -> Response:
    store = request.app.state.services.store
    request.app.state.metrics.twins.set(await store.count_twins())
    request.app.state.metrics.users.set(await store.count_users())
    return Response(
        generate_latest(request.app.state.metrics.registry), media_type=CONTENT_TYPE_LATEST
    )
