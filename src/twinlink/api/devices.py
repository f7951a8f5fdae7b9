"""/api/v1/twins/{slug}/devices (people manage devices) and /api/v1/device (a device itself)."""

from __future__ import annotations

import time
from typing import Annotated

from fastapi import APIRouter, Depends, Request
from fastapi.security import HTTPAuthorizationCredentials, HTTPBearer
from pydantic import BaseModel, Field

from twinlink.api.deps import Caller
from twinlink.api.models.devices import (
    DeletedDevice,
    DeviceList,
    DeviceState,
    DeviceView,
    DeviceWithToken,
)
from twinlink.api.models.problem import problems
from twinlink.api.routing import ExactJsonRoute
from twinlink.auth.service import AuthError
from twinlink.domain.records import Device
from twinlink.registry.build import human_time, human_time_or_none
from twinlink.registry.devices import DEVICE_NAME, DeviceService

router = APIRouter(
    prefix="/api/v1",
    tags=["devices"],
    route_class=ExactJsonRoute,
    responses=problems(401, 404, 422, 503),
)
_device_bearer = HTTPBearer(
    auto_error=False, scheme_name="DeviceToken", description="A device token: `tld_...`"
)


def device_service(request: Request) -> DeviceService:
    return request.app.state.services.devices  # type: ignore[no-any-return]


Devices = Annotated[DeviceService, Depends(device_service)]


async def this_device(
    devices: Devices,
    credentials: Annotated[HTTPAuthorizationCredentials | None, Depends(_device_bearer)],
) -> Device:
    if credentials is None:
        raise AuthError("a device token is required")
    return await devices.authenticate(credentials.credentials)


ThisDevice = Annotated[Device, Depends(this_device)]


class NewDevice(BaseModel):
    name: str = Field(pattern=DEVICE_NAME.pattern, description="unique within the twin")
    description: str = Field("", max_length=2000)


def device_view(d: Device) -> DeviceView:
    return DeviceView(
        name=d.name,
        twin=d.twin_slug,
        description=d.description,
        token_prefix=d.prefix,
        created=human_time(d.created_ns),
        last_seen=human_time_or_none(d.last_seen_ns),
    )


def device_state(d: Device, request: Request) -> DeviceState:
    # Whether it (or a connector speaking for it) has a session to this server now: the
    # WebSocket, MQTT, a UDP or OPC UA connector. Connected, it is being seen now.
    view = device_view(d)
    connected = request.app.state.services.device_hub.session(d.id) is not None
    if connected:
        view.last_seen = human_time(time.time_ns())
    return DeviceState(**view.model_dump(), connected=connected)


@router.get(
    "/twins/{slug}/devices",
    summary="The devices of a twin, and `default_device`: where a command that names no "
    "device goes now (null: it must name one) (viewers)",
    responses=problems(403),
)
async def list_devices(slug: str, caller: Caller, devices: Devices, request: Request) -> DeviceList:
    found = await devices.list(caller, slug)
    chosen = await request.app.state.services.commands.default_device(caller, slug)
    return DeviceList(devices=[device_state(d, request) for d in found], default_device=chosen)


@router.post(
    "/twins/{slug}/devices",
    status_code=201,
    summary="Add a device (editors); its token is in the answer, once",
    responses=problems(403, 409, 507),
)
async def create_device(
    slug: str, body: NewDevice, caller: Caller, devices: Devices
) -> DeviceWithToken:
    device, token = await devices.create(caller, slug, body.name, body.description)
    return DeviceWithToken(**device_view(device).model_dump(), token=token)


@router.get(
    "/twins/{slug}/devices/{device}", summary="One device (viewers)", responses=problems(403)
)
async def get_device(
    slug: str, device: str, caller: Caller, devices: Devices, request: Request
) -> DeviceState:
    return device_state(await devices.get(caller, slug, device), request)


@router.post(
    "/twins/{slug}/devices/{device}/token",
    summary="Replace a device's token (editors); the old one stops working",
    responses=problems(403, 409, 507),
)
async def rotate_device_token(
    slug: str, device: str, caller: Caller, devices: Devices
) -> DeviceWithToken:
    record, token = await devices.rotate(caller, slug, device)
    return DeviceWithToken(**device_view(record).model_dump(), token=token)


@router.delete(
    "/twins/{slug}/devices/{device}",
    summary="Remove a device and its token (editors)",
    responses=problems(403, 409, 507),
)
async def delete_device(slug: str, device: str, caller: Caller, devices: Devices) -> DeletedDevice:
    await devices.delete(caller, slug, device)
    return DeletedDevice(deleted=device)


@router.get("/device", summary="The device a device token belongs to (device tokens only)")
async def whoami(device: ThisDevice) -> DeviceView:
    return device_view(device)
