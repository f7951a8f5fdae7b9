"""Device properties: /api/v1/twins/{slug}/devices/{device}/properties for people and
/api/v1/device/properties for a device without a WebSocket."""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Body, Depends, Request

from twinlink.api.deps import Caller
from twinlink.api.devices import ThisDevice
from twinlink.api.models.commands import DeviceProperties, ReportAck
from twinlink.api.models.problem import problems
from twinlink.api.responses import JSONAnswer
from twinlink.api.routing import ExactJsonRoute
from twinlink.commands import PropertyService

router = APIRouter(
    prefix="/api/v1",
    tags=["properties"],
    route_class=ExactJsonRoute,
    responses=problems(401, 404, 422, 503),
)


async def property_service(request: Request) -> PropertyService:
    return request.app.state.services.properties  # type: ignore[no-any-return]


Properties = Annotated[PropertyService, Depends(property_service)]


@router.get(
    "/twins/{slug}/devices/{device}/properties",
    summary="Reported and desired properties of a device, and their delta (viewers)",
    response_class=JSONAnswer,
    response_model=DeviceProperties,
    responses=problems(403),
)
async def get_properties(
    slug: str, device: str, caller: Caller, properties: Properties
) -> JSONAnswer:
    return JSONAnswer({"device": device, **(await properties.show(caller, slug, device)).view()})


@router.patch(
    "/twins/{slug}/devices/{device}/properties/desired",
    summary="Change desired properties (editors): name -> value, null removes one",
    response_class=JSONAnswer,
    response_model=DeviceProperties,
    responses=problems(403, 409, 507),
)
async def patch_desired(
    slug: str,
    device: str,
    changes: Annotated[dict[str, Any], Body(description="property name -> value (or null)")],
    caller: Caller,
    properties: Properties,
) -> JSONAnswer:
    props = await properties.set_desired(caller, slug, device, changes)
    return JSONAnswer({"device": device, **props.view()})


@router.get(
    "/device/properties",
    summary="This device's properties: desired, delta and version (device token)",
    response_class=JSONAnswer,
    response_model=DeviceProperties,
)
async def device_properties(device: ThisDevice, properties: Properties) -> JSONAnswer:
    return JSONAnswer({"device": device.name, **(await properties.for_device(device)).view()})


@router.post(
    "/device/properties",
    summary="Report property values (device token); the answer has the desired delta",
    response_class=JSONAnswer,
    response_model=ReportAck,
    responses=problems(507),
)
async def report_properties(
    device: ThisDevice,
    properties: Properties,
    body: Annotated[dict[str, Any], Body(description='{"properties": {name: value}}')],
) -> JSONAnswer:
    return JSONAnswer(await properties.report(device, body.get("properties")))
