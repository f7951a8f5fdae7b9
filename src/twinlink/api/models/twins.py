"""Answers of /api/v1/twins and /api/v1/apply: twins, their parts, relations and roles."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, Field

Role = Literal["owner", "editor", "viewer"]


class TwinSummary(BaseModel):
    slug: str = Field(description="the twin's name in URLs")
    id: str = Field(description="the DT document's `id` (or `dt-id`): the twin's global id")
    name: str
    url: str = Field(description="the canonical URL of the twin's document")
    created: str = Field(description="ISO 8601, UTC")
    modified: str = Field(description="ISO 8601, UTC")
    levels: list[str] = Field(description="privacy parts (of those the caller may see)")


class TwinPage(BaseModel):
    items: list[TwinSummary]
    next_cursor: str | None = Field(description="`cursor` of the next page; null at the end")


class Applied(TwinSummary):
    outcome: Literal["created", "updated", "unchanged"]


class Updated(Applied):
    dry_run: Literal[True] | None = Field(
        None, description="only with dry_run=true: the documents were checked, nothing stored"
    )


class AppliedList(BaseModel):
    results: list[Applied] = Field(description="one per twin, in the documents' order")


class Twin(TwinSummary):
    role: Literal["owner", "editor", "viewer", "admin"] | None = Field(
        description="the caller's role on the twin (`admin` for platform admins)"
    )
    document: dict[str, Any] = Field(
        description="the DT document: the parts the caller may see, merged"
    )


class DeletedTwins(BaseModel):
    deleted: list[str] = Field(description="the slugs deleted (the twin, and with cascade its "
                               "descendants)")  # fmt: skip


class Parts(BaseModel):
    levels: list[str]


class RemoteSummary(BaseModel):
    """A twin of another instance a relation names (docs/federation.md)."""

    url: str = Field(description="Where the document was fetched (its hosting-iri).")
    name: str
    state: str = Field(
        description="reachable, stale or gone; pending (not fetched yet) or refused (by the "
        "SSRF guard) when no copy is kept."
    )
    fetched_at: str | None = Field(description="When the copy was fetched (RFC 3339, UTC).")
    remote_id: int | None = Field(None, description="The remote twin (/api/v1/remote-twins).")


class RelationNode(BaseModel):
    """A twin in a relation tree; a related id that is not registered here has
    `registered: false` and no slug or name, and `remote` when it is another instance's
    twin (an http(s) dt-id)."""

    id: str
    slug: str | None = None
    name: str | None = None
    registered: bool | None = None
    remote: RemoteSummary | None = None
    nodes: list[RelationNode]


class RoleGrant(BaseModel):
    username: str
    role: Role


class RoleChange(BaseModel):
    username: str
    role: Role | None = Field(description="null when the role was taken away")


class Roles(BaseModel):
    roles: list[RoleGrant]
