"""The same FMI 2 SSP archive (the msd pair of tests/fmus) run by twinlink and by FMPy's
`simulate_ssp` (fmpy/ssp/simulation.py, which `python -m fmpy.ssp.simulate` calls; that
module parses sys.argv when imported, so the function is taken from where it lives).

What FMPy's master does, read from its source (FMPy 0.3.32), and how ours is run to match:
- Jacobi: every component steps from the connector values of the previous step (set
  inputs, doStep, get outputs, one component after another), the connections applied only
  after all stepped. Ours runs with the jacobi master.
- No exchange at initialization: every connector starts at 0.0, so each input's first
  step sees 0.0, not the connected output. Ours copies the outputs at initialization (as
  Maestro does): the system is chosen so every connected output is 0 at the start (both
  masses at rest position, the second one moving, no coupling damper), where both agree.
- Parameters only from the `parameter_set` argument (the SSD's bindings are not applied):
  it gets the archive's .ssv, which our reader applies as the system's binding.
- Time advances by `time += step_size` while `time < stop_time`: the step is a power of two
  so the sum is exact and the number of steps the same (ours computes start + k h).
- Its row for a step is [the step's start time, the values after the step]; ours is
  [the step's end time, the same values], plus a first row at the start time.
"""

from __future__ import annotations

import zipfile
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from fmpy.ssp.simulation import simulate_ssp  # type: ignore[import-untyped]
from fmpy.ssp.ssd import read_ssv  # type: ignore[import-untyped]

from tests.conftest import FmuFiles
from twinlink.cosim.runner import run
from twinlink.cosim.ssp import extract, read_ssp

pytestmark = pytest.mark.integration

STEP, END = 2.0**-6, 10.0  # 640 steps
PARAMETERS = {
    "mass.x1": 0.0,
    "mass.v1": 0.0,
    "mass.m1": 1.0,
    "mass.c1": 1.5,
    "mass.d1": 0.1,
    "spring.x2": 0.0,
    "spring.v2": 1.0,  # the kick that starts it all
    "spring.m2": 2.0,
    "spring.c2": 3.0,
    "spring.d2": 0.05,
    "spring.cc": 2.0,
    "spring.dc": 0.0,
}
RECORDED = ("mass.x1", "mass.v1", "spring.x2", "spring.v2", "spring.fk")

SSD = """<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription
    xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon"
    xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription"
    version="1.0" name="msd" generationTool="twinlink tests">
  <ssd:System name="msd">
    <ssd:ParameterBindings>
      <ssd:ParameterBinding source="resources/params.ssv"/>
    </ssd:ParameterBindings>
    <ssd:Elements>
      <ssd:Component name="mass" type="application/x-fmu-sharedlibrary"
          source="resources/msd_mass.fmu">
        <ssd:Connectors>
          <ssd:Connector name="fk" kind="input"><ssc:Real/></ssd:Connector>
          <ssd:Connector name="x1" kind="output"><ssc:Real/></ssd:Connector>
          <ssd:Connector name="v1" kind="output"><ssc:Real/></ssd:Connector>
        </ssd:Connectors>
      </ssd:Component>
      <ssd:Component name="spring" type="application/x-fmu-sharedlibrary"
          source="resources/msd_spring.fmu">
        <ssd:Connectors>
          <ssd:Connector name="x1" kind="input"><ssc:Real/></ssd:Connector>
          <ssd:Connector name="v1" kind="input"><ssc:Real/></ssd:Connector>
          <ssd:Connector name="fk" kind="output"><ssc:Real/></ssd:Connector>
          <ssd:Connector name="x2" kind="output"><ssc:Real/></ssd:Connector>
          <ssd:Connector name="v2" kind="output"><ssc:Real/></ssd:Connector>
        </ssd:Connectors>
      </ssd:Component>
    </ssd:Elements>
    <ssd:Connections>
      <ssd:Connection startElement="mass" startConnector="x1" endElement="spring"
          endConnector="x1"/>
      <ssd:Connection startElement="mass" startConnector="v1" endElement="spring"
          endConnector="v1"/>
      <ssd:Connection startElement="spring" startConnector="fk" endElement="mass"
          endConnector="fk"/>
    </ssd:Connections>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0" stopTime="{end}"/>
</ssd:SystemStructureDescription>
"""

SSV = """<?xml version="1.0" encoding="UTF-8"?>
<ssv:ParameterSet xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues"
    version="1.0" name="msd">
  <ssv:Parameters>
{parameters}
  </ssv:Parameters>
</ssv:ParameterSet>
"""


@pytest.fixture(scope="module")
def archive(fmu_files: FmuFiles, tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("ssp") / "msd.ssp"
    parameters = "\n".join(
        f'    <ssv:Parameter name="{name}"><ssv:Real value="{value!r}"/></ssv:Parameter>'
        for name, value in PARAMETERS.items()
    )
    with zipfile.ZipFile(path, "w") as zf:
        zf.writestr("SystemStructure.ssd", SSD.format(end=END))
        zf.writestr("resources/params.ssv", SSV.format(parameters=parameters))
        zf.write(fmu_files("msd_mass"), "resources/msd_mass.fmu")
        zf.write(fmu_files("msd_spring"), "resources/msd_spring.fmu")
    return path


def test_our_run_of_an_ssp_agrees_with_fmpys_simulate_ssp(archive: Path, tmp_path: Path) -> None:
    system = read_ssp(archive, step_size=STEP)
    assert system.end_time == END and system.algorithm.size == STEP
    system = replace(
        system,
        algorithm=replace(system.algorithm, master="jacobi"),
        log_variables={"mass": ("x1", "v1"), "spring": ("x2", "v2", "fk")},
    )
    folder = tmp_path / "ssp"
    extract(archive, folder)
    fmus = {i.fmu: folder / i.fmu for i in system.instances}
    ours = run(system, fmus)

    theirs = simulate_ssp(
        str(archive),
        stop_time=END,
        step_size=STEP,
        parameter_set=read_ssv(str(archive), resource="resources/params.ssv"),
    )
    assert len(theirs) == len(ours.values) - 1 == round(END / STEP)
    assert np.array_equal(theirs["time"] + STEP, ours.column("time")[1:])
    for column in RECORDED:
        assert ours.column(column)[0] == PARAMETERS.get(column, 0.0)  # fk = cc (x2 - x1) = 0
        mine, fmpy_values = ours.column(column)[1:], theirs[column]
        assert np.abs(mine - fmpy_values).max() <= 1e-9, column  # 0.0 on the day it was written
    # and it is a real run: the kick reached the first mass through the coupling
    assert np.abs(ours.column("mass.x1")).max() > 0.1
