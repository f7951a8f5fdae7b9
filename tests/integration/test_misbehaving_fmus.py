"""The misbehaving test FMUs really misbehave: a segfault, a memory leak, error statuses.

The crash and the leak run in a child Python process (a segfault takes the whole process down,
and the leak must be measured in a process of its own); the status FMU runs in this process.
"""

from __future__ import annotations

import json
import math
import signal
import subprocess
import sys
from pathlib import Path

import fmpy
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (
    FMU2Slave,
)

from tests.conftest import FmuFiles
from tests.integration._fmi2_log import Fmi2Log

pytestmark = pytest.mark.integration

# Run in a child: instantiate the FMU, set the given Real variables, initialize, set the input u
# (value reference 0), take `steps` steps of 0.1 s and print the outputs and the RSS as JSON.
CHILD = """
import json, sys
import psutil
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

path, unzipdir, output_vr, u, steps = sys.argv[1:6]
parameters = json.loads(sys.argv[6])
description = read_model_description(path)
fmu = FMU2Slave(
    guid=description.guid,
    unzipDirectory=extract(path, unzipdir=unzipdir),
    modelIdentifier=description.coSimulation.modelIdentifier,
)
fmu.instantiate()
fmu.setupExperiment(startTime=0.0)
for vr, value in parameters.items():
    fmu.setReal([int(vr)], [value])
fmu.enterInitializationMode()
fmu.exitInitializationMode()
fmu.setReal([0], [float(u)])
process = psutil.Process()
rss_before = process.memory_info().rss
for i in range(int(steps)):
    fmu.doStep(i * 0.1, 0.1)
rss_after = process.memory_info().rss
print(json.dumps({"y": fmu.getReal([int(output_vr)])[0], "rss_growth": rss_after - rss_before}))
fmu.terminate()
fmu.freeInstance()
"""

MB = 1024 * 1024


def run_child(
    path: Path,
    unzipdir: Path,
    *,
    output_vr: int,
    u: float,
    steps: int = 1,
    parameters: dict[int, float] | None = None,
) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [
            sys.executable,
            "-c",
            CHILD,
            str(path),
            str(unzipdir),
            str(output_vr),
            repr(u),
            str(steps),
            json.dumps(parameters or {}),
        ],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )


# --------------------------------------------------------------------------------------------
# crash: a real SIGSEGV in fmi2DoStep
# --------------------------------------------------------------------------------------------


def test_the_crash_fmu_segfaults_above_its_threshold(fmu_files: FmuFiles, tmp_path: Path) -> None:
    child = run_child(fmu_files("crash"), tmp_path / "fmu", output_vr=2, u=100.5)
    assert child.returncode == -signal.SIGSEGV, (child.returncode, child.stdout, child.stderr)
    assert child.stdout == ""


@pytest.mark.parametrize(
    ("u", "parameters"),
    [
        (3.0, {}),
        (100.0, {}),  # at the threshold: not above it
        (150.0, {1: 1000.0}),  # above the default, below a raised threshold
    ],
)
def test_the_crash_fmu_doubles_its_input_otherwise(
    fmu_files: FmuFiles, tmp_path: Path, u: float, parameters: dict[int, float]
) -> None:
    child = run_child(fmu_files("crash"), tmp_path / "fmu", output_vr=2, u=u, parameters=parameters)
    assert child.returncode == 0, child.stderr
    assert json.loads(child.stdout)["y"] == 2 * u


# --------------------------------------------------------------------------------------------
# leak: mb_per_step MB per step, touched and never freed
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("u", "parameters", "expected_mb"),
    [
        (1.0, {}, 10 * 8.0),  # the default mb_per_step
        (1.0, {1: 3.0}, 10 * 3.0),
        (0.0, {}, 0.0),  # no leak while u <= 0
    ],
)
def test_the_leak_fmu_grows_the_resident_memory_by_mb_per_step(
    fmu_files: FmuFiles,
    tmp_path: Path,
    u: float,
    parameters: dict[int, float],
    expected_mb: float,
) -> None:
    child = run_child(
        fmu_files("leak"), tmp_path / "fmu", output_vr=2, u=u, steps=10, parameters=parameters
    )
    assert child.returncode == 0, child.stderr
    result = json.loads(child.stdout)
    assert result["y"] == u
    growth_mb = result["rss_growth"] / MB
    if expected_mb:
        assert 0.5 * expected_mb < growth_mb < 1.5 * expected_mb + 4
    else:
        assert growth_mb < 4


# --------------------------------------------------------------------------------------------
# status: fmi2Error with a logged message for u < 0, fmi2Fatal for NaN
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("u", "status", "message"),
    [
        (-2.5, 3, (3, "logStatusError", "negative input u=-2.5 is not allowed")),
        (math.nan, 4, (4, "logStatusFatal", "input u is NaN")),
    ],
)
def test_the_status_fmu_fails_the_step_and_says_why(
    fmu_files: FmuFiles,
    tmp_path: Path,
    u: float,
    status: int,
    message: tuple[int, str, str],
) -> None:
    path = fmu_files("status")
    description = fmpy.read_model_description(str(path))
    fmu = FMU2Slave(
        guid=description.guid,
        unzipDirectory=fmpy.extract(str(path), unzipdir=str(tmp_path / "fmu")),
        modelIdentifier=description.coSimulation.modelIdentifier,
    )
    log = Fmi2Log()
    fmu.instantiate(callbacks=log.callbacks, loggingOn=True)
    try:
        fmu.setupExperiment(startTime=0.0)
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()

        fmu.setReal([0], [1.25])
        fmu.doStep(0.0, 0.1)
        assert fmu.getReal([1]) == [1.25]
        assert log.messages == []

        fmu.setReal([0], [u])
        with pytest.raises(FMICallException) as caught:
            fmu.doStep(0.1, 0.1)
        assert caught.value.function == "fmi2DoStep"
        assert caught.value.status == status
        assert log.messages == [message]
    finally:
        fmu.freeInstance()
