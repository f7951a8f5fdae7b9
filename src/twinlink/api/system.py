"""/healthz and /metrics."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter, Request
from prometheus_client import CONTENT_TYPE_LATEST, generate_latest
from starlette.responses import Response

from twinlink.api.deps import Caller
from twinlink.api.problems import problem

router = APIRouter(tags=["system"])


@router.get("/healthz", summary="Liveness and store health (no token needed)")
async def healthz(request: Request) -> Any:
    try:
        ok = await request.app.state.services.store.ping()
    except Exception:  # a broken store is what this endpoint exists to report
        ok = False
    if not ok:
        return problem(503, "the store does not answer")
    return {"status": "ok", "version": request.app.version}


@router.get("/metrics", summary="Prometheus metrics (text format)")
async def metrics(request: Request, _: Caller) -> Response:
    store = request.app.state.services.store
    request.app.state.metrics.twins.set(await store.count_twins())
    request.app.state.metrics.users.set(await store.count_users())
    return Response(
        generate_latest(request.app.state.metrics.registry), media_type=CONTENT_TYPE_LATEST
    )
