"""MQTT ingest benchmark: raw MQTT 3.1.1 clients in another process publish telemetry to a
real `twinlink up`, in the embedded mode (its own listener; QoS 0 and 1, one sample and 100
samples a message) and the external mode (through a real Mosquitto); messages/s sent,
samples/s stored and the server's CPU. In the same run, the reference: the same clients
through the same Mosquitto to a subscriber that only counts, the most the broker passes on.

    .venv/bin/python bench/mqtt.py            # 5 cases, 5 s each, about a minute
    .venv/bin/python bench/mqtt.py --quick    # the same cases, 2 s each
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
from _mqtt_broker import BROKER_SETTINGS, Mosquitto, TwinlinkWithEnv
from _report import machine_info, write_json

HERE = Path(__file__).resolve().parent
SLUG = "mqtt-bench"
SIGNALS = 2  # angle and force: a stream's count is of values, one a signal of a sample
CONNECTIONS = 4  # devices, each its own connection, all in one client process
PLATFORM_USER, DEVICE_USER = "twinlink", "device"
GOAL_EMBEDDED_QOS1 = 20_000  # samples/s, the goal
GOAL_EXTERNAL_SHARE = 0.8  # external mode stores at least this share of the reference's rate


@dataclass
class Case:
    key: str
    label: str
    mode: str  # embedded, external, reference
    qos: int
    per_message: int  # samples a message
    window: int  # QoS 1 messages in flight a connection


CASES = [
    Case("embedded_qos0", "embedded, QoS 0, 1 sample a message", "embedded", 0, 1, 0),
    Case("embedded_qos1", "embedded, QoS 1, 1 sample a message", "embedded", 1, 1, 100),
    Case("embedded_qos1_batch", "embedded, QoS 1, 100 samples a message", "embedded", 1, 100, 20),
    Case("external_qos1", "external (Mosquitto), QoS 1, 1 sample", "external", 1, 1, 100),
    Case("reference_qos1", "reference: Mosquitto to a counting subscriber", "reference", 1, 1, 100),
]


def _client(mode: str, cfg: dict[str, Any], **kw: Any) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, str(HERE / "_mqtt_client.py"), mode, json.dumps(cfg)],
        stdout=subprocess.PIPE,
        text=True,
        **kw,
    )


def _publish(
    port: int, credentials: list[list[str]], case: Case, seconds: float, *cpus: Cpu
) -> dict[str, Any]:
    """Run the clients; the CPU counts start when they start sending."""
    start = time.time() + 1.5  # the client process imports and connects meanwhile
    cfg = {
        "start": start,
        "host": "127.0.0.1",
        "port": port,
        "credentials": credentials,
        "topics": [f"twinlink/{SLUG}/d{i}/telemetry" for i in range(CONNECTIONS)],
        "qos": case.qos,
        "window": case.window,
        "per_message": case.per_message,
        "seconds": seconds,
    }
    client = _client("pub", cfg)
    time.sleep(max(0.0, start - time.time()))
    for cpu in cpus:
        cpu.start()
    out, _ = client.communicate(timeout=seconds + 120)
    return json.loads(out)  # type: ignore[no-any-return]


def _stored(admin: httpx.Client) -> int:
    """Samples stored: the stream's count is of values, one per signal of a sample."""
    streams = admin.get(f"/api/v1/twins/{SLUG}/streams").json()["streams"]
    return sum(s["count"] for s in streams if s["name"] == "telemetry") // SIGNALS


def _settled(admin: httpx.Client, expected: int, timeout: float = 120) -> tuple[int, float | None]:
    """The stored count once it reaches `expected` or stops growing for two seconds, and the
    wall time it was first seen at that count (None: it was there at the first look)."""
    deadline = time.monotonic() + timeout
    last, since, seen = -1, time.monotonic(), None
    while time.monotonic() < deadline:
        now = _stored(admin)
        if now != last:
            seen = None if last < 0 else time.time()
            last, since = now, time.monotonic()
        if now >= expected or time.monotonic() - since > 2.0:
            break
        time.sleep(0.02)
    return last, seen


class Cpu:
    """CPU seconds a process used from start() on, as a share of one core over the seconds
    the case ran (the processes are idle before and after)."""

    def __init__(self, pid: int | None) -> None:
        self.proc = psutil.Process(pid) if pid else None

    def _now(self) -> float:
        if self.proc is None:
            return 0.0
        t = self.proc.cpu_times()
        return t.user + t.system  # type: ignore[no-any-return]

    def start(self) -> None:
        self.c0 = self._now()

    def share(self, seconds: float) -> float | None:
        if self.proc is None:
            return None
        return (self._now() - self.c0) / seconds


def run_twinlink_case(
    server: TwinlinkWithEnv,
    admin: httpx.Client,
    port: int,
    credentials: list[list[str]],
    case: Case,
    seconds: float,
    broker_pid: int | None = None,
) -> dict[str, Any]:
    cpu, broker_cpu = Cpu(server.pid), Cpu(broker_pid)
    before = _stored(admin)
    sent = _publish(port, credentials, case, seconds, cpu, broker_cpu)
    expected = before + sent["sent"] * case.per_message
    stored, seen = _settled(admin, expected)
    stored -= before
    # Stored by the clients' last PUBACK, or when the count was first seen complete (the
    # external mode: the broker acknowledges before twinlink has stored).
    elapsed = max(seen or 0.0, sent["end"]) - sent["start"]
    return _row(case, sent, stored, stored / (sent["sent"] * case.per_message) if sent["sent"]
                else None, elapsed, cpu.share(elapsed), broker_cpu.share(elapsed))  # fmt: skip


def run_reference(broker: Mosquitto, case: Case, seconds: float) -> dict[str, Any]:
    cfg = {"host": "127.0.0.1", "port": broker.port, "username": PLATFORM_USER,
           "password": PLATFORM_USER, "filter": "twinlink/#"}  # fmt: skip
    sub = _client("sub", cfg, stdin=subprocess.PIPE)
    assert sub.stdin is not None and sub.stdout is not None
    try:
        assert sub.stdout.readline().strip() == "READY"
        cpu, broker_cpu = Cpu(sub.pid), Cpu(broker.pid)
        creds = [[DEVICE_USER, DEVICE_USER]] * CONNECTIONS
        sent = _publish(broker.port, creds, case, seconds, cpu, broker_cpu)
        sub.stdin.write("count\n")
        sub.stdin.flush()
        got = json.loads(sub.stdout.readline())
        elapsed = max(got["last"], sent["end"]) - sent["start"]
        subscriber_cpu, mosquitto_cpu = cpu.share(elapsed), broker_cpu.share(elapsed)
    finally:
        sub.stdin.close()
        sub.wait(10)
    received = got["received"]  # by the subscriber: nothing is stored
    share = received / sent["sent"] if sent["sent"] else None
    # server CPU: the counting subscriber's
    return _row(case, sent, received, share, elapsed, subscriber_cpu, mosquitto_cpu)


def _row(
    case: Case, sent: dict[str, Any], stored: int, share: float | None, elapsed: float,
    server_cpu: float | None, broker_cpu: float | None,
) -> dict[str, Any]:  # fmt: skip
    return {
        "case": case.label,
        "key": case.key,
        "mode": case.mode,
        "qos": case.qos,
        "samples_per_message": case.per_message,
        "connections": CONNECTIONS,
        "window": case.window,
        "sent": sent["sent"],
        "send_seconds": round(sent["seconds"], 3),
        "stored": stored,
        "stored_share": share,
        "seconds": round(elapsed, 3),
        "sent_per_s": sent["sent"] / sent["seconds"],
        "stored_per_s": stored / elapsed,
        "server_cpu": server_cpu,
        "broker_cpu": broker_cpu,
        "client_cpu": sent["client_cpu"],
    }


def _make_twin(admin: httpx.Client) -> list[str]:
    """The twin and its devices d0..d3; their tokens."""
    doc = {"version": "1.0", "privacy": "public", "id": "urn:bench:mqtt", "slug": SLUG,
           "name": "MQTT bench"}  # fmt: skip
    admin.post("/api/v1/apply", json=doc).raise_for_status()
    tokens = []
    for i in range(CONNECTIONS):
        r = admin.post(f"/api/v1/twins/{SLUG}/devices", json={"name": f"d{i}"})
        r.raise_for_status()
        tokens.append(r.json()["token"])
    return tokens


def run_embedded(cases: list[Case], seconds: float, tmp: Path) -> list[dict[str, Any]]:
    server = TwinlinkWithEnv(tmp / "embedded")
    server.start()
    rows = []
    try:
        headers = {"Authorization": f"Bearer {server.admin_token}"}
        with httpx.Client(base_url=server.url, headers=headers, timeout=60) as admin:
            tokens = _make_twin(admin)
            address = admin.get("/api/v1/mqtt").json()["address"]
            port = int(address.rsplit(":", 1)[1])
            creds = [[f"d{i}", token] for i, token in enumerate(tokens)]
            for case in cases:
                print(f"{case.label} ...", flush=True)
                rows.append(run_twinlink_case(server, admin, port, creds, case, seconds))
    finally:
        server.stop()
    return rows


def run_external(cases: list[Case], seconds: float, tmp: Path) -> tuple[list[dict[str, Any]], str]:
    broker = Mosquitto({PLATFORM_USER: PLATFORM_USER, DEVICE_USER: DEVICE_USER})
    broker.start()
    rows = []
    try:
        for case in (c for c in cases if c.mode == "reference"):
            print(f"{case.label} ...", flush=True)
            rows.append(run_reference(broker, case, seconds))
        external = [c for c in cases if c.mode == "external"]
        if external:
            env = {"TWINLINK_MQTT_MODE": "external", "TWINLINK_MQTT_BROKER_URL": broker.url,
                   "TWINLINK_MQTT_USERNAME": PLATFORM_USER,
                   "TWINLINK_MQTT_PASSWORD": PLATFORM_USER}  # fmt: skip
            server = TwinlinkWithEnv(tmp / "external", extra_env=env)
            server.start()
            try:
                headers = {"Authorization": f"Bearer {server.admin_token}"}
                with httpx.Client(base_url=server.url, headers=headers, timeout=60) as admin:
                    _make_twin(admin)
                    deadline = time.monotonic() + 10
                    while admin.get("/api/v1/mqtt").json().get("state") != "connected":
                        if time.monotonic() > deadline:
                            raise RuntimeError("twinlink did not connect to Mosquitto")
                        time.sleep(0.05)
                    creds = [[DEVICE_USER, DEVICE_USER]] * CONNECTIONS
                    for case in external:
                        print(f"{case.label} ...", flush=True)
                        rows.insert(
                            0,
                            run_twinlink_case(
                                server, admin, broker.port, creds, case, seconds, broker.pid
                            ),
                        )
            finally:
                server.stop()
    finally:
        broker.stop()
    return rows, broker.version


def _n(x: float) -> str:
    return f"{x:,.0f}".replace(",", " ")


def _pct(x: float | None) -> str:
    return "-" if x is None else f"{x:.0%}"


def goals(report: dict[str, Any]) -> list[str]:
    rows = {r["key"]: r for r in report["cases"]}
    out = []
    if "embedded_qos1" in rows:
        rate = rows["embedded_qos1"]["stored_per_s"]
        ok = "met" if rate >= GOAL_EMBEDDED_QOS1 else "NOT met"
        out.append(f"embedded QoS 1 >= {_n(GOAL_EMBEDDED_QOS1)} samples/s: {_n(rate)} ({ok})")
    if "external_qos1" in rows and "reference_qos1" in rows:
        ext, ref = rows["external_qos1"]["stored_per_s"], rows["reference_qos1"]["stored_per_s"]
        share = ext / ref if ref else 0.0
        ok = "met" if share >= GOAL_EXTERNAL_SHARE else "NOT met"
        out.append(
            f"external within {1 - GOAL_EXTERNAL_SHARE:.0%} of the Mosquitto-only reference: "
            f"{_n(ext)} vs {_n(ref)} samples/s, {share:.1%} ({ok})"
        )
    return out


def render(report: dict[str, Any]) -> str:
    m = report["machine"]
    lines = [
        f"MQTT ingest, {CONNECTIONS} connections in one client process, samples of "
        f"{SIGNALS} signals; {m['nproc']} CPUs, Python {m['python']}, commit {m['git']}",
        f"{report['mosquitto']}, {', '.join(f'{k} {v}' for k, v in BROKER_SETTINGS.items())}",
        "",
        f"{'case':<48} {'window':>6} {'sent msg/s':>10} {'stored/s':>10} {'stored':>7} "
        f"{'server CPU':>10} {'broker CPU':>10} {'client CPU':>10}",
    ]
    for r in report["cases"]:
        lines.append(
            f"{r['case']:<48} {r['window'] or '-':>6} {_n(r['sent_per_s']):>10} "
            f"{_n(r['stored_per_s']):>10} {_pct(r['stored_share']):>7} "
            f"{_pct(r['server_cpu']):>10} {_pct(r['broker_cpu']):>10} {_pct(r['client_cpu']):>10}"
        )
    lines += [
        "",
        "window: QoS 1 messages in flight a connection; stored/s: samples durable in history "
        "per second, from the first message until all were stored (reference: messages the "
        "subscriber received); stored: share of the samples sent; CPU: share of one core "
        "(server CPU of the reference: the subscriber's; client CPU: the publishing process "
        "while it sent).",
        "",
        "Goals:",
        *(f"  {g}" for g in goals(report)),
        "",
        "Seed: ThingsBoard CE single node, about 3 500 MQTT messages/s (4-vCPU m5.xlarge); "
        "the NTNU platform's API took at most about 500 samples/s.",
    ]
    return "\n".join(lines)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="2 s a case")
    parser.add_argument("--seconds", type=float, help="seconds a case sends (5; 2 quick)")
    parser.add_argument("--json", type=Path, help="results file (bench/results/mqtt-*.json)")
    args = parser.parse_args()
    seconds = args.seconds or (2.0 if args.quick else 5.0)
    report: dict[str, Any] = {"machine": machine_info(), "seconds": seconds, "cases": []}
    with tempfile.TemporaryDirectory(prefix="twinlink-mqtt-bench-") as tmp:
        report["cases"] += run_embedded([c for c in CASES if c.mode == "embedded"], seconds,
                                        Path(tmp))  # fmt: skip
        rows, version = run_external(CASES, seconds, Path(tmp))
        report["cases"] += rows
    report["mosquitto"] = version
    report["broker_settings"] = BROKER_SETTINGS
    report["goals"] = goals(report)
    print(render(report))
    path = write_json(report, args.json, "mqtt")
    print(f"\nresults: {os.path.relpath(path)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
