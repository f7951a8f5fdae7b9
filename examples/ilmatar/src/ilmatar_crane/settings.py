"""Ports, demo credentials and tunables of the crane services."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

OPCUA_NAMESPACE = "http://twinlink.example/ilmatar"
OPCUA_PATH = "/ilmatar/"


@dataclass(frozen=True)
class CranePorts:
    """Where each service listens; 0 lets the OS pick a free port (Crane.ports has the real)."""

    opcua: int = 4840
    historian: int = 8701
    bridge: int = 8703
    cad: int = 8704
    sensors: int = 8705


# What each port is for, as a person would name it.
PORT_NAMES = {
    "opcua": "OPC UA server",
    "historian": "historian",
    "bridge": "OPC UA bridge",
    "cad": "CAD store",
    "sensors": "sensor manager",
}


@dataclass(frozen=True)
class DemoCredentials:
    """Fixed credentials so the demo works out of the box. They are published in docs/crane.md
    and protect nothing: the services are demo stand-ins meant for loopback only."""

    historian_username: str = "crane"
    historian_password: str = "ilmatar-demo"
    bridge_api_key: str = "ilmatar-bridge-demo-key"
    cad_token: str = "ilmatar-cad-demo-token"
    sensors_client_id: str = "twinlink-gateway"
    sensors_client_secret: str = "ilmatar-sensors-demo-secret"
    sensors_username: str = "operator"
    sensors_password: str = "ilmatar-demo"


@dataclass(frozen=True)
class CraneSettings:
    credentials: DemoCredentials = field(default_factory=DemoCredentials)
    token_ttl_s: float = 300.0  # historian and sensor manager access tokens
    plant_period_s: float = 0.1  # 10 Hz simulation and OPC UA updates
    historian_period_s: float = 1.0
    historian_retention_s: float = 3 * 3600.0
    autopilot: bool = True  # drive a demo lifting route while nobody commands the crane
    autopilot_hold_s: float = 120.0  # how long a manual set-point pauses the autopilot
    cad_dir: Path | None = None  # serve this folder; None: the generated crane models
    seed: int = 16052  # the plant's noise, so two runs record the same data
