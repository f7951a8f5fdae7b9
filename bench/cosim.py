"""Co-simulation benchmark: macro steps per second of twinlink's master (a Session stepped
as runner.run steps it: a row kept per step) on the 2-FMU mass-spring-damper pair and the
10-FMU chain of tests/fmus, Gauss-Seidel and Jacobi; in the same run, the same FMUs driven by
FMPy's FMU2Slave in a plain Python loop (bench/_cosim_plain.py) as the reference, and each
FMU's doStep alone as the floor. Then real-time pacing at 1 kHz (cosim/pacing.run_paced):
how late each step starts.

    .venv/bin/python bench/cosim.py            # about 1 minute
    .venv/bin/python bench/cosim.py --quick    # about 15 s

Prints a table (each figure beside its goal) and writes JSON to
bench/results/cosim-<UTC timestamp>.json (or --json PATH). Both runs of a case must end on
the same values: the reference does the same work, or the run fails (exit 1).
"""

from __future__ import annotations

import argparse
import contextlib
import os
import statistics
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from itertools import pairwise
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _cosim_plain import PlainLoop
from _report import ROOT, machine_info, write_json
from twinlink.cosim.model import Algorithm, Connection, Instance, Port, System
from twinlink.cosim.pacing import run_paced
from twinlink.cosim.session import Session
from twinlink.processors.fmubuild import build_fmu

GOAL_STEPS_PER_S = 20_000  # the 2-FMU system, ours
GOAL_RATIO = 1.2  # ours' time per step over the plain loop's, at most
GOAL_P99_MS = 1.0  # real-time start jitter at 1 kHz
H = 0.001  # 1 kHz: the step of every case, so the paced run is the same system
Params = dict[Port, float | int | bool | str]


def msd_system(master: str, steps: int) -> System:
    """The mass-spring-damper pair of tests/integration/test_cosim_master.py."""
    mass, spring = "msd1.m1", "msd2.m2"
    values = {"m1": 1.0, "c1": 1.0, "d1": 0.1, "m2": 2.0, "c2": 3.0, "d2": 0.05}
    params: Params = {Port(mass, "x1"): 1.0}
    params |= {Port(mass if k.endswith("1") else spring, k): v for k, v in values.items()}
    params |= {Port(spring, "cc"): 2.0, Port(spring, "dc"): 0.2}
    wires = [((mass, "x1"), (spring, "x1")), ((mass, "v1"), (spring, "v1"))]
    wires += [((spring, "fk"), (mass, "fk"))]
    return System(
        instances=(Instance(mass, "msd_mass.fmu"), Instance(spring, "msd_spring.fmu")),
        connections=tuple(Connection(Port(*a), Port(*b)) for a, b in wires),
        parameters=params,
        log_variables={mass: ("x1", "v1"), spring: ("x2", "fk")},
        algorithm=Algorithm("fixed-step", H, master=master),  # type: ignore[arg-type]
        end_time=steps * H,
        source="yaml",
    )


def chain_system(master: str, steps: int, n: int = 10) -> System:
    """n masses in a row, each tied to its neighbours (tests/integration/test_cosim_chain.py)."""
    names = [f"mass{i + 1}" for i in range(n)]
    connections: list[Connection] = []
    for left, right in pairwise(names):
        for a, b in (("x", "xl"), ("v", "vl")):
            connections.append(Connection(Port(left, a), Port(right, b)))
        for a, b in (("x", "xr"), ("v", "vr")):
            connections.append(Connection(Port(right, a), Port(left, b)))
    params: Params = {Port(names[0], "x"): 1.0}
    for i, name in enumerate(names):
        params |= {Port(name, "m"): 1.0 + 0.1 * i, Port(name, "dl"): 0.05, Port(name, "dr"): 0.05}
    return System(
        instances=tuple(Instance(name, "chain_mass.fmu") for name in names),
        connections=tuple(connections),
        parameters=params,
        log_variables={name: ("x",) for name in names},
        algorithm=Algorithm("fixed-step", H, master=master),  # type: ignore[arg-type]
        end_time=steps * H,
        source="yaml",
    )


def build_fmus(out: Path) -> dict[str, Path]:
    return {
        f"{name}.fmu": build_fmu(ROOT / "tests" / "fmus" / name, out / f"{name}.fmu")
        for name in ("msd_mass", "msd_spring", "chain_mass")
    }


Timed = tuple[float, float, list[float]]  # wall seconds, CPU seconds, the last row


def ours(system: System, fmus: dict[str, Path], steps: int) -> Timed:
    """A Session stepped as runner.run steps it (every row kept); only the steps timed."""
    with Session(system, fmus) as session:
        rows = [session.initialize()]
        begin, cpu = time.perf_counter(), time.thread_time()
        while (row := session.step()) is not None:
            rows.append(row)
        seconds, cpu = time.perf_counter() - begin, time.thread_time() - cpu
    assert len(rows) == steps + 1, (len(rows), steps)
    return seconds, cpu, [float(x) for x in rows[-1]]


def plain(system: System, fmus: dict[str, Path], steps: int) -> Timed:
    loop = PlainLoop(system, fmus)
    try:
        cpu = time.thread_time()
        seconds, rows = loop.run(steps)
        cpu = time.thread_time() - cpu
    finally:
        loop.close()
    return seconds, cpu, rows[-1]


def do_step_only(system: System, fmus: dict[str, Path], steps: int) -> Timed:
    """The floor: each FMU's doStep through FMPy, no exchange, nothing recorded."""
    loop = PlainLoop(system, fmus)
    try:
        units, h = loop.units, system.algorithm.size
        begin, cpu = time.perf_counter(), time.thread_time()
        for k in range(steps):
            for unit in units:
                unit.fmu.doStep(k * h, h)
        return time.perf_counter() - begin, time.thread_time() - cpu, []
    finally:
        loop.close()


Runner = Callable[[System, dict[str, Path], int], Timed]


def measure(label: str, runner: Runner, system: System, fmus: dict[str, Path], steps: int,
            runs: list[Timed]) -> dict[str, Any]:  # fmt: skip
    walls, cpus = [r[0] for r in runs], [r[1] for r in runs]
    return {
        "case": label,
        "fmus": len(system.instances),
        "master": system.algorithm.master,
        "steps": steps,
        "seconds": walls,
        "cpu_seconds": cpus,
        "steps_per_s_best": steps / min(walls),
        "steps_per_s_median": steps / statistics.median(walls),
        "us_per_step_median": statistics.median(walls) / steps * 1e6,
        "cpu_us_per_step_median": statistics.median(cpus) / steps * 1e6,
        "last_row": runs[-1][2],
    }


def throughput(fmus: dict[str, Path], steps: dict[str, int], repeats: int) -> list[dict[str, Any]]:
    """Each case's runs interleaved (ours, the plain loop, the floor, again), after one
    short untimed run of each, so a burst of other work on the machine hits all three."""
    rows = []
    for name, make in (("msd pair", msd_system), ("10-FMU chain", chain_system)):
        for master in ("gauss-seidel", "jacobi"):
            n = steps[name]
            system = make(master, n)
            print(f"{name}, {master} ...", flush=True)
            runners = {"twinlink": ours, "FMPy plain loop": plain, "doStep only": do_step_only}
            for runner in runners.values():
                runner(make(master, n // 10), fmus, n // 10)
            runs: dict[str, list[Timed]] = {label: [] for label in runners}
            for _ in range(repeats):
                for label, runner in runners.items():
                    runs[label].append(runner(system, fmus, n))
            mine, theirs, floor = (
                measure(f"{name}, {label}", runners[label], system, fmus, n, runs[label])
                for label in runners
            )
            same = np.allclose(mine["last_row"], theirs["last_row"], rtol=0, atol=1e-12)
            mine["same_values_as_plain_loop"] = bool(same)
            mine["time_ratio_to_plain_loop"] = (
                mine["us_per_step_median"] / theirs["us_per_step_median"]
            )
            mine["cpu_ratio_to_plain_loop"] = (
                mine["cpu_us_per_step_median"] / theirs["cpu_us_per_step_median"]
            )
            rows += [mine, theirs, floor]
    return rows


def paced(fmus: dict[str, Path], seconds: float) -> list[dict[str, Any]]:
    """run_paced at factor 1.0 with a 1 ms step, as `twinlink cosim run --realtime 1` does;
    then again with this thread at real-time priority (SCHED_FIFO, as `chrt -f 10` gives),
    when the machine allows it."""
    out = []
    for priority in ("normal", "SCHED_FIFO 10"):
        for name, make in (("msd pair", msd_system), ("10-FMU chain", chain_system)):
            print(f"{name}, paced at 1 kHz for {seconds:g} s, {priority} ...", flush=True)
            with _scheduling(priority) as allowed:
                if not allowed:
                    print(f"  {priority} is not allowed here: skipped", flush=True)
                    break
                row = _paced_once(f"{name}, Gauss-Seidel, 1 kHz, {priority}", make, fmus, seconds)
                out.append(row)
    return out


def _paced_once(label: str, make: Callable[[str, int], System], fmus: dict[str, Path],
                seconds: float) -> dict[str, Any]:  # fmt: skip
    with Session(make("gauss-seidel", round(seconds / H)), fmus) as session:
        session.initialize()
        rows: list[Any] = []
        load = os.getloadavg()[0]
        jitter = run_paced(session, 1.0, threading.Event(), rows.append)
    return {
        "case": label, "steps": jitter.steps, "late": jitter.late, "rows": len(rows),
        "p50_ms": jitter.p50, "p99_ms": jitter.p99, "max_ms": jitter.max,
        "loadavg_at_start": round(load, 2),
    }  # fmt: skip


@contextlib.contextmanager
def _scheduling(priority: str) -> Iterator[bool]:
    """This thread at `priority` ("normal", or "SCHED_FIFO n"); yields whether it could."""
    if priority == "normal":
        yield True
        return
    before = os.sched_getscheduler(0), os.sched_getparam(0)
    try:
        os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(int(priority.split()[1])))
    except (PermissionError, AttributeError, OSError):
        yield False
        return
    try:
        yield True
    finally:
        os.sched_setscheduler(0, before[0], before[1])


def goals(report: dict[str, Any]) -> list[dict[str, Any]]:
    out = []
    if rows := report.get("throughput"):
        msd_gs = next(r for r in rows if r["case"] == "msd pair, twinlink"
                      and r["master"] == "gauss-seidel")  # fmt: skip
        ratio = max(r["time_ratio_to_plain_loop"] for r in rows if "time_ratio_to_plain_loop" in r)
        out += [
            {"goal": f">= {GOAL_STEPS_PER_S:,} macro steps/s, 2 FMUs (Gauss-Seidel, median)",
             "measured": f"{msd_gs['steps_per_s_median']:,.0f}",
             "met": msd_gs["steps_per_s_median"] >= GOAL_STEPS_PER_S},
            {"goal": f"<= {GOAL_RATIO}x the plain loop's time per step (worst case)",
             "measured": f"{ratio:.2f}x", "met": ratio <= GOAL_RATIO},
        ]  # fmt: skip
    if paced_rows := report.get("paced"):
        for r in paced_rows:
            if r["case"].startswith("msd pair"):
                priority = r["case"].rsplit(", ", 1)[1]
                out.append({
                    "goal": f"real-time start jitter p99 <= {GOAL_P99_MS:g} ms at 1 kHz, "
                            f"2 FMUs, {priority} priority",
                    "measured": f"{r['p99_ms']:.3f} ms", "met": r["p99_ms"] <= GOAL_P99_MS,
                })  # fmt: skip
    return out


def render(report: dict[str, Any]) -> str:
    m, la = report["machine"], report["loadavg"]
    lines = [
        f"Co-simulation, fixed step {H * 1000:g} ms; {m['nproc']} CPUs ({m['cpu_model']}), "
        f"Python {m['python']}, FMPy {report['fmpy']}, commit {m['git']}; "
        f"load average {la['before']} before, {la.get('after', '-')} after",
        "",
        f"{'case':<34} {'master':<13} {'steps':>7} {'steps/s med':>12} {'best':>9} "
        f"{'us/step':>8} {'CPU us':>7} {'vs plain':>9}",
    ]
    for r in report.get("throughput", []):
        ratio = r.get("time_ratio_to_plain_loop")
        lines.append(
            f"{r['case']:<34} {r['master']:<13} {r['steps']:>7} "
            f"{r['steps_per_s_median']:>12,.0f} {r['steps_per_s_best']:>9,.0f} "
            f"{r['us_per_step_median']:>8.1f} {r['cpu_us_per_step_median']:>7.1f} "
            f"{'' if ratio is None else f'{ratio:.2f}x':>9}"
        )
    lines += ["", f"{'real time':<62} {'steps':>6} {'late':>5} {'p50 ms':>7} {'p99 ms':>7} "
              f"{'max ms':>7}"]  # fmt: skip
    for r in report.get("paced", []):
        lines.append(
            f"{r['case']:<62} {r['steps']:>6} {r['late']:>5} {r['p50_ms']:>7.3f} "
            f"{r['p99_ms']:>7.3f} {r['max_ms']:>7.3f}"
        )
    lines.append("")
    for g in report["goals"]:
        lines.append(f"{'met ' if g['met'] else 'MISSED'} {g['goal']}: {g['measured']}")
    return "\n".join(lines)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer steps, 1 repeat, 2 s paced")
    parser.add_argument("--repeats", type=int, help="runs of each case (3; 1 quick)")
    parser.add_argument("--paced-seconds", type=float, help="wall seconds paced (10; 2 quick)")
    parser.add_argument("--json", type=Path, help="results file (bench/results/cosim-*.json)")
    parser.add_argument("--only", choices=("throughput", "paced"), help="one part only")
    args = parser.parse_args()
    repeats = args.repeats or (1 if args.quick else 3)
    scale = 0.2 if args.quick else 1.0
    steps = {"msd pair": round(50_000 * scale), "10-FMU chain": round(10_000 * scale)}
    import fmpy  # type: ignore[import-untyped]

    report: dict[str, Any] = {
        "machine": machine_info(),
        "fmpy": fmpy.__version__,
        "loadavg": {"before": round(os.getloadavg()[0], 2)},
    }
    with tempfile.TemporaryDirectory(prefix="twinlink-cosim-bench-") as tmp:
        fmus = build_fmus(Path(tmp))
        if args.only != "paced":
            report["throughput"] = throughput(fmus, steps, repeats)
        if args.only != "throughput":
            report["paced"] = paced(fmus, args.paced_seconds or (2.0 if args.quick else 10.0))
    report["loadavg"]["after"] = round(os.getloadavg()[0], 2)
    report["goals"] = goals(report)
    print(render(report))
    path = write_json(report, args.json, "cosim")
    print(f"\nresults: {os.path.relpath(path)}")
    same = all(r.get("same_values_as_plain_loop", True) for r in report.get("throughput", []))
    if not same:
        print("FAILED: twinlink and the plain loop ended on different values", file=sys.stderr)
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
