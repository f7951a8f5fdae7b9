"""`twinlink lib`: the asset library (ls, push, pull, show, versions, tag, rm) and the import
of a DTaaS digital twin folder, through twinlink.client (streamed both ways)."""

from __future__ import annotations

import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import click

from twinlink.cli.common import HelpGroup, client_for, emit, table
from twinlink.cli.dtaas import read_dtaas, twin_yaml
from twinlink.client import Client
from twinlink.client.refs import KINDS

KIND = click.Choice(KINDS)
SCOPE_HELP = "common, group:G, user:U or me"


@contextmanager
def api_client(ctx: click.Context) -> Iterator[Client]:
    """twinlink.client for the server and token of the root command (or saved by login);
    a reference or file the person got wrong is a usage error, not a traceback."""
    resolved = client_for(ctx)
    resolved.http.close()
    with Client(resolved.url, resolved.token) as client:
        try:
            yield client
        except (ValueError, OSError) as err:
            raise click.ClickException(str(err)) from err


def short(digest: str | None) -> str:
    """`sha256:0123456789ab`: enough of a digest to tell versions apart (and a valid ref)."""
    return (digest or "")[:19]


def size(n: int) -> str:
    if n < 1000:
        return f"{n} B"
    value = float(n)
    for unit in ("kB", "MB", "GB"):
        value /= 1000
        if value < 1000 or unit == "GB":
            break
    return f"{value:.1f} {unit}"


@click.group(cls=HelpGroup)
def lib() -> None:
    """The asset library: data, models, tools, functions and twin packages, versioned."""


@lib.command("ls")
@click.option("--kind", type=KIND, help="Only assets of this kind.")
@click.option("--scope", help=f"Only assets of this scope: {SCOPE_HELP}.")
@click.option("-q", "--query", help="Only assets matching these words.")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.pass_context
def lib_ls(
    ctx: click.Context, kind: str | None, scope: str | None, query: str | None, as_json: bool
) -> None:
    """List the assets you may read."""
    with api_client(ctx) as client:
        assets = client.library.ls(kind=kind, scope=scope, q=query)
    if as_json:
        emit(assets, True)
        return
    rows = [
        [a["ref"], ",".join(sorted(a.get("tags") or {})), str(a.get("versions", "")),
         (a.get("description") or "").splitlines()[0][:60] if a.get("description") else ""]
        for a in assets
    ]  # fmt: skip
    table(["ASSET", "TAGS", "VERSIONS", "DESCRIPTION"], rows)


def _pushed(answer: dict[str, Any]) -> str:
    asset, version = answer["asset"], answer["version"]
    files = len(version.get("files") or [])
    what = "pushed" if answer.get("created") else "unchanged (same content as)"
    tags = ", ".join(version.get("tags") or [])
    return (
        f"{what} {asset['scope']}/{asset['kind']}/{asset['name']}@{short(version['digest'])}"
        f" ({files} file{'s' if files != 1 else ''}, {size(version.get('size', 0))})"
        + (f" tags: {tags}" if tags else "")
    )


@lib.command("push")
@click.argument("path", type=click.Path(exists=True))
@click.option("--kind", type=KIND, required=True, help="What the asset is.")
@click.option("--name", required=True, help="The asset's name (lower case, digits, . _ -).")
@click.option("--scope", default="me", show_default=True, help=f"Where: {SCOPE_HELP}.")
@click.option("--tag", "tags", multiple=True, help="Tag the version (repeat); latest moves too.")
@click.option("--description", help="The asset's description.")
@click.pass_context
def lib_push(
    ctx: click.Context, path: str, kind: str, name: str, scope: str, tags: tuple[str, ...],
    description: str | None,
) -> None:  # fmt: skip
    """Push PATH as a new version: a folder's contents (streamed as tar), or one file."""
    with api_client(ctx) as client:
        answer = client.library.push(
            path, kind=kind, name=name, scope=scope, tags=tags, description=description
        )
    click.echo(_pushed(answer))


@lib.command("pull")
@click.argument("ref")
@click.option("-o", "--output", default=".", show_default=True, help="Unpack into this folder.")
@click.option("--archive", type=click.Path(dir_okay=False), help="Save the archive as it is "
              "instead (.tar, .tgz or .zip by the name).")  # fmt: skip
@click.pass_context
def lib_pull(ctx: click.Context, ref: str, output: str, archive: str | None) -> None:
    """Fetch REF ([scope/]kind/name[@tag][#file]): unpacked (unsafe paths refused), one
    file with #file, or the archive."""
    with api_client(ctx) as client:
        written = client.library.pull(ref, output, archive=archive)
    click.echo(f"pulled {ref} into {written}")


@lib.command("show")
@click.argument("ref")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.pass_context
def lib_show(ctx: click.Context, ref: str, as_json: bool) -> None:
    """An asset with its tags and versions; with @version, that version and its files."""
    with api_client(ctx) as client:
        found = client.library.version(ref) if "@" in ref else client.library.show(ref)
    emit(found, as_json)


@lib.command("versions")
@click.argument("ref")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.pass_context
def lib_versions(ctx: click.Context, ref: str, as_json: bool) -> None:
    """The versions of REF, newest first."""
    with api_client(ctx) as client:
        versions = client.library.versions(ref)
    if as_json:
        emit(versions, True)
        return
    rows = [
        [short(v["digest"]), ",".join(v.get("tags") or []), size(v.get("size", 0)),
         v.get("created_by") or ""]
        for v in versions
    ]  # fmt: skip
    table(["VERSION", "TAGS", "SIZE", "BY"], rows)


@lib.command("tag")
@click.argument("ref")
@click.argument("tag")
@click.pass_context
def lib_tag(ctx: click.Context, ref: str, tag: str) -> None:
    """Point TAG at REF's version (moved if it points elsewhere)."""
    with api_client(ctx) as client:
        found = client.library.locate(ref)
        client.library.tag(found, tag)
    click.echo(f"tagged {found.scope}/{found.kind}/{found.name}@{found.version or 'latest'} {tag}")


@lib.command("rm")
@click.argument("ref")
@click.option("--version", help="Delete only this version (a tag or digest).")
@click.pass_context
def lib_rm(ctx: click.Context, ref: str, version: str | None) -> None:
    """Delete an asset, or one version of it; refused while a deployment uses it."""
    with api_client(ctx) as client:
        found = client.library.locate(ref)
        client.library.rm(found, version)
    chosen = version or found.version
    click.echo(
        f"deleted {found.scope}/{found.kind}/{found.name}" + (f"@{chosen}" if chosen else "")
    )


@lib.command("import-dtaas")
@click.argument("folder", type=click.Path(exists=True, file_okay=False, path_type=Path))
@click.option("--name", help="The twin package's name [the folder's].")
@click.option("--scope", default="me", show_default=True, help=f"Where: {SCOPE_HELP}.")
@click.option("--tag", "tags", multiple=True, help="Tag both versions (repeat).")
@click.pass_context
def lib_import_dtaas(
    ctx: click.Context, folder: Path, name: str | None, scope: str, tags: tuple[str, ...]
) -> None:
    """Import a DTaaS digital twin FOLDER unchanged as a twin package: description, README,
    configuration and lifecycle scripts, plus a generated twin.yaml; its configuration
    files also become the data asset NAME-config. Every lifecycle phase it has can then be
    run with `twinlink deploy run`."""
    with api_client(ctx) as client:
        twin = read_dtaas(folder, name)
        config_ref = None
        if twin.config:
            pushed = client.library.push_files(
                twin.config, kind="data", name=f"{twin.name}-config", scope=scope, tags=tags,
                description=f"Configuration of the DTaaS digital twin {twin.name}",
            )  # fmt: skip
            click.echo(_pushed(pushed))
            asset, digest = pushed["asset"], pushed["version"]["digest"]
            config_ref = f"lib:{asset['scope']}/data/{asset['name']}@{digest}"
        with tempfile.TemporaryDirectory() as tmp:
            generated = Path(tmp) / "twin.yaml"
            generated.write_text(twin_yaml(twin, config_ref), "utf-8")
            pushed = client.library.push_files(
                sorted([*twin.files, ("twin.yaml", generated)]), kind="twins", name=twin.name,
                scope=scope, tags=tags, description=twin.description or None,
            )  # fmt: skip
    click.echo(_pushed(pushed))
    asset = pushed["asset"]
    click.echo(f"lifecycle phases: {', '.join(twin.phases)}")
    click.echo(
        f"deploy it: twinlink deploy create {asset['scope']}/twins/{asset['name']} "
        f"--name {twin.name}"
    )
