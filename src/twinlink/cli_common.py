"""What every client command of the CLI shares: the API client and how answers are printed."""

from __future__ import annotations

from typing import Any

import click
import orjson

from twinlink.client import Client
from twinlink.domain.yamlsource import dump_yaml


def client_for(ctx: click.Context) -> Client:
    """A client for the server and token given to the root command (or saved by login)."""
    root = ctx.find_root()
    return Client(root.obj["url"], root.obj["token"])


def emit(data: Any, as_json: bool) -> None:
    if as_json:
        click.echo(orjson.dumps(data, option=orjson.OPT_INDENT_2).decode())
    else:
        click.echo(dump_yaml(data).rstrip())
