"""A co-simulation Session stepped by its caller: rows step by step, an open end, external
inputs, algebraic loops refused, termination, and everything freed whatever happens."""

from __future__ import annotations

import itertools
import tempfile
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from tests.conftest import FmuFiles
from tests.integration.test_cosim_master import MASS, msd_system
from twinlink.cosim.model import Algorithm, Connection, Instance, Port, System
from twinlink.cosim.runner import run
from twinlink.cosim.session import Session
from twinlink.domain.errors import InvalidInputError

pytestmark = pytest.mark.integration


@pytest.fixture(scope="module")
def msd(fmu_files: FmuFiles) -> dict[str, Path]:
    return {"msd1.fmu": fmu_files("msd_mass"), "msd2.fmu": fmu_files("msd_spring")}


def mass_alone(end: float | None) -> System:
    """The first mass with its coupling force `fk` left unconnected (an external input)."""
    return System(
        instances=(MASS,),
        connections=(),
        parameters={Port(MASS.name, "x1"): 0.5, Port(MASS.name, "c1"): 4.0},
        log_variables={MASS.name: ("x1", "fk")},
        algorithm=Algorithm("fixed-step", 0.01),
        end_time=end,
        source="yaml",
    )


def test_a_session_gives_the_rows_the_batch_run_records(msd: dict[str, Path]) -> None:
    system = replace(msd_system("gauss-seidel", 0.05), end_time=2.0)
    with Session(system, msd) as session:
        rows = [session.initialize()]
        while (row := session.step()) is not None:
            rows.append(row)
        assert session.step() is None and session.ended == "" and session.time == 2.0
        columns = session.columns
    result = run(system, msd)
    assert columns == result.columns
    assert np.array_equal(np.vstack(rows), result.values)
    assert len(rows) == 41 and rows[-1][0] == 2.0


def test_an_open_end_steps_for_as_long_as_asked(msd: dict[str, Path]) -> None:
    """end_time None (mode 3): the FMUs are told no stop time and stepping never ends by
    itself, here well past the FMUs' default experiment's stop time of 10 s."""
    system = replace(msd_system("jacobi", 0.5), end_time=None)
    with Session(system, msd) as session:
        session.initialize()
        rows = [session.step() for _ in range(40)]
    times = [row[0] for row in rows if row is not None]
    assert times == pytest.approx([0.5 * k for k in range(1, 41)]) and len(times) == 40


def test_external_inputs_hold_until_set_again(msd: dict[str, Path]) -> None:
    """fk = c1 x1 holds the mass still where it starts; fk = 0 lets it go."""
    fk = Port(MASS.name, "fk")
    with Session(mass_alone(None), msd, external_inputs=[fk]) as session:
        session.set_inputs({fk: 4.0 * 0.5})
        session.initialize()
        still = [session.step() for _ in range(10)]
        session.set_inputs({fk: 0.0})
        moving = [session.step() for _ in range(10)]
    assert session.columns == ("time", "msd1.m1.x1", "msd1.m1.fk")
    assert all(row is not None and row[1] == 0.5 and row[2] == 2.0 for row in still)
    x = [row[1] for row in moving if row is not None]
    assert len(x) == 10 and x[0] < 0.5 and all(b < a for a, b in itertools.pairwise(x))


def test_an_external_input_not_set_keeps_its_start_value(msd: dict[str, Path]) -> None:
    """fk starts at c1 x1 (the file's parameter), not at 0: the mass stays still."""
    fk = Port(MASS.name, "fk")
    system = mass_alone(1.0)
    system = replace(system, parameters={**system.parameters, fk: 2.0})
    with Session(system, msd, external_inputs=[fk]) as session:
        rows = [session.initialize()]
        while (row := session.step()) is not None:
            rows.append(row)
    values = np.vstack(rows)
    assert len(values) == 101 and np.all(values[:, 1] == 0.5) and np.all(values[:, 2] == 2.0)


def test_an_external_input_must_be_one_the_session_was_given(msd: dict[str, Path]) -> None:
    fk, c1 = Port(MASS.name, "fk"), Port(MASS.name, "c1")
    refused = pytest.raises(InvalidInputError, match=r"msd1\.m1\.c1 is not an external input")
    with Session(mass_alone(1.0), msd, external_inputs=[fk]) as session, refused:
        session.set_inputs({c1: 1.0})
    connected = msd_system("jacobi", 0.1)
    with pytest.raises(InvalidInputError, match="fed by a connection"):
        Session(connected, msd, external_inputs=[Port(MASS.name, "fk")])
    with pytest.raises(InvalidInputError, match=r"msd9\.x names no instance"):
        Session(connected, msd, external_inputs=[Port("msd9", "x")])


def test_the_terminating_step_is_returned_then_none(fmu_files: FmuFiles) -> None:
    system = System(
        instances=(Instance("stair", "Stair.fmu"),),
        connections=(),
        parameters={},
        log_variables={"stair": ("counter",)},
        algorithm=Algorithm("fixed-step", 0.5),
        end_time=None,
        source="yaml",
    )
    with Session(system, {"Stair.fmu": fmu_files("stair3")}) as session:
        session.initialize()
        rows = []
        while (row := session.step()) is not None:
            rows.append(row)
        assert session.ended == (
            "instance 'stair' (stair3.fmu) asked to terminate at t = 9 s "
            "(in the step from t = 8.5 s)"
        )
        assert session.step() is None
    assert rows[-1].tolist() == [9.0, 10.0] and len(rows) == 18


def test_close_frees_everything_and_may_be_called_twice(
    msd: dict[str, Path], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    session = Session(msd_system("jacobi", 0.1), msd)
    session.initialize()
    session.step()
    assert str(tmp_path) in Path("/proc/self/maps").read_text()
    session.close()
    session.close()
    assert list(tmp_path.iterdir()) == []
    assert str(tmp_path) not in Path("/proc/self/maps").read_text()


def test_an_algebraic_loop_is_refused_naming_it_and_nothing_is_left(
    msd: dict[str, Path], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Two springs' forces fed to each other's position inputs: msd_spring's fk depends
    directly on x1 (its ModelStructure says so), so the values form a loop no step breaks."""
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    a, b = Instance("a", "msd2.fmu"), Instance("b", "msd2.fmu")
    system = System(
        instances=(a, b),
        connections=(
            Connection(Port("a", "fk"), Port("b", "x1")),
            Connection(Port("b", "fk"), Port("a", "x1")),
            Connection(Port("a", "x2"), Port("b", "v1")),  # through a state: no loop
        ),
        parameters={},
        log_variables={},
        algorithm=Algorithm("fixed-step", 0.1),
        end_time=1.0,
    )
    with pytest.raises(InvalidInputError) as err:
        Session(system, msd)
    message = str(err.value)
    assert "an algebraic loop" in message and "a.fk -> b.x1 -> b.fk -> a.x1 -> a.fk" in message
    assert "b.v1" not in message
    with pytest.raises(InvalidInputError, match="algebraic loop"):
        run(system, msd)
    assert (
        list(tmp_path.iterdir()) == [] and str(tmp_path) not in Path("/proc/self/maps").read_text()
    )


def test_the_msd_pair_has_no_loop_though_fk_has_feedthrough(msd: dict[str, Path]) -> None:
    """fk depends directly on x1 and v1, but they are the mass's states: the cycle of
    connections is broken there, and the pair runs."""
    result = run(replace(msd_system("jacobi", 0.1), end_time=1.0), msd)
    assert result.column("time")[-1] == 1.0 and result.ended == ""
