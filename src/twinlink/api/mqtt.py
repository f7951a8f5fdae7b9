"""/api/v1/mqtt: the MQTT listener's or external broker's status (docs/mqtt.md)."""

from __future__ import annotations

from fastapi import APIRouter, Request

from twinlink.api.deps import Admin
from twinlink.api.models.problem import problems
from twinlink.api.models.system import MqttStatus
from twinlink.api.responses import JSONAnswer

router = APIRouter(prefix="/api/v1", tags=["devices"])


@router.get(
    "/mqtt",
    summary="MQTT: mode, address, state, connected devices and counts (admins)",
    response_class=JSONAnswer,
    response_model=MqttStatus,
    responses=problems(401, 403, 503),
)
async def mqtt_status(request: Request, _: Admin) -> JSONAnswer:
    return JSONAnswer(request.app.state.services.mqtt.view())
