"""An alarm on one signal: a threshold or a rate of change, with hysteresis and a minimum
duration, raising events and optionally sending commands."""

from __future__ import annotations

from typing import Any, Literal

import numpy as np
import numpy.typing as npt
from pydantic import Field, field_validator, model_validator

from twinlink.processors.blueprint import MAX_SPAN_S, Batch, Blueprint, Context, Params

Array = npt.NDArray[np.float64]
Ints = npt.NDArray[np.int64]
Bools = npt.NDArray[np.bool_]


class CommandSpec(Params):
    name: str = Field(min_length=1, description="The command's name.")
    params: dict[str, Any] = Field(default_factory=dict, description="The command's parameters.")
    device: str | None = Field(
        None, description="The device to send it to; empty: the twin's only (or first) device."
    )

    @field_validator("params")
    @classmethod
    def _not_reserved(cls, params: dict[str, Any]) -> dict[str, Any]:
        if reserved := {"name", "device"} & set(params):
            raise ValueError(f"a command parameter may not be called {sorted(reserved)[0]!r}")
        return params


class TriggerParams(Params):
    signal: str = Field(description="The signal watched.")
    mode: Literal["threshold", "rate"] = Field(
        "threshold",
        description="threshold: the value crosses a level; rate: the value changes faster "
        "than rate_limit per second (either way).",
    )
    direction: Literal["above", "below"] = Field(
        "above", description="threshold mode: raise when the value is above high or below low."
    )
    high: float | None = Field(None, description="Raise when the value is above this (above).")
    low: float | None = Field(None, description="Raise when the value is below this (below).")
    clear_at: float | None = Field(
        None,
        description="Hysteresis: clear only when the value is back below this (above) or above "
        "this (below); empty: the raise level itself.",
    )
    rate_limit: float | None = Field(
        None, gt=0, description="rate mode: raise when |d signal / dt| exceeds this, per second."
    )
    clear_fraction: float = Field(
        0.8,
        gt=0,
        le=1,
        description="rate mode: clear when |d signal / dt| is below rate_limit times this.",
    )
    min_duration_s: float = Field(
        0.0,
        ge=0,
        le=MAX_SPAN_S,
        description="Raise only once the condition has held this long, in seconds.",
    )
    command: CommandSpec | None = Field(None, description="A command to send on raising.")
    clear_command: CommandSpec | None = Field(None, description="A command to send on clearing.")
    output: Literal["samples", "changes"] = Field(
        "samples",
        description="samples: `{signal}.alarm` (1 raised, 0 not) at every sample; changes: at "
        "the first sample and when it changes.",
    )

    @model_validator(mode="after")
    def _levels(self) -> TriggerParams:
        if self.mode == "rate":
            if self.rate_limit is None:
                raise ValueError("rate mode needs rate_limit")
            return self
        name = "high" if self.direction == "above" else "low"
        if self.level is None:
            raise ValueError(f"threshold mode, direction {self.direction}, needs {name}")
        if (self.clear_level - self.level) * self.sign > 0:
            raise ValueError(
                f"clear_at ({self.clear_level:g}) must not be {self.direction} "
                f"{name} ({self.level:g})"
            )
        return self

    @property
    def sign(self) -> float:
        return 1.0 if self.direction == "above" else -1.0

    @property
    def level(self) -> float | None:
        return self.high if self.direction == "above" else self.low

    @property
    def clear_level(self) -> float:
        return self.clear_at if self.clear_at is not None else (self.level or 0.0)


def latch(on: Bools, off: Bools, carry: bool) -> Bools:
    """A set/reset flip-flop over samples: on sets, off resets, else the state holds."""
    marks = np.where(on, 1, np.where(off, 0, -1))
    last = np.maximum.accumulate(np.where(marks >= 0, np.arange(marks.shape[0]), -1))
    return np.where(last >= 0, marks[np.maximum(last, 0)] == 1, carry)


class Trigger(Blueprint[TriggerParams]):
    """Alarm trigger (threshold or rate of change)

    Watches one signal. threshold mode: raises when the value goes above `high` (or below
    `low`, direction below) and clears only when it is back past `clear_at` (hysteresis).
    rate mode: raises when |d signal / dt| (between consecutive samples) exceeds `rate_limit`
    per second and clears when it is below `rate_limit * clear_fraction`. With
    `min_duration_s`, the condition must hold that long before the alarm is raised. Raising
    gives an `alarm` event (and `command`, if set), clearing an `alarm_cleared` event (and
    `clear_command`). The output `{signal}.alarm` is 1 while raised, 0 otherwise.
    """

    name = "trigger"
    Params = TriggerParams
    keeps_state = True

    def __init__(self, params: TriggerParams, ctx: Context) -> None:
        super().__init__(params, ctx)
        self._raised = False
        self._since: int | None = None  # when the current run of the raise condition began
        self._last: tuple[int, float] | None = None  # the previous sample, for the rate
        self._started = False

    def inputs(self) -> list[str]:
        return [self.params.signal]

    def outputs(self) -> list[str]:
        return [f"{self.params.signal}.alarm"]

    def process(self, batch: Batch) -> Batch | None:
        x = batch.columns.get(self.params.signal)
        ok = np.isfinite(x) if x is not None else np.zeros(len(batch), dtype=bool)
        if x is None or not ok.any():
            return None
        t, v = batch.times[ok], x[ok]
        metric = self._metric(t, v)
        state = self._states(t, metric)
        before = np.concatenate([[self._raised], state[:-1]])
        for i in np.flatnonzero(state != before):
            self._announce(bool(state[i]), int(t[i]), float(v[i]), float(metric[i]))
        self._raised = bool(state[-1])
        if self.params.output == "samples":
            keep = np.ones(t.shape[0], dtype=bool)
        else:
            keep = state != before
            keep[0] |= not self._started  # the first sample tells the state at the start
        self._started = True
        if not keep.any():
            return None
        return Batch(t[keep], {self.outputs()[0]: state[keep].astype(np.float64)})

    def _metric(self, t: Ints, v: Array) -> Array:
        """What the condition is on: the value, or |d value / dt| per second (NaN if unknown)."""
        if self.params.mode == "threshold":
            return v
        prev_t, prev_v = self._last if self._last is not None else (int(t[0]), np.nan)
        self._last = (int(t[-1]), float(v[-1]))
        dt = np.diff(t, prepend=prev_t) / 1e9
        dv = np.diff(v, prepend=prev_v)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.abs(np.where(dt > 0, dv / dt, np.nan))

    def _states(self, t: Ints, metric: Array) -> Bools:
        """The alarm state after each sample."""
        p = self.params
        if p.mode == "threshold":
            on = (metric - (p.level or 0.0)) * p.sign > 0
            off = (metric - p.clear_level) * p.sign < 0
        else:
            limit = p.rate_limit or 0.0
            on, off = metric > limit, metric < limit * p.clear_fraction
        before = np.concatenate([[self._since is not None], on[:-1]])
        last = np.maximum.accumulate(np.where(on & ~before, np.arange(t.shape[0]), -1))
        carry = self._since if self._since is not None else 0
        since = np.where(last >= 0, t[np.maximum(last, 0)], carry)
        self._since = int(since[-1]) if on[-1] else None
        held = on & (t - since >= round(p.min_duration_s * 1e9))
        return latch(held, off, self._raised)

    def _announce(self, raised: bool, time_ns: int, value: float, metric: float) -> None:
        p = self.params
        s = p.signal
        if p.mode == "rate":
            limit = (p.rate_limit or 0.0) * (1 if raised else p.clear_fraction)
            what = f"{s} changes at {metric:g}/s, " + ("faster than" if raised else "below")
            message = f"{what} {limit:g}/s"
        elif raised:
            message = f"{s} is {value:g}, {p.direction} {p.level:g}"
        else:
            back = "below" if p.direction == "above" else "above"
            message = f"{s} is {value:g}, back {back} {p.clear_level:g}"
        if raised and p.min_duration_s:
            message += f" for {p.min_duration_s:g} s"
        extra = {"rate": metric} if p.mode == "rate" else {}
        kind = "alarm" if raised else "alarm_cleared"
        self.ctx.event(kind, message, time_ns=time_ns, signal=s, value=value, **extra)
        command = p.command if raised else p.clear_command
        if command is not None:
            self.ctx.command(command.name, command.device, **command.params)
