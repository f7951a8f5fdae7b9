"""Answers of /api/v1/twins/{slug}/streams: a twin's stored telemetry. Times are integers,
ns since the epoch; `start` and `end` echo the range asked for (null when left open)."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, Field

Ns = int
SignalKind = Literal["integer", "number", "bool", "string", "mixed"]


class SignalInfo(BaseModel):
    name: str
    kind: SignalKind = Field(description="what its values are; `mixed` for more than one kind")
    values: int = Field(description="how many values are stored")
    count: int = Field(description="the same as `values` (kept for older clients)")
    first: Ns | None
    last: Ns | None


class StreamInfo(BaseModel):
    name: str
    samples: int = Field(description="how many samples (times) are stored")
    values: int = Field(description="how many values, over all signals")
    count: int = Field(description="the same as `values` (kept for older clients)")
    first: Ns | None
    last: Ns | None
    signals: list[SignalInfo]


class StreamList(BaseModel):
    twin: str
    streams: list[StreamInfo]


class TimedValue(BaseModel):
    time: Ns
    value: Any = Field(description="a number, bool or string")


class Latest(BaseModel):
    twin: str
    stream: str
    values: dict[str, TimedValue] = Field(description="signal -> its newest value")


class _Range(BaseModel):
    twin: str
    stream: str
    start: Ns | None
    end: Ns | None


class Row(BaseModel):
    time: Ns
    values: dict[str, Any] = Field(description="signal -> value at this time")


class SamplesPage(_Range):
    rows: list[Row]
    next_cursor: str | None = Field(description="`cursor` of the next page; null at the end")


class AggregateRow(BaseModel):
    time: Ns = Field(description="the bucket's start")
    values: dict[str, dict[str, float | None]] = Field(
        description="signal -> function -> value (sums of integers are exact integers)"
    )


class AggregateAnswer(_Range):
    bucket: str = Field(description="the bucket width, e.g. `1m`")
    bucket_ns: int
    fn: list[str]
    rows: list[AggregateRow]
    skipped: list[str] = Field(description="signals left out: they hold text")


class Series(BaseModel):
    time: list[Ns]
    value: list[float]


class DownsampleAnswer(_Range):
    method: Literal["minmax", "lttb"]
    points: int
    signals: dict[str, Series]
    skipped: list[str] = Field(description="signals left out: they hold text")
