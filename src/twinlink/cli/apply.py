"""`twinlink apply`: twins from DT documents and connectors from connector files, idempotent."""

from __future__ import annotations

import sys
from pathlib import Path

import click

from twinlink.cli.client import ApiCallError
from twinlink.cli.common import client_for
from twinlink.cli.connectors import apply_connectors, connector_file

YAML_SUFFIXES = (".yaml", ".yml", ".json")
# A folder holding one of these is a library asset (a twin package, a DTaaS twin, an asset with
# its metadata): it is pushed with `twinlink lib push`, and its YAML is no DT document.
ASSET_MARKERS = ("twin.yaml", "asset.yaml", "lifecycle")


def _document_files(paths: tuple[str, ...]) -> list[Path]:
    files: list[Path] = []
    for p in map(Path, paths):
        if p.is_dir():
            assets = {m.parent for name in ASSET_MARKERS for m in p.rglob(name)}
            files.extend(
                sorted(
                    f
                    for f in p.rglob("*")
                    if f.suffix in YAML_SUFFIXES
                    and f.is_file()
                    and not assets.intersection(f.parents)
                )
            )
        else:
            files.append(p)
    return files


@click.command(short_help="Create or update twins and connectors from files; idempotent.")
@click.option(
    "-f",
    "--filename",
    "paths",
    multiple=True,
    required=True,
    help="A YAML/JSON file, a folder of them, or - for standard input. Repeatable.",
)
@click.pass_context
def apply(ctx: click.Context, paths: tuple[str, ...]) -> None:
    """Create or update twins from DT documents, and connectors from connector files
    (`twin:` and `connectors:` at the top); idempotent, like kubectl apply."""
    client = client_for(ctx)
    failed = False
    sources: list[tuple[str, bytes]] = []
    for path in paths:
        if path == "-":
            sources.append(("<stdin>", sys.stdin.buffer.read()))
    for f in _document_files(tuple(p for p in paths if p != "-")):
        try:
            sources.append((str(f), f.read_bytes()))
        except OSError as err:
            raise click.ClickException(f"cannot read {f}: {err.strerror}") from err
    for name, body in sources:
        kind = "application/json" if name.endswith(".json") else "application/yaml"
        connector_docs = connector_file(body.decode("utf-8", "replace"))
        if connector_docs is not None:
            try:
                for line in apply_connectors(client, connector_docs):
                    click.echo(line)
            except ApiCallError as err:
                click.echo(f"{name}: {err}", err=True)
                failed = True
            continue
        try:
            answer = client.json(
                "POST", "/api/v1/apply", content=body, headers={"Content-Type": kind}
            )
        except ApiCallError as err:
            click.echo(f"{name}: {err}", err=True)
            failed = True
            continue
        for r in answer["results"]:
            click.echo(f"twin/{r['slug']} {r['outcome']} ({', '.join(r['levels'])})")
    if failed:
        ctx.exit(1)
