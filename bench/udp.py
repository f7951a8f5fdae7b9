"""UDP datasource benchmark: catman datagrams from another process into a connector of a real
`twinlink up`, at paced rates and flat out; how many are taken in and stored, and the server's
CPU. In the same run, a bare uvloop receiver that only counts datagrams is the reference: the
most a Python listener takes in on this machine.

    .venv/bin/python bench/udp.py            # 5 cases, 10 s each, about 1.5 minutes
    .venv/bin/python bench/udp.py --quick    # 3 cases, 3 s each
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import httpx
import psutil

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _report import machine_info, write_json
from _server import Twinlink

HERE = Path(__file__).resolve().parent
CHANNELS = ["time", "force", "angle", "strain"]
SLUG = "udp-bench"


@dataclass
class Case:
    label: str
    rate: int  # datagrams/s; 0 = as fast as the sender goes
    records: int  # catman records per datagram


CASES = [
    Case("1 record a datagram, 5 000/s", 5_000, 1),
    Case("1 record a datagram, 20 000/s", 20_000, 1),
    Case("1 record a datagram, 50 000/s", 50_000, 1),
    Case("1 record a datagram, flat out", 0, 1),
    Case("20 records a datagram, 5 000/s", 5_000, 20),
]
QUICK = [CASES[1], CASES[3], CASES[4]]


def _sender(port: int, case: Case, seconds: float) -> subprocess.Popen[str]:
    args = [str(port), str(case.rate), str(seconds), str(case.records), str(len(CHANNELS))]
    return subprocess.Popen(
        [sys.executable, str(HERE / "_udp_sender.py"), "127.0.0.1", *args],
        stdout=subprocess.PIPE,
        text=True,
    )


def _status(admin: httpx.Client) -> dict[str, Any]:
    r = admin.get(f"/api/v1/twins/{SLUG}/connectors/udp")
    r.raise_for_status()
    return r.json()["status"]  # type: ignore[no-any-return]


def _stored(admin: httpx.Client) -> int:
    """Samples stored: the stream's count is of values, one per signal of a sample."""
    streams = admin.get(f"/api/v1/twins/{SLUG}/streams").json()["streams"]
    values = sum(s["count"] for s in streams if s["name"] == "telemetry")
    return values // (len(CHANNELS) - 1)  # the time channel is the sample's time


def _settled(admin: httpx.Client, expected: int, timeout: float = 30) -> int:
    """The stored count once it reaches `expected` or stops growing for a second."""
    deadline = time.monotonic() + timeout
    last, since = -1, time.monotonic()
    while time.monotonic() < deadline:
        now = _stored(admin)
        if now >= expected:
            return now
        if now != last:
            last, since = now, time.monotonic()
        elif time.monotonic() - since > 1.0:
            return now
        time.sleep(0.1)
    return last


def run_case(server: Twinlink, admin: httpx.Client, case: Case, seconds: float) -> dict[str, Any]:
    config = {"port": 0, "format": "catman", "channels": CHANNELS, "time_channel": "time"}
    r = admin.post(
        f"/api/v1/twins/{SLUG}/connectors",
        json={"name": "udp", "kind": "udp", "config": config},
    )
    r.raise_for_status()
    port = int(r.json()["status"]["address"].rsplit(":", 1)[1])
    proc = psutil.Process(server.pid)
    try:
        before_cpu, before_stored = proc.cpu_times(), _stored(admin)
        sender = _sender(port, case, seconds)
        out, _ = sender.communicate(timeout=seconds + 60)
        sent = json.loads(out)
        status = _status(admin)
        after_cpu = proc.cpu_times()
        stored = _settled(admin, before_stored + status["samples"]) - before_stored
    finally:
        admin.delete(f"/api/v1/twins/{SLUG}/connectors/udp")
    cpu = (after_cpu.user + after_cpu.system - before_cpu.user - before_cpu.system) / sent[
        "seconds"
    ]
    received = status["messages"]
    return {
        "case": case.label,
        "rate": case.rate,
        "records": case.records,
        "seconds": round(sent["seconds"], 3),
        "sent": sent["sent"],
        "send_errors": sent["send_errors"],
        "received": received,
        "received_share": received / sent["sent"] if sent["sent"] else None,
        "samples": status["samples"],
        "stored": stored,
        "sent_per_s": sent["sent"] / sent["seconds"],
        "received_per_s": received / sent["seconds"],
        "stored_per_s": stored / sent["seconds"],
        "server_cpu": cpu,
        "errors": status["errors"],
    }


def run_reference(case: Case, seconds: float) -> dict[str, Any]:
    ref = subprocess.Popen(
        [sys.executable, str(HERE / "_udp_reference.py")],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    assert ref.stdin is not None and ref.stdout is not None
    try:
        port = int(ref.stdout.readline())
        sender = _sender(port, case, seconds)
        out, _ = sender.communicate(timeout=seconds + 60)
        sent = json.loads(out)
        ref.stdin.write("count\n")
        ref.stdin.flush()
        received = json.loads(ref.stdout.readline())["received"]
    finally:
        ref.stdin.close()
        ref.wait(10)
    return {
        "case": f"reference: bare uvloop receiver, {case.label}",
        "sent": sent["sent"],
        "received": received,
        "received_share": received / sent["sent"] if sent["sent"] else None,
        "sent_per_s": sent["sent"] / sent["seconds"],
        "received_per_s": received / sent["seconds"],
    }


def _n(x: float) -> str:
    return f"{x:,.0f}".replace(",", " ")


def render(report: dict[str, Any]) -> str:
    m = report["machine"]
    lines = [
        f"UDP datasource, catman records of {len(CHANNELS)} doubles; {m['nproc']} CPUs, "
        f"Python {m['python']}, commit {m['git']}",
        "",
        f"{'case':<52} {'sent/s':>9} {'taken in/s':>11} {'share':>7} {'stored/s':>10} "
        f"{'server CPU':>10}",
    ]
    for r in report["cases"]:
        lines.append(
            f"{r['case']:<52} {_n(r['sent_per_s']):>9} {_n(r['received_per_s']):>11} "
            f"{r['received_share']:>7.1%} {_n(r['stored_per_s']):>10} {r['server_cpu']:>10.0%}"
        )
    for r in report["references"]:
        lines.append(
            f"{r['case']:<52} {_n(r['sent_per_s']):>9} {_n(r['received_per_s']):>11} "
            f"{r['received_share']:>7.1%}"
        )
    lines += [
        "",
        "taken in: datagrams the connector read (the rest the kernel dropped: its receive "
        "buffer was full); stored: samples durable in history; server CPU: share of one core.",
        "Seed: the NTNU platform's API took at most about 500 samples/s; the rig sends 100.",
    ]
    return "\n".join(lines)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="3 cases, 3 s each")
    parser.add_argument("--seconds", type=float, help="seconds a case sends (10; 3 quick)")
    parser.add_argument("--json", type=Path, help="results file (bench/results/udp-*.json)")
    args = parser.parse_args()
    seconds = args.seconds or (3.0 if args.quick else 10.0)
    cases = QUICK if args.quick else CASES
    report: dict[str, Any] = {"machine": machine_info(), "cases": [], "references": []}
    with tempfile.TemporaryDirectory(prefix="twinlink-udp-bench-") as tmp:
        server = Twinlink(Path(tmp) / "data")
        server.start()
        try:
            headers = {"Authorization": f"Bearer {server.admin_token}"}
            with httpx.Client(base_url=server.url, headers=headers, timeout=60) as admin:
                doc = {"version": "1.0", "privacy": "public", "id": "urn:bench:udp",
                       "slug": SLUG, "name": "UDP bench"}  # fmt: skip
                admin.post("/api/v1/apply", json=doc).raise_for_status()
                for case in cases:
                    print(f"{case.label} ...", flush=True)
                    report["cases"].append(run_case(server, admin, case, seconds))
        finally:
            server.stop()
    for case in (CASES[2], CASES[3]):
        print(f"reference, {case.label} ...", flush=True)
        report["references"].append(run_reference(case, seconds))
    print(render(report))
    path = write_json(report, args.json, "udp")
    print(f"\nresults: {os.path.relpath(path)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
