"""Scale-out benchmark (issue 15): PostgreSQL, Kafka, two `twinlink up` nodes, haproxy and
the devices, all on this machine; the embedded server and a single node on PostgreSQL and
Kafka in the same run, as the references.

Cases, in this order (each with servers of its own, started for it and stopped after):
- `embedded`: one `twinlink up` with its defaults (SQLite, history_sync full; the in-process
  bus);
- `single`: one node on PostgreSQL and Kafka;
- `cluster`: two nodes on the same PostgreSQL and Kafka behind haproxy, which spreads the
  devices' requests over them.

In each: 100 devices (`--devices`) post batches over HTTP keep-alive for 60 s (`--seconds`),
one batch in flight each; afterwards every twin's stored sample count must equal what its
device had acknowledged (0 lost). Then the live delay at 1 000 samples/s and the command
round trip, with the device on the second node and the subscriber or caller on the first.
A py-spy profile of the first node during the load says where its time goes.

    .venv/bin/python bench/cluster.py            # 60 s a case, about 5 minutes
    .venv/bin/python bench/cluster.py --quick    # 10 s a case, about 2 minutes

Prints a table and writes JSON to bench/results/cluster-<UTC time>.json (or --json PATH).
Exit status: 0 when every case ran and nothing acknowledged was lost; 1 when a case failed or
a sample was lost; 2 when PostgreSQL or Kafka could not be started. A goal not met does not
fail the run. The pieces: _cluster_infra.py (servers), _cluster_client.py (the HTTP devices,
in client processes of their own), _cluster_cases.py (the measurements), _cluster_profile.py
(py-spy) and _cluster_report.py (goals, table).
"""

from __future__ import annotations

import argparse
import asyncio
import os
import sys
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _cluster_cases import Plan, command_round_trips, live_delay, throughput
from _cluster_infra import Infra, Setup, haproxy_aborts, start_setup
from _cluster_report import goals, render
from _live_fleet import make_fleet
from _live_report import relative
from _report import RESULTS, _version, machine_info, write_json
from live import raise_fd_limit, run

CASES = {"embedded": 1, "single": 1, "cluster": 2}  # case -> nodes
EXTRA_PACKAGES = ("asyncpg", "aiokafka", "twinlink-edge", "orjson")


def parse_args(argv: list[str] | None) -> tuple[Plan, list[str], Path | None, bool]:
    p = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument("--quick", action="store_true", help="10 s a case instead of 60")
    p.add_argument("--seconds", type=float, help="seconds of load a case (60; 10 quick)")
    p.add_argument("--devices", type=int, default=100, help="HTTP devices (100)")
    p.add_argument("--batch-size", type=int, default=100, help="samples a batch (100)")
    p.add_argument("--signals", type=int, default=4, help="float signals a sample (4)")
    p.add_argument("--client-procs", type=int, default=2, help="processes of devices (2)")
    p.add_argument("--cases", default=",".join(CASES), help=f"subset of {','.join(CASES)}")
    p.add_argument(
        "--live-flush-ms", type=float, default=2.0, help="live device's SDK flush_interval (2)"
    )
    p.add_argument("--profile-seconds", type=float, help="py-spy of node1 (10; 4 quick; 0 off)")
    p.add_argument("--json", type=Path, help="results file (default bench/results/cluster-*.json)")
    a = p.parse_args(argv)
    cases = [c for c in CASES if c in a.cases.split(",")]
    if set(a.cases.split(",")) - set(CASES) or not cases:
        p.error(f"--cases: choose from {','.join(CASES)}")
    if a.devices < 1 or a.batch_size < 1 or a.signals < 1 or a.client_procs < 1:
        p.error("--devices, --batch-size, --signals and --client-procs are at least 1")
    seconds = a.seconds or (10.0 if a.quick else 60.0)
    profile = a.profile_seconds if a.profile_seconds is not None else (4.0 if a.quick else 10.0)
    plan = Plan(
        seconds=seconds,
        devices=a.devices,
        batch_size=a.batch_size,
        signals=a.signals,
        client_procs=a.client_procs,
        live_rate=1000,
        live_seconds=4.0 if a.quick else 10.0,
        live_flush_s=a.live_flush_ms / 1000,
        commands=300 if a.quick else 1000,
        command_seconds=3.0 if a.quick else 10.0,
        profile_s=min(profile, seconds),
    )
    return plan, cases, a.json, a.quick


def main(argv: list[str] | None = None) -> int:
    plan, cases, json_path, quick = parse_args(argv)
    raise_fd_limit()
    machine = machine_info()
    machine["packages"].update({d: _version(d) for d in EXTRA_PACKAGES})
    report: dict[str, Any] = {
        "machine": machine,
        "quick": quick,
        "config": vars(plan),
        "loadavg": {"before": round(os.getloadavg()[0], 2)},
        "cases": {},
    }
    status = run(_benchmark(plan, cases, report))
    report["loadavg"]["after"] = round(os.getloadavg()[0], 2)
    report["goals"] = goals(report["cases"])
    print(render(report))
    path = write_json(report, json_path, name="cluster")
    print(f"\nresults: {relative(path)}")
    return status


async def _benchmark(plan: Plan, cases: list[str], report: dict[str, Any]) -> int:
    infra: Infra | None = None
    status = 0
    stamp = datetime.now(UTC).strftime("%Y%m%dT%H%M%SZ")
    try:
        for name in cases:
            if name != "embedded" and infra is None:
                print("starting PostgreSQL and Kafka ...", flush=True)
                try:
                    infra = await asyncio.to_thread(Infra.start)
                except Exception as err:
                    print(f"error: {err}", file=sys.stderr)
                    report["error"] = str(err)
                    return 2
            print(f"{name} ...", flush=True)
            case = await _case(name, None if name == "embedded" else infra, plan, stamp)
            report["cases"][name] = case
            stored = case.get("throughput", {}).get("stored", {})
            if "error" in case or stored.get("lost", 1) or stored.get("extra", 1):
                status = 1
    finally:
        if infra is not None:
            infra.stop()
    return status


async def _case(name: str, infra: Infra | None, plan: Plan, stamp: str) -> dict[str, Any]:
    """One setup: started, measured, stopped. A part that fails is recorded and the others
    still run."""
    case: dict[str, Any] = {}
    try:
        setup = await asyncio.to_thread(start_setup, name, infra, CASES[name])
    except Exception as err:
        return {"error": f"could not start: {err}"}
    try:
        fleet = await make_fleet(setup.nodes[0], "dev", plan.devices + 2)
        slugs, tokens = fleet.slugs[: plan.devices], fleet.tokens[: plan.devices]
        print(f"  {plan.devices} devices for {plan.seconds:g} s ...", flush=True)
        RESULTS.mkdir(parents=True, exist_ok=True)
        profile = RESULTS / f"cluster-profile-{stamp}-{name}.txt"
        case["throughput"] = await throughput(setup, slugs, tokens, plan, profile)
        print("  live delay and commands ...", flush=True)
        for part, measure, i in (
            ("live", live_delay, -1),
            ("commands", command_round_trips, -2),
        ):
            try:
                case[part] = await measure(setup, fleet.slugs[i], fleet.tokens[i], plan)
            except Exception as err:
                case[f"{part}_error"] = f"{type(err).__name__}: {err}"
    except Exception as err:
        case["error"] = f"{type(err).__name__}: {err}"
        case.update(_dead(setup))
    finally:
        case["node_logs"] = [_log_tail(n.log()) for n in setup.nodes if n.log().strip()]
        if setup.haproxy is not None:
            case["haproxy"] = haproxy_aborts(setup.haproxy.directory / "haproxy.log")
        await asyncio.to_thread(setup.stop)
    return case


def _log_tail(log: str, lines: int = 15) -> str:
    """A node's last lines for the JSON, without the first admin's password and token it prints."""
    secret = ("password", "token")
    kept = [line for line in log.splitlines() if not any(s in line.lower() for s in secret)]
    return "\n".join(kept[-lines:])


def _dead(setup: Setup) -> dict[str, Any]:
    dead = setup.dead()
    return {"dead_nodes": dead} if dead else {}


if __name__ == "__main__":
    sys.exit(main())
