"""`twinlink up` and `twinlink demo`: run the server in this process."""

from __future__ import annotations

import os
from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import click

from twinlink.config import load_settings

if TYPE_CHECKING:
    from twinlink.app import Services
    from twinlink.auth.service import Bootstrap

# The server's modules are imported inside the commands, so `twinlink --help` and the
# client commands start without loading the web framework.

F = TypeVar("F", bound=Callable[..., Any])


def _server_options(data_dir_default: str) -> Callable[[F], F]:
    def decorate(fn: F) -> F:
        return _add_server_options(fn, data_dir_default)

    return decorate


def _add_server_options(fn: F, data_dir_default: str) -> F:
    fn = click.option(
        "--config",
        "config_file",
        type=click.Path(dir_okay=False),
        help="TOML settings file. Env: TWINLINK_CONFIG.",
    )(fn)
    fn = click.option(
        "--data-dir",
        type=click.Path(file_okay=False, path_type=Path),
        help=f"Data folder. Env: TWINLINK_DATA_DIR [default: {data_dir_default}].",
    )(fn)
    fn = click.option(
        "--port", type=int, help="TCP port, 0 for any free one. Env: TWINLINK_PORT [default: 8000]."
    )(fn)
    fn = click.option("--host", help="Bind address. Env: TWINLINK_HOST [default: 127.0.0.1].")(fn)
    return fn


@click.command()
@_server_options("./twinlink-data")
def up(host: str | None, port: int | None, data_dir: Path | None, config_file: str | None) -> None:
    """Run the twinlink server."""
    from twinlink.server import serve

    serve(load_settings(config_file, host=host, port=port, data_dir=data_dir))


@click.command()
@_server_options("./.twinlink-demo")
@click.option(
    "--examples",
    type=click.Path(file_okay=False, path_type=Path),
    default=Path("examples"),
    show_default=True,
    help="Folder of example DT documents to load.",
)
def demo(
    host: str | None,
    port: int | None,
    data_dir: Path | None,
    config_file: str | None,
    examples: Path,
) -> None:
    """Run the server with the example twins loaded (data in ./.twinlink-demo).

    It logs warnings only, as text, unless TWINLINK_LOG_LEVEL or TWINLINK_LOG_FORMAT say
    otherwise (info and json are `twinlink up`'s defaults).
    """
    from twinlink.server import mqtt_port_free, print_bootstrap, serve

    settings = load_settings(config_file, host=host, port=port, data_dir=data_dir)
    given = settings.model_fields_set  # by a flag, a variable or the settings file
    if "data_dir" not in given:
        settings.data_dir = Path(".twinlink-demo")
    # A person reads the demo's output: the welcome below says what runs; each device
    # connecting and each schema step would bury it.
    if "log_level" not in given:
        settings.log_level = "warning"
    if "log_format" not in given:
        settings.log_format = "text"
    if (
        settings.mqtt_mode == "embedded"
        and "mqtt_port" not in settings.model_fields_set
        and not mqtt_port_free(settings)
    ):
        settings.mqtt_port = 0  # a broker already has 1883: the demo takes any free port

    secrets_file = settings.data_dir / "admin-credentials.txt"

    printed: list[bool] = []  # the bootstrap text, which ends with a blank line

    def bootstrap(created: Bootstrap) -> None:
        print_bootstrap(created)
        printed.append(True)
        # The demo keeps its generated secrets so a second `make demo` can still sign in.
        settings.data_dir.mkdir(parents=True, exist_ok=True)
        fd = os.open(secrets_file, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        with os.fdopen(fd, "w") as f:
            f.write(
                f"username: {created.username}\npassword: {created.password or '(preset)'}\n"
                f"token: {created.token or '(preset)'}\n"
            )

    async def ready(services: Services) -> Callable[[], Awaitable[None]] | None:
        from twinlink.demo import load_examples, start_demo_fmu, start_demo_simulator
        from twinlink.demo_crane import start_crane_services, start_demo_crane

        # The crane's services first: the documents name the ports they really got.
        crane = await start_crane_services()
        loaded = await load_examples(services, examples, crane.documents if crane else None)
        stop_simulator = await start_demo_simulator(services, settings.base_url)
        notes = [await start_demo_fmu(services, examples)]
        stop_crane: Callable[[], Awaitable[None]] | None = None
        if crane is not None:
            crane_note, stop_crane = await start_demo_crane(services, crane)
            notes.append(crane_note)
        if stop_simulator is None:
            notes = []  # no Tingen twin: nothing of the demo runs
        else:
            notes.insert(0, "Tingen streams live from a simulated rig (device tingenSAP).")
        if services.mqtt.port is not None:
            notes.append(
                f"Devices may publish over MQTT to {settings.mqtt_host}:{services.mqtt.port}, "
                f"topics twinlink/{{twin}}/{{device}}/telemetry (docs/mqtt.md)."
            )
        welcome = _welcome(settings.base_url, loaded, examples, notes, secrets_file)
        click.echo(welcome if printed else "\n" + welcome, err=True)

        async def stop_all() -> None:
            for stop in (stop_simulator, stop_crane):
                if stop is not None:
                    await stop()

        return stop_all

    serve(settings, on_ready=ready, on_bootstrap=bootstrap)


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
