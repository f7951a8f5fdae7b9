"""`twinlink export`: a twin's document as YAML or JSON, or converted to an exchange format
(WoT Thing Description, DTDL, Asset Administration Shell JSON or AASX) by the server.

The server converts (docs/formats.md "Endpoints and commands"): it knows the twin's public URL
and which listeners run, so the links in an export are the ones clients really reach, and the
document converted is the one this token may read, never more.
"""

from __future__ import annotations

import sys
from pathlib import Path
from urllib.parse import quote

import click

from twinlink.cli.common import client_for

# The format names of `GET /twins/{slug}?format=`, plus the AASX package of its own route.
EXPORT_FORMATS = ("yaml", "json", "wot-td", "dtdl", "aas-json", "aasx")


def export_path(slug: str, fmt: str) -> tuple[str, dict[str, str]]:
    """The server's path and query of one export."""
    twin = quote(slug, safe="")
    if fmt == "aasx":
        return f"/twins/{twin}/export.aasx", {}
    return f"/twins/{twin}", {"format": fmt}


@click.command(short_help="A twin's document as YAML, JSON, WoT TD, DTDL, AAS JSON or AASX.")
@click.argument("slug")
@click.option(
    "-f",
    "--format",
    "fmt",
    type=click.Choice(EXPORT_FORMATS),
    default="yaml",
    show_default=True,
    help="yaml or json: the DT document; wot-td: a W3C WoT Thing Description 1.1; dtdl: a "
    "DTDL v3 Interface; aas-json: an Asset Administration Shell environment; aasx: the same "
    "as an AASX package (a binary file: give -o).",
)
@click.option(
    "-o",
    "--output",
    type=click.Path(path_type=Path, dir_okay=False),
    help="File to write [default: standard output]; written whole or not at all.",
)
@click.pass_context
def export(ctx: click.Context, slug: str, fmt: str, output: Path | None) -> None:
    """Write twin SLUG's document, as the token may read it, in a format.

    A twin without a public part needs a token (--token, TWINLINK_TOKEN or `twinlink login`).
    """
    if fmt == "aasx" and output is None and sys.stdout.isatty():
        # A zip package on a terminal is noise, and may leave it in a strange state.
        raise click.UsageError("an AASX package is a binary file: write it with -o FILE.")
    path, params = export_path(slug, fmt)
    body = client_for(ctx).request("GET", path, params=params).content
    if output is None or str(output) == "-":
        sys.stdout.buffer.write(body)
        sys.stdout.buffer.flush()
        return
    # Written beside the target and renamed: an interrupted run leaves no half file under its
    # name (an AASX cut short is a broken zip).
    partial = output.with_name(output.name + ".part")
    try:
        partial.write_bytes(body)
        partial.replace(output)
    except OSError as err:
        partial.unlink(missing_ok=True)
        raise click.ClickException(f"cannot write {output}: {err.strerror}") from err
    click.echo(f"wrote {len(body)} bytes ({fmt}) to {output}", err=True)
