"""The answer of /api/v1/search."""

from __future__ import annotations

from pydantic import BaseModel, Field


class Match(BaseModel):
    feature: str | None = Field(description="the feature that matched; null: the twin itself")
    privacy: str = Field(description="the privacy part it is in")
    snippet: str = Field(description="text around the match, the words in <mark>")


class Hit(BaseModel):
    slug: str
    name: str
    score: float
    matches: list[Match]


class KeywordCount(BaseModel):
    value: str
    count: int


class Facets(BaseModel):
    keywords: list[KeywordCount]
    counted_hits: int = Field(description="how many of the first hits the facets count")


class SearchAnswer(BaseModel):
    query: str
    keyword: str | None
    total: int
    limit: int
    offset: int
    hits: list[Hit]
    facets: Facets
