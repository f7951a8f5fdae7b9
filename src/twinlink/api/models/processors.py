"""Answers of /api/v1/blueprints, /api/v1/twins/{slug}/processors and .../fmus."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict, Field

from twinlink.processors.spec import InputMap, Rates


class Blueprint(BaseModel):
    name: str
    source: str = Field(description="`installed` (an entry point) or the file it came from")
    title: str | None = None
    description: str | None = None
    keeps_state: bool | None = Field(None, description="new params keep the worker's state")
    params_schema: dict[str, Any] | None = Field(None, description="its parameters' JSON schema")
    error: str | None = Field(None, description="why it cannot be loaded (then it is unusable)")


class Blueprints(BaseModel):
    blueprints: list[Blueprint]


class Percentiles(BaseModel):
    p50: float | None
    p99: float | None


class ProcessorStats(BaseModel):
    samples_in: int
    samples_out: int
    batches: int
    dropped: int
    restarts: int
    crashes: int
    rss_bytes: int
    step_time_s: Percentiles
    added_latency_s: Percentiles


class ProcessorView(BaseModel):
    name: str
    twin: str
    blueprint: str
    source: str = Field(description="the stream it reads")
    output: str | None = Field(description="the stream it writes (null: its own name)")
    inputs: dict[str, InputMap | str]
    params: dict[str, Any]
    rates: Rates
    python_requirements: list[str] = Field(
        default_factory=list, description="pip requirements of its own Python env, if any"
    )
    memory_limit_mb: int
    batch_timeout_s: float
    enabled: bool
    state: str = Field(
        description="starting, running, backoff, stopping, stopped, failed or finished (the "
        "model ended its simulation; started again by restart or update)"
    )
    pid: int | None
    last_error: str | None
    restart_at: float | None = Field(description="Unix time (s) of the next start (backoff)")
    stats: ProcessorStats | None
    running: dict[str, Any] = Field(description="what the running worker says of itself")
    created_ns: int
    modified_ns: int
    kept_state: bool | None = Field(
        None, description="only in answers to a change: whether the worker kept its state"
    )


class Processors(BaseModel):
    processors: list[ProcessorView]


class ProcessorEvent(BaseModel):
    id: int
    time_ns: int
    kind: str
    message: str
    data: dict[str, Any]


class ProcessorEvents(BaseModel):
    events: list[ProcessorEvent]


class LogLine(BaseModel):
    time_ns: int
    text: str


class ProcessorLogs(BaseModel):
    lines: list[LogLine]


class FmuView(BaseModel):
    """An FMU and what FMPy read from it (`model_name`, `fmi_version`, ...); `variables`
    only for one FMU."""

    model_config = ConfigDict(extra="allow", json_schema_extra={"additionalProperties": True})

    name: str
    sha256: str
    size: int
    uploaded_ns: int
    variables: list[dict[str, Any]] | None = None


class Fmus(BaseModel):
    fmus: list[FmuView]
