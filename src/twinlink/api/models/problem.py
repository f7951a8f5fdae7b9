"""Problem details (RFC 9457): the body of every error answer, and the error answers each
route declares in /openapi.json."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict, Field

# What each status means for any route of the API; a route's own summary says the rest.
MEANINGS = {
    401: "No token, or a token that is not valid (expired, revoked, unknown)",
    403: "The token is valid, but its user may not do this",
    404: "There is no such thing, or the caller may not see it",
    409: "The change conflicts with what is stored (a name taken, a thing in use)",
    413: "The body is larger than the server takes",
    422: "A parameter or the body is not valid; `errors` says where",
    502: "Another instance could not be read (unreachable, too slow, not a document)",
    503: "Storage failed or a read ran over its time budget; try again (Retry-After)",
    507: "The disk is full: nothing was stored; try again once space is freed",
}


class ProblemItem(BaseModel):
    """One thing wrong with the request: where (a parameter's path, or a document's line)
    and what."""

    message: str
    path: str | None = Field(None, description="e.g. `query.limit` or `features[0].name`")
    line: int | None = Field(None, description="the line in a DT document, from 1")
    column: int | None = Field(None, description="the column in a DT document, from 1")
    document: int | None = Field(None, description="which document of a stream, from 0")


class Problem(BaseModel):
    """An error answer (`application/problem+json`). `detail` is meant for a person: it says
    what to change. Some errors add fields: `errors` (what is wrong where), or `reason` and
    `devices` (a command that must name its device)."""

    model_config = ConfigDict(extra="allow", json_schema_extra={"additionalProperties": True})

    type: str = Field("about:blank", description="always `about:blank`: the status says it")
    title: str = Field(description="the status's name, e.g. `Not found`")
    status: int = Field(ge=400, le=599)
    detail: str
    errors: list[ProblemItem] | None = None
    reason: str | None = None
    devices: list[str] | None = None


def problems(*statuses: int) -> dict[int | str, dict[str, Any]]:
    """The `responses` of a route (or a router) for the error statuses it can answer."""
    return {status: {"model": Problem, "description": MEANINGS[status]} for status in statuses}
