"""Exponential smoothing

A first order low-pass filter for one measurement, written the way blueprints for the
Tvilling digital platform are written: the smoothed value follows the measurement with the
given time constant.
"""

# ruff: noqa: UP006, UP035 - the original platform's style (typing.List) on purpose
import math
from typing import List


class P:
    input_names = ("measurement",)
    output_names = ("smoothed", "rate", "steps")

    def __init__(self, time_constant=0.5, gain=1, mode="ema", warmup: int = 0, limit=1e9):
        """
        :param time_constant: the time constant of the filter in seconds
        :param gain: the factor the smoothed value is multiplied with
        :param mode: 'ema' to smooth, 'hold' to pass the latest measurement through
        :param warmup: the number of steps to take before giving outputs
        :param limit: a measurement beyond this is an error
        """
        if float(time_constant) <= 0:
            raise ValueError("time_constant must be positive")
        self.time_constant = float(time_constant)
        self.gain = float(gain)
        self.mode = mode
        self.warmup = int(warmup)
        self.limit = float(limit)
        self.measurement = 0.0
        self.smoothed = None
        self.rate = 0.0
        self.steps = 0
        self.t = 0

    def start(self, start_time, initial=None):
        self.t = start_time
        self.smoothed = initial

    def set_inputs(self, input_refs: List[int], input_values: List[int]):
        for i in range(len(input_refs)):
            if input_refs[i] == 0:
                if abs(input_values[i]) > self.limit:
                    raise ValueError(f"measurement {input_values[i]} is beyond {self.limit}")
                self.measurement = input_values[i]

    def get_outputs(self, output_refs: List[int]):
        if self.steps <= self.warmup or self.smoothed is None:
            return None
        outputs = [self.smoothed * self.gain, self.rate, self.steps]
        return [outputs[ref] for ref in output_refs]

    def get_time(self):
        return self.t

    def step(self, t):
        dt = t - self.t
        self.t = t
        if self.smoothed is None or self.mode == "hold":
            new = self.measurement
        else:
            alpha = 1 - math.exp(-dt / self.time_constant)
            new = self.smoothed + alpha * (self.measurement - self.smoothed)
        if self.smoothed is not None and dt > 0:
            self.rate = (new - self.smoothed) / dt
        self.smoothed = new
        self.steps += 1
