"""Answers of the command and property routes, for people and for devices."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, Field

CommandState = Literal["pending", "delivered", "succeeded", "failed", "expired"]


class CommandView(BaseModel):
    id: str
    twin: str
    device: str
    name: str
    args: dict[str, Any]
    state: CommandState
    queued: bool = Field(description="kept for a device that was offline")
    sent_by: str | None
    created: str = Field(description="ISO 8601, UTC")
    expires: str = Field(description="ISO 8601, UTC")
    delivered: str | None
    finished: str | None
    result: Any = Field(description="what the device answered (any JSON value)")
    error: str | None
    late_status: str | None = Field(description="a result that came after it expired")


class CommandList(BaseModel):
    commands: list[CommandView]


class PendingCommand(BaseModel):
    id: str
    name: str
    args: dict[str, Any]
    expires: int = Field(description="ns since the epoch")


class PendingCommands(BaseModel):
    commands: list[PendingCommand]


class ResultAck(BaseModel):
    id: str
    state: CommandState
    late_status: str | None


class TimedProperty(BaseModel):
    value: Any
    time: str = Field(description="ISO 8601, UTC")


class DeviceProperties(BaseModel):
    device: str
    reported: dict[str, TimedProperty]
    desired: dict[str, TimedProperty]
    delta: dict[str, Any] = Field(description="desired values the device has not reported yet")
    version: int = Field(description="the version of the desired values")


class ReportAck(BaseModel):
    version: int
    desired: dict[str, Any] = Field(description="the delta: desired values still to apply")
