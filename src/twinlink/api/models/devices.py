"""Answers of /api/v1/twins/{slug}/devices and /api/v1/device. A device's token is in an
answer once, when it is made or replaced."""

from __future__ import annotations

from pydantic import BaseModel, Field


class DeviceView(BaseModel):
    name: str
    twin: str = Field(description="the slug of the device's twin")
    description: str
    token_prefix: str = Field(description="the token's first characters, to recognise it by")
    created: str = Field(description="ISO 8601, UTC")
    last_seen: str | None = Field(description="ISO 8601, UTC; now while it is connected")


class DeviceState(DeviceView):
    connected: bool = Field(
        description="whether it (or a connector speaking for it) has a session to this server"
    )


class DeviceWithToken(DeviceView):
    token: str = Field(description="the device token: shown in this answer only")


class DeviceList(BaseModel):
    devices: list[DeviceState]
    default_device: str | None = Field(
        description="where a command that names no device goes now; null: it must name one"
    )


class DeletedDevice(BaseModel):
    deleted: str = Field(description="the device's name")
