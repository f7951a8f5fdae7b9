"""Kinds of instance in a co-simulation, on real FMUs: a model exchange FMU under FMPy's
solvers (msd_mass_me, FMI 2; the lag of _fmu_c.py, FMI 2 and 3, with a state event)
coupled with co-simulation FMUs, against the monolithic ODE; FMU state for a rollback;
isolated instances (a C FMU as in process, two Python FMUs each in a process of its own, a
segfault and a kill failing the run by name); the YAML form's `isolated`; and a Python FMU
whose `python_requirements` give it a virtualenv of its own (pip from the package index)."""

from __future__ import annotations

import math
import os
import re
import signal
import subprocess
import sys
import zipfile
from dataclasses import replace
from pathlib import Path

import numpy as np
import psutil
import pytest
from scipy.integrate import solve_ivp

from tests.conftest import FmuFiles
from tests.integration import _fmu_c
from twinlink.cosim.isolated import IsolatedSlave
from twinlink.cosim.kinds import kind_of, open_slave
from twinlink.cosim.mexslave import MeSlave, Solver
from twinlink.cosim.model import Algorithm, Connection, Instance, Port, System
from twinlink.cosim.session import Session
from twinlink.cosim.slaves import CosimRunError, Slave
from twinlink.cosim.yamlform import read_yaml, to_yaml
from twinlink.domain.errors import InvalidInputError
from twinlink.processors.fmuinfo import inspect_fmu

pytestmark = pytest.mark.integration

MASS, SPRING = Instance("m", "mass.fmu"), Instance("s", "spring.fmu")
# msd_mass(_me) and msd_spring: lightly damped, coupled more stiffly than tied to the walls
PARAMS = {"m1": 1.0, "c1": 1.0, "d1": 0.1, "m2": 2.0, "c2": 3.0, "d2": 0.05, "cc": 2.0, "dc": 0.2}
END = 10.0


def msd_system(step: float, mass: Instance = MASS) -> System:
    parameters: dict[Port, float | int | bool | str] = {
        Port(mass.name, "x1"): 1.0,
        **{Port(mass.name, n): PARAMS[n] for n in ("m1", "c1", "d1")},
        **{Port(SPRING.name, n): PARAMS[n] for n in ("m2", "c2", "d2", "cc", "dc")},
    }
    return System(
        instances=(mass, SPRING),
        connections=(
            Connection(Port(mass.name, "x1"), Port(SPRING.name, "x1")),
            Connection(Port(mass.name, "v1"), Port(SPRING.name, "v1")),
            Connection(Port(SPRING.name, "fk"), Port(mass.name, "fk")),
        ),
        parameters=parameters,
        log_variables={mass.name: ("x1",), SPRING.name: ("x2",)},
        algorithm=Algorithm("fixed-step", step),
        end_time=END,
        source="yaml",
    )


def rows_of(session: Session) -> np.ndarray:
    rows = [session.initialize()]
    while (row := session.step()) is not None:
        rows.append(row)
    return np.array(rows)


def monolithic(times: np.ndarray) -> np.ndarray:
    """x1 and x2 of the two masses solved as one ODE, tightly."""
    p = PARAMS

    def f(_t: float, y: np.ndarray) -> list[float]:
        x1, v1, x2, v2 = y
        fk = p["cc"] * (x2 - x1) + p["dc"] * (v2 - v1)
        return [v1, (fk - p["c1"] * x1 - p["d1"] * v1) / p["m1"],
                v2, (-fk - p["c2"] * x2 - p["d2"] * v2) / p["m2"]]  # fmt: skip

    sol = solve_ivp(f, (0.0, END), [1.0, 0.0, 0.0, 0.0], t_eval=times, rtol=1e-11, atol=1e-12)
    assert sol.success
    return np.vstack([sol.y[0], sol.y[2]]).T


@pytest.fixture(scope="module")
def msd(fmu_files: FmuFiles) -> dict[str, Path]:
    return {
        "mass.fmu": fmu_files("msd_mass"),
        "mass_me.fmu": fmu_files("msd_mass_me"),
        "spring.fmu": fmu_files("msd_spring"),
    }


# -- model exchange -------------------------------------------------------------------------


def test_a_model_exchange_only_fmu_runs_under_a_solver(msd: dict[str, Path]) -> None:
    me = inspect_fmu(msd["mass_me.fmu"])
    assert kind_of(me, msd["mass_me.fmu"]) == "model-exchange"
    assert kind_of(inspect_fmu(msd["mass.fmu"]), msd["mass.fmu"]) == "co-simulation"


def test_model_exchange_coupled_with_co_simulation_is_close_to_the_monolithic_ode(
    msd: dict[str, Path],
) -> None:
    mass_me = Instance("m", "mass_me.fmu")
    errors = {}
    for h in (0.02, 0.01):
        with Session(msd_system(h, mass_me), msd) as session:
            assert isinstance(session._slaves[0], MeSlave)  # msd_mass_me has no doStep
            rows = rows_of(session)
        assert rows[-1, 0] == pytest.approx(END)
        errors[h] = float(np.max(np.abs(rows[:, 1:] - monolithic(rows[:, 0]))))
    # the coupling (inputs held over a step) dominates: first order, as with co-simulation
    assert errors[0.01] < 0.05
    assert 1.6 < errors[0.02] / errors[0.01] < 2.5, errors
    # and the same run with msd_mass's own RK4 substeps gives nearly the same rows
    with Session(msd_system(0.01), msd) as session:
        assert isinstance(session._slaves[0], Slave)
        cs = rows_of(session)
    with Session(msd_system(0.01, mass_me), msd) as session:
        me_rows = rows_of(session)
    assert np.max(np.abs(cs - me_rows)) < 1e-4


@pytest.mark.parametrize(("version", "solver"), [(2, "CVode"), (3, "CVode"), (2, "Euler")])
def test_the_lag_as_model_exchange_steps_its_ode_and_its_state_event(
    tmp_path: Path, version: int, solver: Solver
) -> None:
    """der(y) = (u - y) / tau: with u held at 1 from y = 0, y = 1 - exp(-t); the output n
    counts crossings of y = 0.5, a state event the solver finds (at t = ln 2)."""
    fmu = _fmu_c.build_fmu(tmp_path, version)
    slave = MeSlave("lag", fmu, tmp_path / "x", solver=solver, solver_step=1e-4)
    try:
        u, _ = slave.port("u", into=True)
        y, yi = slave.port("y", into=False)
        n, ni = slave.port("n", into=False)
        slave.bind()
        slave.enter_initialization(0.0, None)
        slave.exit_initialization()
        u.buffer[0] = 1.0
        t, seen = 0.0, []
        for _ in range(10):
            slave.write()
            t = slave.step(t, 0.1)
            slave.read()
            seen.append((t, float(y.buffer[yi]), int(n.buffer[ni])))
    finally:
        slave.close()
    for time, value, crossings in seen:
        assert value == pytest.approx(1 - math.exp(-time), abs=1e-4 if solver == "CVode" else 1e-3)
        assert crossings == (1 if time > math.log(2) else 0), seen
    assert seen[-1][0] == pytest.approx(1.0)


def me_only(fmu: Path) -> Path:
    """A copy of `fmu` without its <CoSimulation> element: a model exchange only FMU."""
    out = fmu.with_name(f"{fmu.stem}_me.fmu")
    with zipfile.ZipFile(fmu) as src, zipfile.ZipFile(out, "w") as dst:
        for item in src.infolist():
            data = src.read(item)
            if item.filename == "modelDescription.xml":
                data = re.sub(rb"<CoSimulation [^>]*/>", b"", data)
            dst.writestr(item, data)
    return out


@pytest.mark.parametrize("version", [2, 3])
def test_open_slave_runs_a_model_exchange_only_fmu_under_a_solver(
    tmp_path: Path, version: int
) -> None:
    both = _fmu_c.build_fmu(tmp_path, version)
    for fmu, kind in ((both, Slave), (me_only(both), MeSlave)):
        slave = open_slave(Instance("l", "l.fmu"), fmu, tmp_path / fmu.stem)
        try:
            assert type(slave) is kind
        finally:
            slave.close()


@pytest.mark.parametrize("kind", [MeSlave, IsolatedSlave])
def test_a_model_exchange_instance_rolls_back_to_a_saved_state(
    msd: dict[str, Path], tmp_path: Path, kind: type[MeSlave | IsolatedSlave]
) -> None:
    """In this process, and in a process of its own (whose child runs a MeSlave)."""
    slave = kind("m", msd["mass_me.fmu"], tmp_path)
    x, xi = slave.port("x1", into=False)

    def step(t: float) -> tuple[float, float]:
        reached = slave.step(t, 0.5)
        slave.read()
        return reached, float(x.buffer[xi])

    try:
        assert slave.can_rollback  # canGetAndSetFMUstate="true"
        slave.bind()
        slave.enter_initialization(0.0, 10.0)
        slave.exit_initialization()
        t = slave.step(0.0, 0.5)
        state = slave.save_state()
        first = step(t)
        step(first[0])  # further on, then back
        slave.restore_state(state)
        again = step(t)
        slave.free_state(state)
    finally:
        slave.close()
    assert first[0] == again[0] == pytest.approx(1.0)
    assert again[1] == first[1]  # the same step again: the solver restarted at the save
    assert first[1] == pytest.approx(math.cos(1.0), abs=1e-5)  # x1 = cos t, m1 = c1 = 1


def test_open_slave_names_an_fmu_it_cannot_read(tmp_path: Path) -> None:
    bad = tmp_path / "bad.fmu"
    bad.write_bytes(b"not a zip")
    with pytest.raises(CosimRunError, match=r"instance 'b' \(bad.fmu\)"):
        open_slave(Instance("b", "bad.fmu"), bad, tmp_path / "b")


# -- isolated instances ---------------------------------------------------------------------

SCALE = """\
import os

from pythonfmu import Fmi2Causality, Fmi2Initial, Fmi2Slave, Fmi2Variability, Real


class {name}(Fmi2Slave):
    author = "twinlink tests"
    description = "y = k u, and the pid of the process it runs in"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.u, self.y, self.k, self.pid = 0.0, 0.0, 1.0, float(os.getpid())
        self.register_variable(Real("u", causality=Fmi2Causality.input))
        self.register_variable(Real("y", causality=Fmi2Causality.output, initial=Fmi2Initial.exact))
        self.register_variable(
            Real("pid", causality=Fmi2Causality.output, initial=Fmi2Initial.exact)
        )
        self.register_variable(
            Real("k", causality=Fmi2Causality.parameter, variability=Fmi2Variability.tunable)
        )

    def do_step(self, current_time, step_size):
        self.y = self.k * self.u
        return True
"""


@pytest.fixture(scope="module")
def scales(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """ScaleA.fmu and ScaleB.fmu: two Python FMUs (pythonfmu), y = k u."""
    folder = tmp_path_factory.mktemp("scales")
    built = {}
    for name in ("ScaleA", "ScaleB"):
        source = folder / f"{name}.py"
        source.write_text(SCALE.format(name=name))
        subprocess.run(
            [sys.executable, "-m", "pythonfmu", "build", "-f", str(source), "-d", str(folder)],
            check=True, capture_output=True,
        )  # fmt: skip
        built[f"{name}.fmu"] = folder / f"{name}.fmu"
    return built


def scaled_system(mass: Instance = MASS) -> System:
    """The mass's x1 scaled by a (k 2) then b (k 3), Gauss-Seidel: b.y = 6 x1 at each row."""
    a, b = Instance("a", "ScaleA.fmu"), Instance("b", "ScaleB.fmu")
    return System(
        instances=(mass, a, b),
        connections=(
            Connection(Port(mass.name, "x1"), Port("a", "u")),
            Connection(Port("a", "y"), Port("b", "u")),
        ),
        parameters={Port("a", "k"): 2.0, Port("b", "k"): 3.0},
        log_variables={mass.name: ("x1",), "a": ("pid",), "b": ("y", "pid")},
        algorithm=Algorithm("fixed-step", 0.01),
        end_time=1.0,
        source="yaml",
    )


def test_an_isolated_instance_gives_the_rows_it_gives_in_process(msd: dict[str, Path]) -> None:
    mass, spring = Instance("m", "mass.fmu", isolated=True), Instance("s", "spring.fmu", True)
    system = replace(msd_system(0.01), instances=(mass, spring))
    with Session(system, msd) as session:
        assert [type(s) for s in session._slaves] == [IsolatedSlave, IsolatedSlave]
        pids = [s.pid for s in session._slaves]  # type: ignore[attr-defined]
        isolated = rows_of(session)
    assert not any(psutil.pid_exists(pid) for pid in pids)  # closed: their processes ended
    with Session(msd_system(0.01), msd) as session:
        in_process = rows_of(session)
    np.testing.assert_array_equal(isolated, in_process)


def test_two_python_fmus_run_each_in_its_own_process(
    msd: dict[str, Path], scales: dict[str, Path]
) -> None:
    assert kind_of(inspect_fmu(scales["ScaleA.fmu"]), scales["ScaleA.fmu"]) == "python"
    with Session(scaled_system(), msd | scales) as session:
        kinds = {s.name: type(s) for s in session._slaves}
        rows = rows_of(session)
        columns = session.columns
    assert kinds == {"m": Slave, "a": IsolatedSlave, "b": IsolatedSlave}
    col = {name: k for k, name in enumerate(columns)}
    np.testing.assert_allclose(rows[1:, col["b.y"]], 6 * rows[1:, col["m.x1"]], rtol=1e-12)
    pid_a, pid_b = set(rows[:, col["a.pid"]]), set(rows[:, col["b.pid"]])
    assert len(pid_a) == len(pid_b) == 1 and pid_a != pid_b  # one process each, all along
    assert os.getpid() not in pid_a | pid_b


def test_a_crashing_isolated_fmu_fails_the_run_naming_it(
    msd: dict[str, Path], fmu_files: FmuFiles
) -> None:
    """crash.fmu segfaults once u > threshold; u is the lone mass's v1 = -sin t, above 0.5
    from t = 7 pi / 6."""
    crash = Instance("c", "crash.fmu", isolated=True)
    system = System(
        instances=(MASS, crash),
        connections=(Connection(Port("m", "v1"), Port("c", "u")),),
        parameters={Port("c", "threshold"): 0.5},
        log_variables={"m": ("x1",)},
        algorithm=Algorithm("fixed-step", 0.01),
        end_time=10.0,
        source="yaml",
    )
    session = Session(system, msd | {"crash.fmu": fmu_files("crash")})
    with session:
        rows = [session.initialize()]
        with pytest.raises(CosimRunError) as caught:
            while (row := session.step()) is not None:
                rows.append(row)
    assert "instance 'c' (crash.fmu)" in str(caught.value)
    assert "killed by SIGSEGV" in str(caught.value)
    assert rows[-1][0] == pytest.approx(7 * math.pi / 6, abs=0.02)  # the rows before it, kept


def test_a_child_killed_mid_run_fails_the_run_and_leaves_no_process(
    msd: dict[str, Path], scales: dict[str, Path]
) -> None:
    session = Session(scaled_system(), msd | scales)
    with session:
        session.initialize()
        for _ in range(5):
            assert session.step() is not None
        victim = next(s for s in session._slaves if s.name == "b")
        other = next(s for s in session._slaves if s.name == "a")
        os.kill(victim.pid, signal.SIGKILL)  # type: ignore[attr-defined]
        with pytest.raises(CosimRunError, match=r"instance 'b' \(ScaleB.fmu\).*SIGKILL"):
            session.step()
    assert not psutil.pid_exists(other.pid)  # type: ignore[attr-defined]


# -- the YAML form --------------------------------------------------------------------------

YAML = """\
instances:
  a: a.fmu
  b: {fmu: b.fmu, isolated: true}
algorithm: {type: fixed-step, size: 0.1}
end_time: 1
"""


def test_the_yaml_form_reads_and_writes_an_isolated_instance() -> None:
    system = read_yaml("c.yaml", text=YAML)
    assert system.instances == (Instance("a", "a.fmu"), Instance("b", "b.fmu", isolated=True))
    assert read_yaml("again.yaml", text=to_yaml(system)) == system


@pytest.mark.parametrize(
    ("entry", "message"),
    [
        ("{fmu: b.fmu, isolated: yes please}", "line 3, column 19: instances.b.isolated: is not"),
        ("{fmu: b.fmu, isolate: true}", "instances.b: has unknown keys \\(isolate\\)"),
        ("{isolated: true}", "instances.b: is not an FMU path"),
    ],
)
def test_the_yaml_form_refuses_a_wrong_instance_entry(entry: str, message: str) -> None:
    with pytest.raises(InvalidInputError, match=message):
        read_yaml("c.yaml", text=YAML.replace("{fmu: b.fmu, isolated: true}", entry))
