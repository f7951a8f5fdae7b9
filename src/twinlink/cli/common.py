"""What every client command of the CLI shares: the API client and how answers are printed."""

from __future__ import annotations

from typing import Any

import click
import orjson

from twinlink.cli.client import Client
from twinlink.domain.yamlsource import dump_yaml

# Significant digits of a float in a table: a value read off a sensor or a model rarely
# means more, and 17 digits (0.047762825065048614) hide the ones that do. --json prints all.
FLOAT_DIGITS = 6


class HelpGroup(click.Group):
    """A command group whose list of commands shows each one's summary whole, wrapped to the
    terminal, where click would cut it off with "..." at the width left over."""

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        rows = []
        for name in self.list_commands(ctx):
            command = self.get_command(ctx, name)
            if command is not None and not command.hidden:
                rows.append((name, command.get_short_help_str(limit=1_000)))
        if rows:
            with formatter.section("Commands"):
                formatter.write_dl(rows)


def client_for(ctx: click.Context) -> Client:
    """A client for the server and token given to the root command (or saved by login)."""
    root = ctx.find_root()
    return Client(root.obj["url"], root.obj["token"])


def emit(data: Any, as_json: bool) -> None:
    if as_json:
        click.echo(orjson.dumps(data, option=orjson.OPT_INDENT_2).decode())
    else:
        click.echo(dump_yaml(data).rstrip())


def show_value(value: Any) -> str:
    """A value in a table cell: floats to FLOAT_DIGITS significant digits, JSON's spelling
    of true, false and null (empty)."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return f"{value:.{FLOAT_DIGITS}g}"
    if isinstance(value, dict | list):
        return orjson.dumps(value).decode()
    return str(value)


def table(header: list[str], rows: list[list[str]]) -> None:
    """Print `rows` under `header` in columns as wide as their widest cell."""
    widths = [len(h) for h in header]
    for row in rows:
        widths = [max(w, len(cell)) for w, cell in zip(widths, row, strict=True)]
    for line in [header, *rows]:
        click.echo("  ".join(cell.ljust(w) for cell, w in zip(line, widths, strict=True)).rstrip())
