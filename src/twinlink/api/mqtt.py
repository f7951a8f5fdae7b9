"""/api/v1/mqtt: the MQTT listener's or external broker's status (docs/mqtt.md)."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter, Request

from twinlink.api.deps import Admin
from twinlink.api.responses import JSONAnswer

router = APIRouter(prefix="/api/v1", tags=["devices"])


@router.get(
    "/mqtt",
    summary="MQTT: mode, address, state, connected devices and counts (admins)",
    response_class=JSONAnswer,
)
async def mqtt_status(request: Request, _: Admin) -> dict[str, Any]:
    return request.app.state.services.mqtt.view()  # type: ignore[no-any-return]
