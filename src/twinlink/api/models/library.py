"""Bodies and answers of /api/v1/library (docs/library.md)."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict, Field


class FileView(BaseModel):
    path: str = Field(description="the file's path inside the version ('/'-separated)")
    sha256: str
    size: int
    executable: bool


class VersionSummary(BaseModel):
    digest: str = Field(description="sha256: and the hex digest of the version's manifest")
    size: int = Field(description="bytes of all its files")
    file_count: int
    meta: dict[str, Any] = Field(description="`fmus`: each FMU's FMI description, by path")
    tags: list[str]
    created_ns: int
    created_by: str | None


class VersionView(VersionSummary):
    files: list[FileView]


class AssetView(BaseModel):
    scope: str = Field(description="common, group:<group> or user:<username>")
    kind: str = Field(description="data, models, tools, functions or twins")
    name: str
    ref: str = Field(description="<scope>/<kind>/<name>, as written after lib:")
    description: str
    keywords: list[str]
    licence: str
    author: str
    tags: dict[str, str] = Field(description="tag -> version digest")
    latest: str | None = Field(description="the digest `latest` points at")
    versions: int = Field(description="how many versions it has")
    created_by: str | None
    created_ns: int
    updated_ns: int


class Assets(BaseModel):
    assets: list[AssetView]
    next: str | None = Field(description="pass as `after` for the next page; null on the last page")


class AssetDetail(AssetView):
    versions: list[VersionSummary] = Field(description="newest first")  # type: ignore[assignment]
    version_count: int


class Versions(BaseModel):
    versions: list[VersionSummary]


class PushAnswer(BaseModel):
    asset: AssetView
    version: VersionView
    created: bool = Field(description="false: a version with the same content existed")


class AssetChange(BaseModel):
    model_config = ConfigDict(extra="forbid")

    description: str | None = Field(None, max_length=10_000)
    keywords: list[str] | None = Field(None, max_length=100)
    licence: str | None = Field(None, max_length=200)
    author: str | None = Field(None, max_length=200)


class TagBody(BaseModel):
    model_config = ConfigDict(extra="forbid")

    version: str = Field(
        min_length=1, max_length=80, description="a tag, a digest or a digest prefix"
    )
