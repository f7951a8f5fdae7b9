"""`twinlink demo`: the server with demo settings, and beside it the example twins, the simulated
Tingen rig and its FMU, and the Ilmatar crane's services behind the gateway."""

from __future__ import annotations

import os
from collections.abc import Awaitable, Callable
from pathlib import Path

import click

from twinlink.app import Services
from twinlink.auth.service import Bootstrap
from twinlink.config import Settings
from twinlink.server import mqtt_port_free, print_bootstrap, serve
from twinlink_demo.crane import start_crane_services, start_demo_crane
from twinlink_demo.deployed import can_deploy, deploy_tingen
from twinlink_demo.examples import admin_principal, load_examples
from twinlink_demo.tingen import start_demo_fmu, start_demo_simulator

Stop = Callable[[], Awaitable[None]]


def serve_demo(settings: Settings, examples: Path) -> None:
    """Run the server with the demo until it is stopped (Ctrl-C). `settings` as `twinlink up`
    reads them; what they leave unset gets the demo's defaults (demo_defaults)."""
    demo_defaults(settings)
    secrets_file = settings.data_dir / "admin-credentials.txt"
    printed: list[bool] = []  # the bootstrap text, which ends with a blank line

    def bootstrap(created: Bootstrap) -> None:
        print_bootstrap(created)
        printed.append(True)
        _keep_secrets(created, secrets_file)

    async def ready(services: Services) -> Stop:
        notes, loaded, stop = await start_demo(services, settings, examples)
        welcome = _welcome(settings.base_url, loaded, examples, notes, secrets_file)
        click.echo(welcome if printed else "\n" + welcome, err=True)
        return stop

    serve(settings, on_ready=ready, on_bootstrap=bootstrap)


def demo_defaults(settings: Settings) -> None:
    """Data in ./.twinlink-demo, warnings only as text, and any free MQTT port when a broker
    already has 1883: each unless a flag, a variable or the settings file says otherwise."""
    given = settings.model_fields_set  # by a flag, a variable or the settings file
    if "data_dir" not in given:
        settings.data_dir = Path(".twinlink-demo").absolute()  # runs work in their own folders
    # A person reads the demo's output: the welcome says what runs; each device connecting
    # and each schema step would bury it.
    if "log_level" not in given:
        settings.log_level = "warning"
    if "log_format" not in given:
        settings.log_format = "text"
    if (
        settings.mqtt_mode == "embedded"
        and "mqtt_port" not in given
        and not mqtt_port_free(settings)
    ):
        settings.mqtt_port = 0  # a broker already has 1883: the demo takes any free port


def _keep_secrets(created: Bootstrap, secrets_file: Path) -> None:
    """The demo keeps its generated secrets so a second `make demo` can still sign in."""
    secrets_file.parent.mkdir(parents=True, exist_ok=True)
    fd = os.open(secrets_file, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    with os.fdopen(fd, "w") as f:
        f.write(
            f"username: {created.username}\npassword: {created.password or '(preset)'}\n"
            f"token: {created.token or '(preset)'}\n"
        )


async def start_demo(
    services: Services, settings: Settings, examples: Path
) -> tuple[list[str | None], list[str], Stop]:
    """Start everything beside the server: the lines for the welcome text, the twins loaded
    ("slug (outcome)") and the function that stops what was started."""
    # The crane's services first: the documents name the ports they really got.
    crane = await start_crane_services()
    deploy = await can_deploy(services)  # Tingen from its package: not from its document
    skip = (examples / "tingen" / "tingen.yaml",) if deploy else ()
    loaded = await load_examples(services, examples, crane.documents if crane else None, skip)
    notes, stop_simulator = await _start_tingen(services, settings, examples, deploy, loaded)
    stop_crane: Stop | None = None
    if crane is not None:
        crane_note, stop_crane = await start_demo_crane(services, crane)
        notes.append(crane_note)
    if stop_simulator is None:
        notes = []  # no Tingen twin: nothing of the demo runs
    if services.mqtt.port is not None:
        notes.append(
            f"Devices may publish over MQTT to {settings.mqtt_host}:{services.mqtt.port}, "
            f"topics twinlink/{{twin}}/{{device}}/telemetry (docs/mqtt.md)."
        )

    async def stop_all() -> None:
        for stop in (stop_simulator, stop_crane):
            if stop is not None:
                await stop()

    return notes, loaded, stop_all


async def _start_tingen(
    services: Services, settings: Settings, examples: Path, deploy: bool, loaded: list[str]
) -> tuple[list[str | None], Stop | None]:
    """Tingen deployed from its package (`deploy`) or, without the library or on an older
    demo's data, made directly; the welcome's lines and the function that stops its rig. A
    deployed twin is added to `loaded`."""
    principal = await admin_principal(services)
    if deploy and principal is not None:
        twin, notes, stop = await deploy_tingen(services, principal, examples, settings.base_url)
        if twin is not None:
            loaded.append(twin)
        return notes, stop
    stop_simulator = await start_demo_simulator(services, settings.base_url)
    notes = ["Tingen streams live from a simulated rig (device tingenSAP).",
             await start_demo_fmu(services, examples)]  # fmt: skip
    return notes, stop_simulator


def _welcome(
    url: str, loaded: list[str], examples: Path, notes: list[str | None], secrets_file: Path
) -> str:
    lines = [
        f"Demo twins: {', '.join(loaded) or f'none found in {examples}'}",
        *(note for note in notes if note),
        f"Open {url}/app/twins/tingen/live (the web app: Tingen live),",
        f"{url}/ (twins) and {url}/docs (API).",
        f"Sign in as admin; the password and token are in {secrets_file}.",
        f"CLI: twinlink --url {url} login -u admin",
    ]
    return "".join(f"  {line}\n" for line in lines)
