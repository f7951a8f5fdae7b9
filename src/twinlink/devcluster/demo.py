"""The local cluster's demo: the example twins applied through the load balancer as the admin
(what `twinlink apply -f examples` does), and the simulated Tingen rig streaming to the
cluster as the device `tingenSAP` (`twinlink simulate tingen`, a process of its own that
connects through the load balancer, as a device on the network would).

Less than `make demo`, which runs beside a single server in its process: no Tingen FMU
processor, no crane services behind the gateway (docs/scale-out.md says so).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import httpx

from twinlink.devcluster._process import dying_with_parent, stop_process
from twinlink.domain.errors import TwinlinkError

DEVICE = "tingenSAP"
TWIN = "tingen"
_OUTCOMES = ("created", "updated", "unchanged")


class DemoError(TwinlinkError):
    """The cluster refused a demo document or device."""


def example_files(folder: Path) -> list[Path]:
    """The DT documents under `folder`; not the library's twin packages (`library/`), which
    are templates pushed to the library, not documents."""
    return sorted(
        p
        for p in folder.rglob("*")
        if p.suffix in (".yaml", ".yml")
        and p.is_file()
        and "library" not in p.relative_to(folder).parts[:1]
    )


def load_examples(client: httpx.Client, folder: Path) -> list[str]:
    """Apply every DT document under `folder`; one "slug (outcome)" per twin, already-loaded
    ones unchanged. `client` is the admin's, on the load balancer."""
    outcomes: dict[str, set[str]] = {}
    for path in example_files(folder):
        answer = client.post(
            "/api/v1/apply",
            content=path.read_bytes(),
            headers={"Content-Type": "application/yaml"},
        )
        if answer.status_code != 200:
            raise DemoError(f"{path} was not loaded: {answer.status_code} {answer.text[:300]}")
        for result in answer.json()["results"]:
            outcomes.setdefault(result["slug"], set()).add(result["outcome"])
    return [
        f"{slug} ({next((o for o in _OUTCOMES if o in seen), '/'.join(sorted(seen)))})"
        for slug, seen in outcomes.items()
    ]


def device_token(client: httpx.Client) -> str | None:
    """A fresh token of the Tingen twin's device tingenSAP (created on the first start);
    None when there is no Tingen twin."""
    devices = f"/api/v1/twins/{TWIN}/devices"
    answer = client.post(devices, json={"name": DEVICE, "description": "the simulated rig"})
    if answer.status_code == 409:  # there from an earlier start: a new token for this one
        answer = client.post(f"{devices}/{DEVICE}/token")
    if answer.status_code == 404:
        return None
    if answer.status_code not in (200, 201):
        raise DemoError(f"the device {DEVICE} of {TWIN}: {answer.status_code} {answer.text[:300]}")
    return str(answer.json()["token"])


@dataclass
class Simulator:
    log_file: Path
    process: subprocess.Popen[bytes]

    def stop(self) -> None:
        # SIGINT: the rig stops sending and waits for its last batches' acknowledgements
        stop_process(self.process, signal.SIGINT, 10)


def start_simulator(url: str, token: str, log_file: Path) -> Simulator:
    """`twinlink simulate tingen` against `url`; the token in its environment, not its
    command line (which any user of the machine may read)."""
    env = {**os.environ, "TWINLINK_DEVICE_TOKEN": token}
    env.pop("TWINLINK_TOKEN", None)
    with log_file.open("ab") as log:
        process = subprocess.Popen(
            [sys.executable, "-m", "twinlink", "--url", url, "simulate", "tingen", "--twin", TWIN],
            env=env,
            stdout=log,
            stderr=subprocess.STDOUT,
            stdin=subprocess.DEVNULL,
            preexec_fn=dying_with_parent(signal.SIGINT),
            process_group=0,  # a Ctrl-C in the terminal reaches the launcher alone
        )
    return Simulator(log_file, process)
