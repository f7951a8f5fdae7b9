"""The `cosim` blueprint's pure parts: its parameters checked without a file (the 422 at
create), and the inputs it holds between samples."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from twinlink.cosim._livefeed import typed
from twinlink.cosim.blueprint import CosimBlueprint, CosimParams, checked_system, logged
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


def test_integer_and_boolean_inputs_are_rounded_as_the_fmu_blueprint_sets_them() -> None:
    nan = np.nan
    u = np.array([[0.4, 2.6, -0.2, nan], [nan, -2.5, 0.0, 1.5]])
    typed(u, ["Boolean", "Int8", "Real", "Enumeration"])
    np.testing.assert_array_equal(u, [[1.0, 3.0, -0.2, nan], [nan, -2.0, 0.0, 2.0]])
