"""A generic signal source: sine, step, noise and random walk signals at any rate."""

from __future__ import annotations

import math
import random
from dataclasses import dataclass, field
from typing import Literal

Shape = Literal["sine", "step", "noise", "walk"]
SHAPES: tuple[Shape, ...] = ("sine", "step", "noise", "walk")


@dataclass
class GenericModel:
    signals: int = 4
    shape: Shape | Literal["mixed"] = "mixed"
    period_s: float = 10.0
    amplitude: float = 1.0
    noise: float = 0.05
    rng: random.Random = field(default_factory=random.Random)
    _time: float = 0.0
    _walk: list[float] = field(default_factory=list)

    def names(self) -> list[str]:
        return [f"{self._shape_of(i)}_{i}" for i in range(self.signals)]

    def step(self, dt: float) -> dict[str, float]:
        self._time += dt
        if len(self._walk) != self.signals:
            self._walk = [0.0] * self.signals
        out = {}
        for i, name in enumerate(self.names()):
            out[name] = self._value(i, dt)
        return out

    def _shape_of(self, i: int) -> Shape:
        return SHAPES[i % len(SHAPES)] if self.shape == "mixed" else self.shape

    def _value(self, i: int, dt: float) -> float:
        phase = 2 * math.pi * (self._time / self.period_s + i / max(self.signals, 1))
        shape = self._shape_of(i)
        if shape == "sine":
            base = self.amplitude * math.sin(phase)
        elif shape == "step":
            base = self.amplitude if math.sin(phase) >= 0 else -self.amplitude
        elif shape == "noise":
            base = self.rng.gauss(0.0, self.amplitude)
        else:
            self._walk[i] += self.rng.gauss(0.0, self.amplitude * math.sqrt(dt))
            base = self._walk[i]
        return base + (self.rng.gauss(0.0, self.noise) if self.noise else 0.0)
