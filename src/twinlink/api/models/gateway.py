"""Answers of the gateway's routes: services, their health, service accounts, the audit log.
Credentials show only whether each secret is set (`token_set`), never the secret."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field


class Health(BaseModel):
    checked_at: float = Field(description="Unix time in seconds")
    path: str | None
    status: Literal["up", "down"]
    http_status: int | None
    ms: float
    error: str | None = None


class UpstreamMs(BaseModel):
    mean: float
    p50: float | None
    p95: float | None


class ServiceStats(BaseModel):
    statuses: dict[str, int] = Field(description="HTTP status -> answers")
    failures: dict[str, int] = Field(description="kind of failure -> count")
    bytes_in: int
    bytes_out: int
    upstream_ms: UpstreamMs | None


class ServiceAuth(BaseModel):
    """How the gateway signs in to the service: `method`, and its settings (a secret only as
    `<name>_set`: whether it is set)."""

    model_config = ConfigDict(extra="allow", json_schema_extra={"additionalProperties": True})

    method: str


class ServiceView(BaseModel):
    name: str
    twin: str
    source: Literal["document", "api"]
    base_url: str
    feature: str | None
    description: str | None
    auth: ServiceAuth
    methods: list[str]
    limits: dict[str, float]
    health_path: str | None
    websocket: bool
    tls: dict[str, Any]
    blocked: str | None = Field(description="why the gateway does not forward to it, if so")
    gateway_path: str
    health: Health | None
    requests: int
    stats: ServiceStats
    credential_refreshes: int
    credential_error: str | None


class Services(BaseModel):
    services: list[ServiceView]


class ServiceDeleted(BaseModel):
    service: str
    outcome: str = Field(description="`deleted`, or `reset` for a service of the document")


class ServiceHealth(Health):
    service: str


class AuditEntry(BaseModel):
    id: int
    time: float = Field(description="Unix time in seconds")
    time_iso: str
    twin: str
    service: str
    caller: str
    method: str
    path: str
    status: int
    outcome: str
    bytes_in: int
    bytes_out: int
    upstream_ms: float | None
    total_ms: float


class AuditPage(BaseModel):
    entries: list[AuditEntry]
    next_before: int | None = Field(description="`before` of the next page; null at the end")


class ServiceAccount(BaseModel):
    name: str
    user: str
    role: str
    user_id: int


class ServiceAccountList(BaseModel):
    service_accounts: list[ServiceAccount]


class NewServiceAccount(BaseModel):
    name: str
    user: str
    role: str
    token: str = Field(description="its token: shown in this answer only")
    token_prefix: str
