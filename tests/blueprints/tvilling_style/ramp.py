"""Ramp

Gives a value that starts at `start_value` and grows by `slope` per second after
`ramp_delay` seconds, written in the style of the Tvilling digital platform with variables
that carry their own value references. It has no inputs.
"""

# ruff: noqa: UP006, UP035 - the original platform's style (typing.List) on purpose
from typing import List


class Variable:
    def __init__(self, valueReference, name):
        self.valueReference = valueReference
        self.name = name


class P:
    def __init__(self, start_value=0.0, slope=1.0, ramp_delay=0):
        """
        :param start_value: the value before the ramp starts
        :param slope: how much the value grows per second
        :param ramp_delay: the time in seconds before the ramp starts
        """
        self.value = float(start_value)
        self.start_value = float(start_value)
        self.slope = float(slope)
        self.ramp_delay = float(ramp_delay)
        self.inputs = []
        self.outputs = [Variable(7, "ramp"), Variable(3, "seconds")]
        self.t = 0

    def start(self, start_time, slope=None):
        if slope is not None:
            self.slope = float(slope)

    def set_inputs(self, input_refs: List[int], input_values: List[int]):
        pass

    def get_outputs(self, output_refs: List[int]):
        values = {7: self.value, 3: self.t}
        return [values[ref] for ref in output_refs]

    def step(self, t):
        self.t = t
        if t > self.ramp_delay:
            self.value = self.start_value + self.slope * (t - self.ramp_delay)

    def stop(self):
        raise RuntimeError("the ramp was stopped")
