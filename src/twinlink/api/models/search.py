"""The answer of /api/v1/search."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field


class Match(BaseModel):
    feature: str | None = Field(description="the feature that matched; null: the twin itself")
    privacy: str = Field(description="the privacy part it is in")
    snippet: str = Field(description="text around the match, the words in <mark>")


class Hit(BaseModel):
    kind: Literal["twin", "asset"] = Field(description="a twin, or a library asset")
    slug: str | None = Field(description="the twin's; null for an asset")
    name: str
    score: float
    matches: list[Match]
    ref: str | None = Field(None, description="an asset's <scope>/<kind>/<name>")
    scope: str | None = Field(None, description="an asset's scope")
    asset_kind: str | None = Field(None, description="an asset's kind: data, models, ...")
    description: str | None = Field(None, description="an asset's description")


class KeywordCount(BaseModel):
    value: str
    count: int


class Facets(BaseModel):
    keywords: list[KeywordCount]
    counted_hits: int = Field(description="how many of the first hits the facets count")


class RemoteHit(BaseModel):
    """A remote twin (another instance's, kept here read-only) whose text holds the query."""

    remote_id: int = Field(description="its id under /api/v1/remote-twins")
    dt_id: str
    name: str
    url: str = Field(description="where its document is (its hosting-iri)")
    state: str = Field(description="reachable, stale or gone")


class SearchAnswer(BaseModel):
    query: str
    keyword: str | None
    total: int
    limit: int
    offset: int
    hits: list[Hit]
    facets: Facets
    remote: list[RemoteHit] | None = Field(
        None, description="remote twins that match, when asked for (remote=true) or configured"
    )
