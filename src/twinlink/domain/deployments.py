"""Deployments (DTaaS): a twin package brought to life as a twin with its devices, processors,
connectors and gateway services, and the lifecycle state it is in."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal

# `applying` is the state while a create is being applied: a deployment found in it at start
# was cut off by a crash, and is undone (deploy/service.py).
DeploymentState = Literal[
    "planned", "applying", "created", "running", "stopped", "terminated", "failed"
]
STATES: tuple[str, ...] = (
    "planned", "applying", "created", "running", "stopped", "terminated", "failed",
)  # fmt: skip
# Deployments in these states hold nothing: their name may be used again.
ENDED: tuple[str, ...] = ("terminated", "failed")
RESOURCE_TYPES: tuple[str, ...] = ("twin", "device", "processor", "connector", "service")


@dataclass(slots=True)
class DeploymentRecord:
    id: int
    name: str
    package: str  # the pinned ref: lib:<scope>/twins/<name>@sha256:...
    package_ref: str  # as asked
    parameters: dict[str, Any]  # after defaults
    state: str
    twin: str  # the twin's slug (= name)
    # What the deployment made, in the order made: {"type", "name", "spec"} each. It is the
    # journal a failed or crashed create is undone from, and what a reconfigure diffs against.
    journal: list[dict[str, Any]] = field(default_factory=list)
    # The device tokens, sealed with the server's vault (auth/vault.py); None: no devices.
    secrets: bytes | None = field(default=None, repr=False)
    created_by: int | None = None
    created_ns: int = 0
    updated_ns: int = 0
    error: str | None = None

    @property
    def live(self) -> bool:
        return self.state not in ENDED

    def resources(self) -> dict[str, Any]:
        """The names of what the deployment made, by type (the API's `resources`)."""
        out: dict[str, Any] = {"twin": None, "devices": [], "processors": [], "connectors": [],
                               "services": []}  # fmt: skip
        for entry in self.journal:
            if entry["type"] == "twin":
                out["twin"] = entry["name"]
            else:
                out[entry["type"] + "s"].append(entry["name"])
        return out
