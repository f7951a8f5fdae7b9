"""What `twinlink demo` sets up for Tingen: the simulated rig streaming as the device
`tingenSAP`, and the Tingen FMU (built from its C source) running on the rig's live stream."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator, Awaitable, Callable
from pathlib import Path

import click

from twinlink.app import Services
from twinlink.domain.errors import ConflictError, NotFoundError
from twinlink.processors.fmubuild import FmuBuildError, build_if_stale
from twinlink_demo.examples import admin_principal
from twinlink_edge.simulate.runner import run_tingen

DEMO_FMU = "Tingen.fmu"
# The FMU processor of the demo: the rig's tip force in, the simulated tip angle and root
# stress out, beside the measured angle (the thesis's figure 5.3).
DEMO_PROCESSOR = {
    "name": "fmu",
    "blueprint": "fmu",
    "source": "telemetry",
    "inputs": {"F": {"signal": "Input_F_in"}},
    # The beam's first mode (about 9.5 Hz) well damped: the rig's angle is reported rectified
    # and noisy, and a lightly damped mode would ring on every corner of that signal.
    "params": {"fmu": DEMO_FMU, "outputs": ["theta", "sigma"], "parameters": {"zeta": 0.7}},
}


async def start_demo_simulator(
    services: Services, base_url: str
) -> Callable[[], Awaitable[None]] | None:
    """Give the Tingen twin a device `tingenSAP` (a fresh token each start) and run the
    simulated rig against this server; returns the function that stops it."""
    principal = await admin_principal(services)
    if principal is None:
        return None
    try:
        try:
            _, token = await services.devices.create(
                principal, "tingen", "tingenSAP", "the simulated cantilever rig (make demo)"
            )
        except ConflictError:
            _, token = await services.devices.rotate(principal, "tingen", "tingenSAP")
    except NotFoundError:
        return None
    stop = asyncio.Event()
    # The rig is stopped while the server still serves (server._Server): its last batches are
    # acknowledged within a fraction of a second, so it ends with nothing lost.
    rig = run_tingen(base_url, token, stop, close_timeout_s=3.0)
    task = asyncio.create_task(rig, name="demo-simulator")

    async def stop_simulator() -> None:
        stop.set()
        try:
            await asyncio.wait_for(task, 5)
        except Exception:  # the server is going down; the rig's last batches may be lost
            task.cancel()

    return stop_simulator


async def start_demo_fmu(services: Services, examples: Path) -> str | None:
    """Build the Tingen FMU, upload it to the tingen twin and create its processor (once);
    a line for the welcome text, or None when there is no tingen twin."""
    principal = await admin_principal(services)
    source = examples / "tingen" / "fmu"
    if principal is None or not source.is_dir():
        return None
    built = services.fmus.root / "build" / DEMO_FMU
    try:
        await asyncio.to_thread(build_if_stale, source, built)
        await services.fmus.upload(principal, "tingen", DEMO_FMU, _chunks(built))
        await services.processors.create(principal, "tingen", dict(DEMO_PROCESSOR))
    except NotFoundError:
        return None
    except ConflictError:
        pass  # made by an earlier `make demo`; it keeps its settings
    except FmuBuildError as err:
        click.echo(f"the Tingen FMU was not built: {err}", err=True)
        return None
    return "The Tingen FMU runs on the rig's stream (processor fmu, stream fmu)."


async def _chunks(path: Path) -> AsyncIterator[bytes]:
    yield await asyncio.to_thread(path.read_bytes)
