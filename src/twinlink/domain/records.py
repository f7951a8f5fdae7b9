"""Plain records passed between the store and the services (users, tokens, devices, twins,
roles): part of the domain, so every layer may use them."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal

Role = Literal["owner", "editor", "viewer"]
ROLES: tuple[Role, ...] = ("owner", "editor", "viewer")
ROLE_RANK: dict[str, int] = {"viewer": 1, "editor": 2, "owner": 3}


@dataclass(slots=True)
class User:
    id: int
    username: str
    is_admin: bool
    groups: list[str]
    created_ns: int
    disabled: bool = False
    password_hash: str | None = field(default=None, repr=False)


@dataclass(slots=True)
class ApiToken:
    id: int
    user_id: int
    name: str
    prefix: str
    created_ns: int
    expires_ns: int | None
    last_used_ns: int | None
    revoked_ns: int | None
    kind: str = "api"
    scope: str | None = None  # a scoped token's (auth/scopes.py), e.g. a run's `twin:<slug>`


@dataclass(slots=True)
class Device:
    id: int
    twin_id: int
    twin_slug: str
    name: str
    description: str
    prefix: str
    created_ns: int
    last_seen_ns: int | None


@dataclass(slots=True)
class TwinRecord:
    id: int
    slug: str
    dt_id: str
    name: str
    created_ns: int
    modified_ns: int
    visibility: str  # the least private level among its parts: public | group | private
    levels: list[str] = field(default_factory=list)  # privacy levels of its parts


@dataclass(slots=True)
class Edge:
    """A relation between two twins by global id: `source` is parent of (or sibling of) `target`."""

    source: str
    kind: Literal["parent", "sibling"]
    target: str
    declared_by: str
    privacy: str


@dataclass(slots=True)
class TwinWrite:
    """Everything an apply changes, written in one transaction."""

    slug: str
    dt_id: str
    name: str
    created_ns: int
    modified_ns: int
    parts: dict[str, dict[str, Any]]  # all parts after the change, by privacy level
    edges: list[Edge]  # the edges this twin's document declares
    search_rows: list[SearchRow]
    owner_user_id: int | None = None  # granted `owner` when the twin is new
    twin_id: int | None = None  # None creates


@dataclass(slots=True)
class SearchRow:
    privacy: str
    feature: str | None  # None: the twin itself (name, description, top-level fields)
    name: str
    description: str
    keywords: list[str]
    extra: str


@dataclass(slots=True)
class Visibility:
    """What a reader may see: all (admin), or public plus the levels granted per twin."""

    is_admin: bool = False
    user_id: int | None = None
    groups: tuple[str, ...] = ()


@dataclass(slots=True)
class SearchResult:
    total: int
    hits: list[dict[str, Any]]
    facets: list[tuple[str, int]]
    facet_hits: int = 0  # how many of the best hits the facets were counted over


@dataclass(slots=True)
class ProcessorRecord:
    """A processor as stored: its blueprint, its JSON spec and whether it should run."""

    id: int
    twin_id: int
    twin_slug: str
    name: str
    blueprint: str
    spec: dict[str, Any]
    enabled: bool
    created_by: int | None
    created_ns: int
    modified_ns: int


@dataclass(slots=True)
class ConnectorRecord:
    """A connector as stored: its kind, the device it speaks for, its settings (secrets apart,
    sealed) and whether it should run."""

    id: int
    twin_id: int
    twin_slug: str
    device_id: int
    device: str
    name: str
    kind: str
    settings: dict[str, Any]
    secret: bytes | None
    enabled: bool
    created_by: int | None
    created_ns: int
    modified_ns: int


@dataclass(slots=True)
class ProcessorEvent:
    id: int
    processor_id: int
    time_ns: int
    kind: str
    message: str
    data: dict[str, Any]


@dataclass(slots=True)
class FmuRecord:
    id: int
    twin_id: int
    name: str
    sha256: str
    size: int
    info: dict[str, Any]
    uploaded_by: int | None
    uploaded_ns: int


@dataclass(slots=True)
class ServiceRecord:
    """A gateway service's stored settings (see migration 0006)."""

    id: int
    twin_id: int
    name: str
    source: str  # api | document
    settings: dict[str, Any]
    secret: bytes | None = field(default=None, repr=False)
    auth_origin: str | None = None
    created_by: int | None = None
    created_ns: int = 0
    modified_ns: int = 0


@dataclass(slots=True)
class AuditEntry:
    """One request the gateway answered on a service path."""

    time_ns: int
    twin: str
    service: str
    caller: str
    method: str
    path: str
    status: int
    outcome: str  # forwarded | refused | failed
    bytes_in: int
    bytes_out: int
    upstream_ms: float | None
    total_ms: float
    id: int = 0
