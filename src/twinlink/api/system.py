"""/healthz and /metrics."""

from __future__ import annotations

import hashlib
import hmac

from fastapi import APIRouter, Depends, Request
from prometheus_client import CONTENT_TYPE_LATEST, generate_latest
from starlette.responses import Response

from twinlink.api.deps import Bearer, optional_principal
from twinlink.api.models.problem import problems
from twinlink.api.models.system import Healthy
from twinlink.api.problems import problem
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
    try:
        ok = await request.app.state.services.store.ping()
    except Exception:  # a broken store is what this endpoint exists to report
        ok = False
    if not ok:
        return problem(503, "the store does not answer")
    return JSONAnswer({"status": "ok", "version": request.app.version})


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
