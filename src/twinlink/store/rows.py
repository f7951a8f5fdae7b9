"""Rows of the metadata tables read as records, for every backend (SQLite, PostgreSQL): the
column lists that are the same SQL in both dialects, and one function a record.

A row is read by column name, which `sqlite3.Row`, `asyncpg.Record` and a dict all allow, so
this module needs neither driver. SQLite keeps booleans as 0 and 1, hence `bool(...)`;
PostgreSQL's booleans pass through it unchanged.
"""

from __future__ import annotations

from typing import Any, Protocol

import orjson

from twinlink.domain.records import (
    ApiToken,
    AuditEntry,
    ConnectorRecord,
    Device,
    Edge,
    FmuRecord,
    ProcessorEvent,
    ProcessorRecord,
    ServiceRecord,
    TwinRecord,
    User,
)


class Row(Protocol):
    """A row read by column name."""

    def __getitem__(self, key: str, /) -> Any: ...


USER_COLUMNS = "id, username, password_hash, is_admin, groups_json, disabled, created_ns"
TOKEN_COLUMNS = (
    "id, user_id, name, prefix, kind, created_ns, expires_ns, last_used_ns, revoked_ns, scope"
)

DEVICE_COLUMNS = (
    "d.id, d.twin_id, t.slug, d.name, d.description, d.prefix, d.created_ns, d.last_seen_ns"
)
DEVICE_FROM = "FROM devices d JOIN twins t ON t.id = d.twin_id"

# The twins' columns differ: each dialect gathers a twin's privacy levels its own way.
EDGE_COLUMNS = "source, kind, target, declared_by, privacy"

CONNECTOR_COLUMNS = (
    "c.id, c.twin_id, t.slug, c.device_id, d.name AS device, c.name, c.kind, c.settings,"
    " c.secret, c.enabled, c.created_by, c.created_ns, c.modified_ns"
)
CONNECTOR_FROM = (
    "FROM connectors c JOIN twins t ON t.id = c.twin_id JOIN devices d ON d.id = c.device_id"
)

PROCESSOR_COLUMNS = (
    "p.id, p.twin_id, t.slug, p.name, p.blueprint, p.spec, p.enabled, p.created_by,"
    " p.created_ns, p.modified_ns"
)
PROCESSOR_FROM = "FROM processors p JOIN twins t ON t.id = p.twin_id"
FMU_COLUMNS = "id, twin_id, name, sha256, size, info, uploaded_by, uploaded_ns"

SERVICE_COLUMNS = (
    "id, twin_id, name, source, settings, secret, auth_origin, created_by, created_ns, modified_ns"
)
AUDIT_FIELDS = (
    "time_ns", "twin", "service", "caller", "method", "path", "status", "outcome", "bytes_in",
    "bytes_out", "upstream_ms", "total_ms",
)  # fmt: skip
AUDIT_COLUMNS = ", ".join(AUDIT_FIELDS)


def user_of(row: Row) -> User:
    return User(
        id=row["id"],
        username=row["username"],
        is_admin=bool(row["is_admin"]),
        groups=orjson.loads(row["groups_json"]),
        created_ns=row["created_ns"],
        disabled=bool(row["disabled"]),
        password_hash=row["password_hash"],
    )


def token_of(row: Row) -> ApiToken:
    return ApiToken(
        id=row["id"],
        user_id=row["user_id"],
        name=row["name"],
        prefix=row["prefix"],
        kind=row["kind"],
        created_ns=row["created_ns"],
        expires_ns=row["expires_ns"],
        last_used_ns=row["last_used_ns"],
        revoked_ns=row["revoked_ns"],
        scope=row["scope"],
    )


def device_of(row: Row) -> Device:
    return Device(
        id=row["id"],
        twin_id=row["twin_id"],
        twin_slug=row["slug"],
        name=row["name"],
        description=row["description"],
        prefix=row["prefix"],
        created_ns=row["created_ns"],
        last_seen_ns=row["last_seen_ns"],
    )


def visibility_of(levels: list[str]) -> str:
    """A twin's visibility: the least private level among its parts."""
    if "public" in levels:
        return "public"
    if any(level != "private" for level in levels):
        return "group"
    return "private"


def twin_of(row: Row, levels: list[str]) -> TwinRecord:
    """`levels`: the privacy levels of the twin's parts, sorted, as its backend read them."""
    return TwinRecord(
        id=row["id"],
        slug=row["slug"],
        dt_id=row["dt_id"],
        name=row["name"],
        created_ns=row["created_ns"],
        modified_ns=row["modified_ns"],
        visibility=visibility_of(levels),
        levels=levels,
    )


def edge_of(row: Row) -> Edge:
    return Edge(row["source"], row["kind"], row["target"], row["declared_by"], row["privacy"])


def connector_of(row: Row) -> ConnectorRecord:
    return ConnectorRecord(
        id=row["id"],
        twin_id=row["twin_id"],
        twin_slug=row["slug"],
        device_id=row["device_id"],
        device=row["device"],
        name=row["name"],
        kind=row["kind"],
        settings=orjson.loads(row["settings"]),
        secret=row["secret"],
        enabled=bool(row["enabled"]),
        created_by=row["created_by"],
        created_ns=row["created_ns"],
        modified_ns=row["modified_ns"],
    )


def processor_of(row: Row) -> ProcessorRecord:
    return ProcessorRecord(
        id=row["id"],
        twin_id=row["twin_id"],
        twin_slug=row["slug"],
        name=row["name"],
        blueprint=row["blueprint"],
        spec=orjson.loads(row["spec"]),
        enabled=bool(row["enabled"]),
        created_by=row["created_by"],
        created_ns=row["created_ns"],
        modified_ns=row["modified_ns"],
    )


def event_of(row: Row) -> ProcessorEvent:
    return ProcessorEvent(
        row["id"],
        row["processor_id"],
        row["time_ns"],
        row["kind"],
        row["message"],
        orjson.loads(row["data"]),
    )


def fmu_of(row: Row) -> FmuRecord:
    return FmuRecord(
        id=row["id"],
        twin_id=row["twin_id"],
        name=row["name"],
        sha256=row["sha256"],
        size=row["size"],
        info=orjson.loads(row["info"]),
        uploaded_by=row["uploaded_by"],
        uploaded_ns=row["uploaded_ns"],
    )


def service_of(row: Row) -> ServiceRecord:
    return ServiceRecord(
        id=row["id"],
        twin_id=row["twin_id"],
        name=row["name"],
        source=row["source"],
        settings=orjson.loads(row["settings"]),
        secret=row["secret"],
        auth_origin=row["auth_origin"],
        created_by=row["created_by"],
        created_ns=row["created_ns"],
        modified_ns=row["modified_ns"],
    )


def audit_of(row: Row) -> AuditEntry:
    """A row of `SELECT id, {AUDIT_COLUMNS}`."""
    return AuditEntry(id=row["id"], **{f: row[f] for f in AUDIT_FIELDS})
