"""Answers of /api/v1/workspaces."""

from __future__ import annotations

from pydantic import BaseModel, Field


class WorkspaceView(BaseModel):
    user: str
    state: str = Field(description="starting, running, stopping, stopped or failed")
    url: str | None = Field(
        None,
        description="/workspaces/<user>/?ticket=...: the workspace's address with a one-time "
        "ticket (valid 60 s) that the proxy swaps for a session cookie; only while it runs, "
        "and only in answers to its owner",
    )
    started_ns: int | None = None
    idle_s: float | None = Field(None, description="seconds since its last proxied traffic")
    error: str | None = Field(None, description="why it failed")
    log: list[str] = Field(description="the last lines of its log, when it failed")


class Workspaces(BaseModel):
    workspaces: list[WorkspaceView]
