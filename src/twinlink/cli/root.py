"""The `twinlink` command itself: the options every command shares, and the list of commands,
one module per area (`twinlink up` and `demo` in server.py, `twinlink twins` in admin.py, ...)."""

from __future__ import annotations

from typing import Any

import click

from twinlink.cli.admin import devices, tokens, twins, users
from twinlink.cli.apply import apply
from twinlink.cli.client import ApiCallError
from twinlink.cli.cluster import cluster
from twinlink.cli.commands import commands, properties, send
from twinlink.cli.common import HelpGroup
from twinlink.cli.connectors import connectors
from twinlink.cli.cosim import cosim
from twinlink.cli.deploy import deploy
from twinlink.cli.exporting import export
from twinlink.cli.gateway import audit, service_accounts, services
from twinlink.cli.history import history
from twinlink.cli.importformats import FORMAT_COMMANDS
from twinlink.cli.importing import import_
from twinlink.cli.library import lib
from twinlink.cli.processors import blueprints, fmus, processors
from twinlink.cli.search import search
from twinlink.cli.server import demo, up
from twinlink.cli.session import login, logout
from twinlink.cli.simulate import simulate
from twinlink.client import ApiError
from twinlink.config import ConfigError


class _Group(HelpGroup):
    """Turns an ApiCallError into a clear message and exit status 1, never a traceback; in
    click's own style ("Error: ..."), as its usage errors are."""

    def invoke(self, ctx: click.Context) -> Any:
        try:
            return super().invoke(ctx)
        except (ApiCallError, ApiError, ConfigError) as err:
            raise click.ClickException(str(err)) from err


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.option(
    "--url",
    envvar="TWINLINK_URL",
    help="Server URL [default: saved by login, else http://127.0.0.1:8000]. Env: TWINLINK_URL.",
)
@click.option(
    "--token",
    envvar="TWINLINK_TOKEN",
    help="API token [default: saved by login]. Env: TWINLINK_TOKEN.",
)
@click.version_option(package_name="twinlink")
@click.pass_context
def main(ctx: click.Context, url: str | None, token: str | None) -> None:
    """twinlink: an open-source digital twin platform.

    `twinlink up` runs the server; the other commands talk to a running server.
    """
    ctx.ensure_object(dict)
    ctx.obj.update(url=url, token=token)


# `twinlink --help` lists them by name, whatever the order here.
COMMANDS: tuple[click.Command, ...] = (
    up,
    demo,
    cluster,
    login,
    logout,
    apply,
    search,
    import_,
    export,
    twins,
    devices,
    users,
    tokens,
    simulate,
    send,
    commands,
    properties,
    history,
    blueprints,
    processors,
    fmus,
    connectors,
    services,
    audit,
    service_accounts,
    lib,
    deploy,
    cosim,
)
for _command in COMMANDS:
    main.add_command(_command)
# `twinlink import wot-td|dtdl|aas` beside `import twinbase` (cli/importformats.py)
for _command in FORMAT_COMMANDS:
    import_.add_command(_command)
