"""A processor's configuration as users write it (API, CLI, YAML), checked before it runs."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict, Field, field_validator

from twinlink.domain.samples import SIGNAL_NAME, STREAM_NAME
from twinlink.processors.fmuenv import requirement_problem

PROCESSOR_NAME = STREAM_NAME
MAX_SPACING_S = 24 * 3600.0  # a day; a rate limit longer than that is a unit mistake


class InputMap(BaseModel):
    """Where a blueprint input comes from: a signal of the source stream, scaled and offset
    (value * scale + offset; the thesis's `measurement_proportion` is the scale)."""

    model_config = ConfigDict(extra="forbid")

    signal: str = Field(description="signal of the source stream")
    scale: float = Field(1.0, description="multiplied with the value first")
    offset: float = Field(0.0, description="added after scaling")

    @field_validator("signal")
    @classmethod
    def _signal_name(cls, value: str) -> str:
        if not SIGNAL_NAME.match(value):
            raise ValueError(f"{value!r} is not a signal name")
        return value


class Rates(BaseModel):
    """Rate limits like the Tvilling digital platform's, plus batching."""

    model_config = ConfigDict(extra="forbid")

    min_input_spacing_s: float = Field(
        0.0,
        ge=0,
        le=MAX_SPACING_S,
        description="input samples closer than this to the last one used are skipped",
    )
    min_step_spacing_s: float = Field(
        0.0,
        ge=0,
        le=MAX_SPACING_S,
        description="shortest time between steps, for blueprints that step",
    )
    min_output_spacing_s: float = Field(
        0.0,
        ge=0,
        le=MAX_SPACING_S,
        description="output samples closer than this to the last one sent are dropped",
    )
    max_batch: int = Field(
        10_000, ge=1, le=1_000_000, description="most samples handed to the blueprint at once"
    )


class ProcessorSpec(BaseModel):
    """What a processor runs, on what, and where its results go."""

    model_config = ConfigDict(extra="forbid")

    name: str = Field(description="unique within the twin; also the default output stream")
    blueprint: str = Field(description="a blueprint name from /api/v1/blueprints")
    source: str = Field("telemetry", description="the twin's stream the processor reads")
    output: str | None = Field(None, description="the stream it writes [its name]")
    inputs: dict[str, InputMap | str] = Field(
        default_factory=dict,
        description="blueprint input -> source signal (a name, or {signal, scale, offset}); "
        "inputs left out read the source signal of the same name",
    )
    params: dict[str, Any] = Field(default_factory=dict, description="the blueprint's parameters")
    rates: Rates = Field(default_factory=Rates)
    python_requirements: list[str] = Field(
        default_factory=list,
        max_length=100,
        description="pip requirements (`more-itertools==10.7.0`) of a Python FMU: the worker "
        "runs in a virtualenv of its own made from them (docs/processors.md) [none: the "
        "server's Python]",
    )
    memory_limit_mb: int = Field(
        1024, ge=16, le=1 << 20, description="the worker is restarted when its RSS is above this"
    )
    batch_timeout_s: float = Field(
        30.0, gt=0, le=3600, description="a worker stuck this long on one batch is restarted"
    )
    enabled: bool = Field(True, description="whether it runs (now and after a server restart)")

    @field_validator("name", "source")
    @classmethod
    def _stream_name(cls, value: str) -> str:
        if not STREAM_NAME.match(value):
            raise ValueError(
                f"{value!r} must be lowercase letters, digits, '_' or '-', starting with a letter"
            )
        return value

    @field_validator("python_requirements")
    @classmethod
    def _requirements(cls, value: list[str]) -> list[str]:
        for line in value:
            if (problem := requirement_problem(line)) is not None:
                raise ValueError(problem)
        return [line.strip() for line in value]

    @field_validator("output")
    @classmethod
    def _output_name(cls, value: str | None) -> str | None:
        return None if value is None else cls._stream_name(value)

    @property
    def output_stream(self) -> str:
        return self.output or self.name

    def input_maps(self) -> dict[str, InputMap]:
        return {k: InputMap(signal=v) if isinstance(v, str) else v for k, v in self.inputs.items()}

    def stored(self) -> dict[str, Any]:
        """The spec as kept in the store (name, blueprint and enabled are columns there)."""
        return self.model_dump(mode="json", exclude={"name", "blueprint", "enabled"})
