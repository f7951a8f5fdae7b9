"""`twinlink up` and `twinlink demo`: run the server in this process (the demo's own parts come
from its package, examples/demo)."""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import click

from twinlink.config import Settings, load_settings

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
@click.option(
    "--store-url",
    help="PostgreSQL database shared by the nodes, postgresql://user:password@host:port/db. "
    "Env: TWINLINK_STORE_URL [default: the embedded SQLite store in the data folder].",
)
@click.option(
    "--bus-url",
    help="Apache Kafka brokers shared by the nodes, kafka://host:port[,host:port...]. "
    "Env: TWINLINK_BUS_URL [default: the in-process bus].",
)
@click.option(
    "--workers",
    type=click.IntRange(1, 64),
    help="Server processes on this machine, sharing the port; more than 1 needs the store and "
    "bus URLs (PostgreSQL and Kafka). Env: TWINLINK_WORKERS [default: 1].",
)
def up(
    host: str | None,
    port: int | None,
    data_dir: Path | None,
    config_file: str | None,
    store_url: str | None,
    bus_url: str | None,
    workers: int | None,
) -> None:
    """Run the twinlink server."""
    settings = load_settings(
        config_file, host=host, port=port, data_dir=data_dir, store_url=store_url,
        bus_url=bus_url, workers=workers,
    )  # fmt: skip
    if settings.workers > 1:
        from twinlink.workers import run

        sys.exit(run(settings))
    from twinlink.server import serve

    serve(settings)


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
    otherwise (info and json are `twinlink up`'s defaults). The demo is no part of twinlink but
    a package of its own, examples/demo, which `make demo` installs.
    """
    serve_demo = _demo()
    serve_demo(load_settings(config_file, host=host, port=port, data_dir=data_dir), examples)


# The demo's packages: the demo itself, and the crane services it starts.
_DEMO_MODULES = ("twinlink_demo", "ilmatar_crane")


def _demo() -> Callable[[Settings, Path], None]:
    """The demo's entry point; a clear error, not a traceback, when it is not installed (the
    product installs without it: `pip install -e .`)."""
    try:
        from twinlink_demo import serve_demo
    except ModuleNotFoundError as err:
        if err.name not in _DEMO_MODULES:
            raise  # a fault inside the demo, not a missing demo: its traceback says where
        raise click.ClickException(
            f"the demo is not installed (no module {err.name}): "
            "pip install -e examples/ilmatar -e examples/demo (make demo does)"
        ) from err
    return serve_demo
