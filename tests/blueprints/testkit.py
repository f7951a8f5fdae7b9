"""Blueprints for the integration tests, loaded from a blueprints folder like a user's would be."""

from __future__ import annotations

import os
import threading

import numpy as np
from pydantic import Field

from twinlink.processors.blueprint import Batch, Blueprint, BlueprintError, Params


class GainParams(Params):
    signals: list[str] = Field(description="signals to scale")
    factor: float = Field(2.0, description="the gain")


class Gain(Blueprint[GainParams]):
    """Multiplies signals by a factor and counts the samples it has seen (its state)."""

    name = "test-gain"
    Params = GainParams
    keeps_state = True

    def start(self) -> None:
        self.seen = 0

    def inputs(self) -> list[str]:
        return list(self.params.signals)

    def outputs(self) -> list[str]:
        return [*self.params.signals, "seen"]

    def process(self, batch: Batch) -> Batch | None:
        first = self.seen
        self.seen += len(batch)
        columns = {
            s: batch.columns[s] * self.params.factor
            for s in self.params.signals
            if s in batch.columns
        }
        columns["seen"] = np.arange(first + 1, self.seen + 1, dtype=np.float64)
        return batch.with_columns(columns)


class HogParams(Params):
    signal: str = "x"
    mb_per_sample: float = 4.0


class Hog(Blueprint[HogParams]):
    """Keeps `mb_per_sample` MB for every sample whose value is above 0 (a leaking model)."""

    name = "test-hog"
    Params = HogParams

    def start(self) -> None:
        self.kept: list[bytearray] = []

    def inputs(self) -> list[str]:
        return [self.params.signal]

    def process(self, batch: Batch) -> Batch | None:
        for value in batch.columns.get(self.params.signal, np.empty(0)).tolist():
            if value > 0:
                self.kept.append(bytearray(b"x" * int(self.params.mb_per_sample * 2**20)))
        return None


class Fussy(Blueprint[HogParams]):
    """Raises on a negative value, as a model with a bug would."""

    name = "test-fussy"
    Params = HogParams

    def inputs(self) -> list[str]:
        return [self.params.signal]

    def process(self, batch: Batch) -> Batch | None:
        if (batch.columns.get(self.params.signal, np.empty(0)) < 0).any():
            raise BlueprintError("negative values are not allowed")
        return batch


class Stuck(Blueprint[HogParams]):
    """Never returns from a batch with a positive value, as a hung model would."""

    name = "test-stuck"
    Params = HogParams

    def inputs(self) -> list[str]:
        return [self.params.signal]

    def process(self, batch: Batch) -> Batch | None:
        if (batch.columns.get(self.params.signal, np.empty(0)) > 0).any():
            threading.Event().wait()  # forever
        return batch


class Snoop(Blueprint[HogParams]):
    """Reports how many TWINLINK_ settings it can see in its environment (there should be none)."""

    name = "test-snoop"
    Params = HogParams

    def inputs(self) -> list[str]:
        return [self.params.signal]

    def process(self, batch: Batch) -> Batch | None:
        seen = sum(1 for k in os.environ if k.startswith("TWINLINK_"))
        return batch.with_columns({"settings_seen": np.full(len(batch), float(seen))})
