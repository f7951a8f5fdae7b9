"""Ten FMUs in a coupled chain: ten instances of tests/fmus/chain_mass, each mass tied to
its neighbours by a spring and a damper (their positions and velocities as inputs), the ends
to walls, against the same chain solved as one 20-state ODE (scipy's solve_ivp, tightly).

The master holds each input over a communication step, so the coupling is first order in
the step: halving the step halves the error, with Jacobi and with Gauss-Seidel alike.
"""

from __future__ import annotations

from itertools import pairwise
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest
from scipy.integrate import solve_ivp

from tests.conftest import FmuFiles
from twinlink.cosim.master import stepping_order
from twinlink.cosim.model import Algorithm, Connection, Instance, Port, System
from twinlink.cosim.runner import Result, run

pytestmark = pytest.mark.integration

N = 10
NAMES = tuple(f"mass{i + 1}" for i in range(N))
# Unequal masses and springs so no symmetry hides an error in the wiring; SPRINGS[i] ties
# mass i - 1 to mass i (SPRINGS[0] and SPRINGS[N] to the walls), DAMPERS likewise.
MASSES = [1.0 + 0.1 * i for i in range(N)]
SPRINGS = [2.0 + 0.2 * ((3 * i) % 5) for i in range(N + 1)]
DAMPERS = [0.05 + 0.01 * (i % 3) for i in range(N + 1)]
X0 = [1.0] + [0.0] * (N - 1)  # the first mass pulled aside, the rest at rest
END = 10.0
Array = npt.NDArray[np.float64]


def chain_system(master: str, step: float) -> System:
    connections: list[Connection] = []
    for left, right in pairwise(NAMES):
        connections += [
            Connection(Port(left, "x"), Port(right, "xl")),
            Connection(Port(left, "v"), Port(right, "vl")),
            Connection(Port(right, "x"), Port(left, "xr")),
            Connection(Port(right, "v"), Port(left, "vr")),
        ]
    parameters: dict[Port, float | int | bool | str] = {}
    for i, name in enumerate(NAMES):
        values = {"m": MASSES[i], "kl": SPRINGS[i], "dl": DAMPERS[i]}
        values |= {"kr": SPRINGS[i + 1], "dr": DAMPERS[i + 1], "x": X0[i]}
        parameters |= {Port(name, variable): value for variable, value in values.items()}
    return System(
        instances=tuple(Instance(name, "chain_mass.fmu") for name in NAMES),
        connections=tuple(connections),
        parameters=parameters,
        log_variables={name: ("x",) for name in NAMES},
        algorithm=Algorithm("fixed-step", step, master=master),  # type: ignore[arg-type]
        end_time=END,
        source="yaml",
    )


@pytest.fixture(scope="module")
def chain(fmu_files: FmuFiles) -> dict[str, Path]:
    return {"chain_mass.fmu": fmu_files("chain_mass")}


def monolithic(times: Array) -> Array:
    """The ten positions (rows) at `times`, the chain solved as one ODE."""
    m, k, d = np.array(MASSES), np.array(SPRINGS), np.array(DAMPERS)

    def f(_t: float, y: Array) -> Array:
        x, v = y[:N], y[N:]
        xe, ve = np.pad(x, 1), np.pad(v, 1)  # the walls at 0, still
        force = k[:-1] * (xe[:-2] - x) + d[:-1] * (ve[:-2] - v)
        force += k[1:] * (xe[2:] - x) + d[1:] * (ve[2:] - v)
        return np.concatenate([v, force / m])

    sol = solve_ivp(f, (0.0, END), X0 + [0.0] * N, t_eval=times, rtol=1e-11, atol=1e-12)
    assert sol.success
    return np.asarray(sol.y[:N], dtype=np.float64)


def positions(result: Result) -> Array:
    return np.vstack([result.column(f"{name}.x") for name in NAMES])


def test_the_ten_fmu_chain_converges_to_the_monolithic_solution_at_first_order(
    chain: dict[str, Path],
) -> None:
    steps = (0.04, 0.02, 0.01)
    for master in ("jacobi", "gauss-seidel"):
        errors = []
        for h in steps:
            result = run(chain_system(master, h), chain)
            assert result.ended == "" and result.column("time")[-1] == END
            x = positions(result)
            reference = monolithic(result.column("time"))
            # the pull travels down the chain: the far end moves, and is right too
            assert np.abs(reference[-1]).max() > 0.1
            errors.append(float(np.abs(x - reference).max()))
        ratios = [errors[0] / errors[1], errors[1] / errors[2]]
        assert all(1.7 < r < 2.5 for r in ratios), (master, errors)
        assert errors[-1] < 0.03, (master, errors)


def test_gauss_seidel_steps_the_chain_from_one_end(chain: dict[str, Path]) -> None:
    """Every pair of neighbours is a cycle; each is broken at its first mass in declared
    order, so the masses step left to right, each seeing its left neighbour's new position."""
    system = chain_system("gauss-seidel", 0.01)
    assert stepping_order(system) == NAMES
    gauss_seidel, jacobi = run(system, chain), run(chain_system("jacobi", 0.01), chain)
    # The first step: the first mass moves the same in both (its right neighbour is still
    # at rest); then a Gauss-Seidel mass sees its left neighbour's new position at once, so
    # the pull reaches the far end in one step, while in Jacobi it has reached the second
    # mass only, from the first one's start.
    after_gs, after_jacobi = positions(gauss_seidel)[:, 1], positions(jacobi)[:, 1]
    assert after_gs[0] == after_jacobi[0] < 1.0
    assert after_jacobi[1] > 0 and np.all(after_jacobi[2:] == 0.0)
    assert np.all(after_gs[1:] > 0)
