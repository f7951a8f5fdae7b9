"""Answers of /api/v1/connector-kinds and /api/v1/twins/{slug}/connectors. A connector's
`config` shows its secret settings only as whether each is set."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, Field


class ConnectorKind(BaseModel):
    kind: str
    description: str
    schema_: dict[str, Any] = Field(alias="schema", description="its config's JSON schema")
    secret_fields: list[str]


class ConnectorKinds(BaseModel):
    kinds: list[ConnectorKind]


class ConnectorStatus(BaseModel):
    state: str
    since_ns: int
    errors: dict[str, int] = Field(description="kind of error -> count")
    error_count: int
    last_error: str | None
    last_error_ns: int | None
    last_message_ns: int | None
    messages: int
    samples: int
    rejected: int
    commands: int
    address: str | None = Field(None, description="where it listens or what it reaches")


class ConnectorView(BaseModel):
    name: str
    twin: str
    kind: str
    device: str
    enabled: bool
    config: dict[str, Any]
    status: ConnectorStatus
    created_ns: int
    modified_ns: int


class Connectors(BaseModel):
    connectors: list[ConnectorView]
