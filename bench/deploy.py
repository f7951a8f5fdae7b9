"""Deploying the Tingen twin package (examples/library/tingen-rig), against making the same
twin by direct API calls, on a real `twinlink up`.

Cases (issue 16's goals):
- **to running**: `POST /api/v1/deployments {package: tingen-rig@1.0.0, start: true}` until its
  FMU processor's worker runs (goal <= 2 s), `--rounds` times, each a new deployment; the
  answer's own time too. The package's execute phase (the simulated rig) starts with it.
- **many**: `--count` deployments of it one after another (goal: 100 in <= 60 s), created but
  not started (each a twin, its device and token, its processor stopped): started, 100 FMU
  workers and 100 simulated rigs would be 200 processes on this 2-core machine, which
  measures the machine, not the deployment.
- **reference**: the same twin made by the calls a person would make without a package:
  apply the DT document, create the device, upload the FMU to the twin, create the processor
  (started for "to running", stopped for "many"), in the same run.

    .venv/bin/python bench/deploy.py [--rounds 5] [--count 100] [--json PATH] [--quick]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import httpx
import yaml

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _report import ROOT, machine_info, write_json
from _server import Twinlink
from twinlink.client import Client
from twinlink.processors.fmubuild import build_if_stale

LIBRARY = ROOT / "examples" / "library"
PACKAGE = "tingen-rig@1.0.0"
GOALS = {"to_running_s": 2.0, "many_100_s": 60.0}
TIMEOUT_S = 60.0


def push_package(server: Twinlink, fmu: Path) -> None:
    """The FMU, the simulator tool and the package, to `common` tagged 1.0.0."""
    with Client(server.url, server.admin_token) as client:
        lib = client.library
        lib.push(fmu, kind="models", name="tingen-beam", scope="common", tags=["1.0.0"])
        tool = LIBRARY / "tingen-sim"
        lib.push(tool, kind="tools", name="tingen-sim", scope="common", tags=["1.0.0"])
        rig = LIBRARY / "tingen-rig"
        lib.push(rig, kind="twins", name="tingen-rig", scope="common", tags=["1.0.0"])


def wait_processor(http: httpx.Client, slug: str, name: str = "fmu") -> None:
    """Poll until the processor's worker runs (fails after TIMEOUT_S)."""
    deadline = time.perf_counter() + TIMEOUT_S
    while True:
        view = http.get(f"/api/v1/twins/{slug}/processors/{name}").json()
        if view.get("state") == "running":
            return
        if time.perf_counter() > deadline:
            raise RuntimeError(f"processor {slug}/{name} never ran: {view}")
        time.sleep(0.005)


def deploy(http: httpx.Client, name: str, start: bool) -> float:
    """Seconds for the deployment's answer."""
    began = time.perf_counter()
    r = http.post("/api/v1/deployments", json={"package": PACKAGE, "name": name, "start": start})
    took = time.perf_counter() - began
    if r.status_code != 201:
        raise RuntimeError(f"deployment {name} refused: {r.status_code} {r.text}")
    return took


def reference(http: httpx.Client, name: str, fmu: bytes, start: bool) -> float:
    """Seconds for the same twin, device, FMU and processor by direct API calls."""
    document = yaml.safe_load((ROOT / "examples" / "tingen" / "tingen.yaml").read_text())
    document |= {"id": f"https://twinlink.example/bench/{name}", "slug": name}
    processor = yaml.safe_load((LIBRARY / "tingen-rig" / "twin.yaml").read_text())
    body = processor["processors"][0]
    body = {**body, "enabled": start}
    body["params"] = {**body["params"], "fmu": "Tingen.fmu", "parameters": {"zeta": 0.7}}
    began = time.perf_counter()
    for method, path, kwargs in (
        ("POST", "/api/v1/apply", {"json": document}),
        ("POST", f"/api/v1/twins/{name}/devices", {"json": {"name": "tingenSAP"}}),
        ("PUT", f"/api/v1/twins/{name}/fmus/Tingen.fmu", {"content": fmu}),
        ("POST", f"/api/v1/twins/{name}/processors", {"json": body}),
    ):
        r = http.request(method, path, **kwargs)
        if not r.is_success:
            raise RuntimeError(f"{method} {path}: {r.status_code} {r.text}")
    return time.perf_counter() - began


def timed(run: Callable[[], float], then: Callable[[], None] | None = None) -> tuple[float, float]:
    """(the call's seconds, seconds until `then` holds as well)."""
    began = time.perf_counter()
    answered = run()
    if then is not None:
        then()
    return answered, time.perf_counter() - began


def summary(values: list[float]) -> dict[str, float]:
    return {
        "median": statistics.median(values),
        "min": min(values),
        "max": max(values),
        "n": len(values),
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--count", type=int, default=100)
    parser.add_argument("--quick", action="store_true", help="2 rounds, 20 deployments")
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    rounds, count = (2, 20) if args.quick else (args.rounds, args.count)
    with tempfile.TemporaryDirectory() as tmp:
        fmu = build_if_stale(ROOT / "examples" / "tingen" / "fmu", Path(tmp) / "tingen.fmu")
        server = Twinlink(Path(tmp) / "data", env={"TWINLINK_MAX_PROCESSORS": "1000"})
        server.start()
        try:
            report = run(server, fmu, rounds, count)
        finally:
            server.stop()
    print_table(report)
    print(f"results: {write_json(report, args.json, 'deploy')}")
    return 0


def run(server: Twinlink, fmu: Path, rounds: int, count: int) -> dict[str, Any]:
    headers = {"Authorization": f"Bearer {server.admin_token}"}
    http = httpx.Client(base_url=server.url, headers=headers, timeout=TIMEOUT_S)
    push_package(server, fmu)
    fmu_bytes = fmu.read_bytes()
    cases = ("deploy_answer", "deploy_running", "reference_answer", "reference_running")
    rows: dict[str, list[float]] = {k: [] for k in cases}
    load_before = os.getloadavg()
    with http:
        # The first of each after the server's start imports what it needs (the package's
        # JSON Schema checks, FMPy in the worker's parent): shown apart, not in the rounds.
        cold = {
            "deploy_running": timed(lambda: deploy(http, "cold", True),
                                    lambda: wait_processor(http, "cold"))[1],
            "reference_running": timed(lambda: reference(http, "cold-ref", fmu_bytes, True),
                                       lambda: wait_processor(http, "cold-ref"))[1],
        }  # fmt: skip
        http.post("/api/v1/deployments/cold/stop")
        http.patch("/api/v1/twins/cold-ref/processors/fmu", json={"enabled": False})
        for i in range(rounds):  # in turns, so both see the same machine
            answer, running = timed(
                lambda i=i: deploy(http, f"run-{i}", True),
                lambda i=i: wait_processor(http, f"run-{i}"),
            )
            rows["deploy_answer"].append(answer)
            rows["deploy_running"].append(running)
            # Its rig and worker stopped: the next round runs alone.
            http.post(f"/api/v1/deployments/run-{i}/stop")
            answer, running = timed(
                lambda i=i: reference(http, f"ref-{i}", fmu_bytes, True),
                lambda i=i: wait_processor(http, f"ref-{i}"),
            )
            rows["reference_answer"].append(answer)
            rows["reference_running"].append(running)
            http.patch(f"/api/v1/twins/ref-{i}/processors/fmu", json={"enabled": False})
        began = time.perf_counter()
        for i in range(count):
            deploy(http, f"many-{i}", False)
        many = time.perf_counter() - began
        began = time.perf_counter()
        for i in range(count):
            reference(http, f"many-ref-{i}", fmu_bytes, False)
        many_reference = time.perf_counter() - began
    return {
        "machine": machine_info(),
        "goals": GOALS,
        "rounds": rounds,
        "count": count,
        "cold_s": cold,
        "to_running_s": {k: summary(v) for k, v in rows.items()},
        # The machine is shared: the 1-minute load average before and after the run.
        "load_average": {"before": load_before[0], "after": os.getloadavg()[0]},
        "many": {"deployments_s": many, "reference_s": many_reference, "count": count},
    }


def print_table(report: dict[str, Any]) -> None:
    print(f"{'case':<34} {'median s':>9} {'min s':>8} {'max s':>8}")
    for key, row in report["to_running_s"].items():
        print(f"{key:<34} {row['median']:>9.3f} {row['min']:>8.3f} {row['max']:>8.3f}")
    for key, seconds in report["cold_s"].items():
        print(f"{key + ' (first, cold)':<34} {seconds:>9.3f}")
    many = report["many"]
    n = many["count"]
    print(f"{f'{n} deployments (created), total':<34} {many['deployments_s']:>9.2f}")
    print(f"{f'{n} by direct API calls, total':<34} {many['reference_s']:>9.2f}")
    load = report["load_average"]
    print(f"load average (1 min): {load['before']:.1f} before, {load['after']:.1f} after")
    goal = report["goals"]
    print(
        f"goals: to running <= {goal['to_running_s']} s, 100 deployments <= {goal['many_100_s']} s"
    )


if __name__ == "__main__":
    sys.exit(main())
