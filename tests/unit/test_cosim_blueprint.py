"""The `cosim` blueprint's pure parts: its parameters checked without a file (the 422 at
create), and the inputs it holds between samples."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from twinlink.cosim.blueprint import CosimBlueprint, CosimParams, _held, checked_system, logged
from twinlink.cosim.model import Port
from twinlink.processors.blueprint import BlueprintError

SYSTEM: dict[str, Any] = {
    "instances": {"plant": "Plant.fmu", "plant.ctrl": "Ctrl.fmu"},
    "connections": {"plant.ctrl.u": "plant.u"},
    "log": {"plant": ["y"]},
    "algorithm": {"type": "fixed-step", "size": 0.01},
}


def params(**changes: Any) -> CosimParams:
    base = {"system": SYSTEM, "inputs": {"meas": "plant.ctrl.y"}, "outputs": {"u": "plant.u"}}
    return CosimParams.model_validate(base | changes)


def test_ports_split_at_the_longest_instance_name() -> None:
    _, inputs, outputs = checked_system(params(outputs={"u": "plant.u", "v": "plant.ctrl.v"}))
    assert inputs == {"meas": Port("plant.ctrl", "y")}
    assert outputs == {"u": Port("plant", "u"), "v": Port("plant.ctrl", "v")}


@pytest.mark.parametrize(
    ("change", "named"),
    [
        ({"inputs": {"meas": "plant.u"}}, "inputs: meas (plant.u): a connection of the system"),
        ({"inputs": {"meas": "pump.y"}}, "inputs.meas: 'pump.y' is not instance.variable"),
        ({"outputs": {"u": "plant"}}, "outputs.u: 'plant' is not instance.variable"),
        ({"system": {**SYSTEM, "algorithm": {"type": "fixed-step", "size": 10**400}}},
         "system: algorithm.size: is too large a time"),
        ({"system": {**SYSTEM, "instances": {"plant": "plant"}}}, "'plant' is not the file name"),
    ],
)  # fmt: skip
def test_a_bad_port_or_system_is_refused_naming_its_key(change: dict[str, Any], named: str) -> None:
    with pytest.raises(BlueprintError) as err:
        CosimBlueprint.check(params(**change))
    assert named in str(err.value)


def test_the_outputs_are_recorded_once_beside_the_logged_variables() -> None:
    system, _, outputs = checked_system(params(outputs={"y": "plant.y", "u": "plant.u"}))
    assert logged(system, list(outputs.values())).log_variables == {"plant": ("y", "u")}


def test_an_input_holds_its_latest_value_across_samples_and_batches() -> None:
    nan = np.nan
    u = np.array([[nan, 1.0], [2.0, nan], [nan, nan], [3.0, 4.0]])
    held = _held(u, np.array([nan, 0.5]))
    np.testing.assert_array_equal(held, [[nan, 1.0], [2.0, 1.0], [2.0, 1.0], [3.0, 4.0]])
    assert _held(np.empty((2, 0)), np.empty(0)).shape == (2, 0)
