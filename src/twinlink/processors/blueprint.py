"""The blueprint API: what a processor runs. This module imports nothing from the server.

A blueprint is a class with typed, documented parameters (a pydantic model, so the API can show
its JSON schema as a form), declared inputs and outputs, and `start` / `process` / `stop`.
It runs inside a worker process; it is handed batches of samples in columns and returns the
batch it made, or None. Events and commands go through its `Context`.

    class Gain(Blueprint[GainParams]):
        "Multiplies each signal by a factor."
        name = "gain"
        Params = GainParams

        def inputs(self) -> list[str]:
            return list(self.params.signals)

        def outputs(self) -> list[str]:
            return list(self.params.signals)

        def process(self, batch: Batch) -> Batch | None:
            return batch.with_columns({s: batch[s] * self.params.factor for s in batch.columns})

Built-in blueprints register through the `twinlink.blueprints` entry point group exactly as
third-party ones do; a `.py` file in the blueprints folder works too.
"""

from __future__ import annotations

import logging
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any, ClassVar, Generic, TypeVar

import numpy as np
from pydantic import AfterValidator, BaseModel, ConfigDict

from twinlink.domain.errors import TwinlinkError

P = TypeVar("P", bound=BaseModel)

# Upper bounds for parameters that are durations and rates, so each is declared with a range
# (in the parameter's JSON schema) and no product of them overflows int64 nanoseconds.
MAX_SPAN_S = 30 * 24 * 3600.0  # a window, a hop, a step or a hold time: 30 days
MAX_RATE_HZ = 1e9  # a sample rate: 1 GHz


class Params(BaseModel):
    """Base for blueprint parameters: unknown keys are an error, so typos are caught."""

    model_config = ConfigDict(extra="forbid")


class NoParams(Params):
    pass


def distinct(names: list[Any]) -> list[Any]:
    """Refuse a list that names something twice (a parameter validator)."""
    if len(set(names)) != len(names):
        raise ValueError("a name is listed twice")
    return names


# A parameter that lists signals (or other names), each at most once.
Names = Annotated[list[str], AfterValidator(distinct)]


class BlueprintError(TwinlinkError):
    """The blueprint cannot go on with these parameters or this input; the message says why."""


@dataclass(slots=True)
class Batch:
    """Samples in columns: `times` in ns since the epoch (int64), one float64 array per signal.

    A sample that lacks a signal has NaN in that column. Booleans arrive as 0.0 / 1.0;
    string values are not passed to processors.
    """

    times: np.ndarray
    columns: dict[str, np.ndarray] = field(default_factory=dict)

    def __len__(self) -> int:
        return int(self.times.shape[0])

    def __getitem__(self, signal: str) -> np.ndarray:
        return self.columns[signal]

    @classmethod
    def of(cls, times: Iterable[int] | np.ndarray, **columns: Iterable[float]) -> Batch:
        return cls(
            np.asarray(times, dtype=np.int64),
            {k: np.asarray(v, dtype=np.float64) for k, v in columns.items()},
        )

    @classmethod
    def empty(cls, signals: Iterable[str] = ()) -> Batch:
        return cls(np.empty(0, np.int64), {s: np.empty(0, np.float64) for s in signals})

    def with_columns(self, columns: Mapping[str, np.ndarray]) -> Batch:
        """A batch with the same times and these columns."""
        return Batch(self.times, dict(columns))

    def take(self, index: np.ndarray | slice) -> Batch:
        return Batch(self.times[index], {k: v[index] for k, v in self.columns.items()})

    @staticmethod
    def concat(batches: list[Batch]) -> Batch:
        if len(batches) == 1:
            return batches[0]
        names: dict[str, None] = {}
        for b in batches:
            names.update(dict.fromkeys(b.columns))
        return Batch(
            np.concatenate([b.times for b in batches]),
            {
                n: np.concatenate([b.columns.get(n, np.full(len(b), np.nan)) for b in batches])
                for n in names
            },
        )


@dataclass(slots=True)
class Event:
    """Something a processor noticed: an alarm raised or cleared, a clamped input, an error."""

    kind: str
    message: str
    time_ns: int = 0
    data: dict[str, Any] = field(default_factory=dict)


@dataclass(slots=True)
class Command:
    """A command for a device of the processor's twin, sent as the processor's owner."""

    name: str
    params: dict[str, Any] = field(default_factory=dict)
    device: str | None = None  # None: the twin's only (or first connected) device


@dataclass(slots=True)
class Context:
    """What a blueprint may use from its surroundings."""

    processor: str
    twin: str
    files: Path  # where uploaded files (FMUs) are found, read-only
    workdir: Path  # a private scratch folder, emptied on each start
    step_spacing_s: float = 0.0  # the `min_step_spacing` rate parameter
    log: logging.Logger = field(default_factory=lambda: logging.getLogger("twinlink.blueprint"))
    events: list[Event] = field(default_factory=list)
    commands: list[Command] = field(default_factory=list)
    # Set by `finish`: the blueprint is done for good (e.g. an FMU that ended its simulation);
    # the worker stops after this batch and the processor is `finished`, not restarted.
    finished: Event | None = None

    def event(self, kind: str, message: str, time_ns: int = 0, **data: Any) -> None:
        self.events.append(Event(kind, message, time_ns, data))

    def finish(self, message: str, **data: Any) -> None:
        self.finished = Event("finished", message, 0, data)

    def command(self, name: str, device: str | None = None, **params: Any) -> None:
        self.commands.append(Command(name, params, device))


class Blueprint(Generic[P]):
    """Base class of blueprints. Subclasses set `name`, `Params` and implement `process`."""

    name: ClassVar[str] = ""
    title: ClassVar[str] = ""
    Params: ClassVar[type[BaseModel]] = NoParams
    # True when `reconfigure` can apply new parameters in place, keeping the state.
    keeps_state: ClassVar[bool] = False

    def __init__(self, params: P, ctx: Context) -> None:
        self.params = params
        self.ctx = ctx

    @classmethod
    def check(cls, params: Any) -> None:
        """Refuse parameters that cannot work before a processor is made with them, so the
        person gets a 422 instead of a worker that fails to start. Cheap checks only (no
        files, no native code); raise BlueprintError saying what to change."""

    @classmethod
    def uploads(cls, params: Any) -> dict[str, dict[str, str]]:
        """The FMUs uploaded to the twin these parameters use, by file name, each with the
        variables named in it and the parameter naming each (`{"Plant.fmu": {"x": "outputs.pos
        (plant.x)"}}`): a processor whose twin lacks one, or whose FMU lacks a variable, is
        refused when made (422). Cheap: no files. (The `fmu` blueprint has its own checks.)"""
        return {}

    def inputs(self) -> list[str]:
        """The signals the blueprint reads, with these parameters."""
        return []

    def outputs(self) -> list[str]:
        """The signals the blueprint writes, with these parameters."""
        return []

    def describe(self) -> dict[str, Any]:
        """Anything worth showing about the running blueprint (an FMU's variables...)."""
        return {}

    def start(self) -> None:
        """Called once before the first batch. Raise BlueprintError if it cannot start."""

    def process(self, batch: Batch) -> Batch | None:
        raise NotImplementedError

    def reconfigure(self, params: P) -> bool:
        """Take new parameters while running. Return False to be restarted with them instead."""
        if not self.keeps_state:
            return False
        self.params = params
        return True

    def stop(self) -> None:
        """Called once at a graceful stop; release files and native resources here."""


def describe_blueprint(cls: type[Blueprint[Any]]) -> dict[str, Any]:
    """A blueprint as the API lists it: name, title, documentation and parameter schema."""
    doc = (cls.__doc__ or "").strip()
    return {
        "name": cls.name,
        "title": cls.title or (doc.splitlines()[0] if doc else cls.name),
        "description": doc,
        "keeps_state": cls.keeps_state,
        "params_schema": cls.Params.model_json_schema(),
    }
