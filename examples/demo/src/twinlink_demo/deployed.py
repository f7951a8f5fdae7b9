"""What `twinlink demo` does for Tingen when the server has the asset library and deployments:
the Tingen assets pushed to `common` (the FMU built from its C source, the simulated rig as a
tool, the twin package `tingen-rig`) and the package deployed and started as the deployment
`tingen`, so the twin, its device, its FMU processor and its rig come from the package.

Pushing the same content again makes no new version, so each start finds the deployment it
made before and starts it again. A data dir from an older demo, whose twin `tingen` was made
directly, keeps that twin: the demo then runs it as before (twinlink_demo.tingen).
"""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator, Awaitable, Callable
from pathlib import Path

import click

from twinlink.app import Services
from twinlink.auth.rights import Principal
from twinlink.client._tar import folder_files, pack
from twinlink.domain.errors import TwinlinkError
from twinlink.processors.fmubuild import FmuBuildError, build_if_stale
from twinlink_edge.simulate.runner import run_tingen

TINGEN = "tingen"  # the deployment, and so the twin
PACKAGE = "common/twins/tingen-rig@1.0.0"
TAGS = ("1.0.0", "latest")
Stop = Callable[[], Awaitable[None]]


async def can_deploy(services: Services) -> bool:
    """Whether Tingen comes from its package: the server has a library and deployments, and
    no twin `tingen` that a deployment did not make (an older demo's data)."""
    deployments = getattr(services, "deployments", None)
    if getattr(services, "library", None) is None or deployments is None:
        return False
    if await deployments.store.find_deployment(TINGEN) is not None:
        return True
    return await services.registry.get_twin(TINGEN) is None


async def deploy_tingen(
    services: Services, principal: Principal, examples: Path, base_url: str
) -> tuple[str | None, list[str | None], Stop | None]:
    """Push the Tingen assets, create the deployment `tingen` (once) and start it; the twin's
    "slug (outcome)", the lines for the welcome text and the function that stops it."""
    try:
        await push_assets(services, principal, examples)
    except (FmuBuildError, TwinlinkError) as err:
        click.echo(f"the Tingen package was not pushed: {err}", err=True)
        return None, [], None
    deployments = services.deployments
    assert deployments is not None
    try:
        record = await deployments.store.find_deployment(TINGEN)
        if record is None or not record.live:
            made = await deployments.create(principal, PACKAGE, TINGEN, {}, None, start=True)
            record, outcome = made.record, "created"
        else:
            if record.state == "running":  # the last demo did not stop it: its rig ended
                await deployments.stop(principal, TINGEN)
            record, outcome = await deployments.start(principal, TINGEN), "unchanged"
    except TwinlinkError as err:
        click.echo(f"the Tingen package was not deployed: {err}", err=True)
        return None, [], None
    notes: list[str | None] = [
        f"Tingen is deployed from the library's package {PACKAGE} (deployment {TINGEN})."
    ]
    stop_rig = None
    if getattr(deployments, "runs", None) is not None:
        notes.append("Its simulated rig streams as the device tingenSAP (the execute phase).")
    else:  # runs are not set up here: the rig runs in this process instead
        tokens = deployments.device_tokens(record)
        stop_rig = _in_process_rig(base_url, tokens["tingenSAP"])
        notes.append("Its simulated rig streams as the device tingenSAP.")
    notes.append("The Tingen FMU runs on the rig's stream (processor fmu, stream fmu).")

    async def stop() -> None:
        if stop_rig is not None:
            await stop_rig()
        # Stopped, it is started again (its execute phase with it) at the next demo.
        try:
            await deployments.stop(principal, TINGEN)
        except TwinlinkError as err:
            click.echo(f"the deployment {TINGEN} did not stop: {err}", err=True)

    return f"{TINGEN} ({outcome})", notes, stop


async def push_assets(services: Services, principal: Principal, examples: Path) -> None:
    """The FMU (built when its sources changed), the rig tool and the package, to `common`."""
    library = services.library
    assert library is not None
    built = services.fmus.root / "build" / "Tingen.fmu"
    await asyncio.to_thread(build_if_stale, examples / "tingen" / "fmu", built)
    await library.push(
        principal, "common", "models", "tingen-beam", _file(built), "file",
        filename="tingen.fmu", tags=TAGS,
    )  # fmt: skip
    for kind, name in (("tools", "tingen-sim"), ("twins", "tingen-rig")):
        folder = examples / "library" / name
        await library.push(principal, "common", kind, name, _tar(folder), "tar", tags=TAGS)


def _in_process_rig(base_url: str, token: str) -> Stop:
    stop = asyncio.Event()
    # The rig is stopped while the server still serves (server._Server): its last batches are
    # acknowledged within a fraction of a second, so it ends with nothing lost.
    task = asyncio.create_task(
        run_tingen(base_url, token, stop, close_timeout_s=3.0), name="demo-simulator"
    )

    async def stop_rig() -> None:
        stop.set()
        try:
            await asyncio.wait_for(task, 5)
        except Exception:  # the server is going down; the rig's last batches may be lost
            task.cancel()

    return stop_rig


async def _file(path: Path) -> AsyncIterator[bytes]:
    yield await asyncio.to_thread(path.read_bytes)


async def _tar(folder: Path) -> AsyncIterator[bytes]:
    """The folder's contents as a tar stream (small folders: packed off the event loop)."""
    chunks = await asyncio.to_thread(lambda: list(pack(folder_files(folder))))
    for chunk in chunks:
        yield chunk
