"""The `twinlink` command: runs the server and talks to a running one over the API."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import click

from twinlink.cli_common import HelpGroup, client_for, emit
from twinlink.client import ClientError, forget_credentials, save_credentials
from twinlink.config import ConfigError

YAML_SUFFIXES = (".yaml", ".yml", ".json")


class _Group(HelpGroup):
    """Turns a ClientError into a clear message and exit status 1, never a traceback; in
    click's own style ("Error: ..."), as its usage errors are."""

    def invoke(self, ctx: click.Context) -> Any:
        try:
            return super().invoke(ctx)
        except (ClientError, ConfigError) as err:
            raise click.ClickException(str(err)) from None


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


from twinlink.cli_server import demo, up  # noqa: E402

main.add_command(up)
main.add_command(demo)


@main.command()
@click.option("-u", "--username", prompt=True, help="User name.")
@click.option(
    "-p", "--password", prompt=True, hide_input=True, help="Password (prompted if left out)."
)
@click.pass_context
def login(ctx: click.Context, username: str, password: str) -> None:
    """Sign in and save a session token for the other commands."""
    client = client_for(ctx)
    answer = client.json(
        "POST", "/api/v1/auth/login", json={"username": username, "password": password}
    )
    path = save_credentials(client.url, answer["token"])
    click.echo(
        f"Signed in to {client.url} as {username}; token saved in {path}"
        f" (expires {answer['expires']})."
    )


@main.command()
@click.pass_context
def logout(ctx: click.Context) -> None:
    """Revoke the saved session token and forget it."""
    client = client_for(ctx)
    if client.token:
        try:
            client.json("POST", "/api/v1/auth/logout")
        except ClientError as err:
            click.echo(
                f"note: the server did not revoke the token ({err.args[0].splitlines()[0]})",
                err=True,
            )
    path = forget_credentials()
    click.echo(f"Signed out; {path} removed." if path else "Signed out.")


def _document_files(paths: tuple[str, ...]) -> list[Path]:
    files: list[Path] = []
    for p in map(Path, paths):
        if p.is_dir():
            files.extend(
                sorted(f for f in p.rglob("*") if f.suffix in YAML_SUFFIXES and f.is_file())
            )
        else:
            files.append(p)
    return files


@main.command(short_help="Create or update twins and connectors from files; idempotent.")
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
            except ClientError as err:
                click.echo(f"{name}: {err}", err=True)
                failed = True
            continue
        try:
            answer = client.json(
                "POST", "/api/v1/apply", content=body, headers={"Content-Type": kind}
            )
        except ClientError as err:
            click.echo(f"{name}: {err}", err=True)
            failed = True
            continue
        for r in answer["results"]:
            click.echo(f"twin/{r['slug']} {r['outcome']} ({', '.join(r['levels'])})")
    if failed:
        ctx.exit(1)


@main.command()
@click.argument("query", nargs=-1)
@click.option("-k", "--keyword", help="Only twins with a feature of this keyword.")
@click.option("-n", "--limit", default=20, show_default=True, help="Most hits to show.")
@click.option("--json", "as_json", is_flag=True, help="Print the raw JSON answer.")
@click.pass_context
def search(
    ctx: click.Context, query: tuple[str, ...], keyword: str | None, limit: int, as_json: bool
) -> None:
    """Find twins and the features that match QUERY."""
    answer = client_for(ctx).json(
        "GET", "/api/v1/search", params={"q": " ".join(query), "keyword": keyword, "limit": limit}
    )
    if as_json:
        emit(answer, True)
        return
    for hit in answer["hits"]:
        features = [m["feature"] for m in hit["matches"] if m["feature"]]
        where = f"  features: {', '.join(features)}" if features else ""
        click.echo(f"{hit['slug']:<24} {hit['name']}{where}")
    click.echo(f"({answer['total']} twin{'s' if answer['total'] != 1 else ''})")


from twinlink.cli_admin import devices, tokens, twins, users  # noqa: E402

main.add_command(devices)
main.add_command(twins)
main.add_command(users)
main.add_command(tokens)

from twinlink.cli_simulate import simulate  # noqa: E402

main.add_command(simulate)

from twinlink.cli_commands import commands, properties, send  # noqa: E402

main.add_command(send)
main.add_command(commands)
main.add_command(properties)

from twinlink.cli_history import history  # noqa: E402

main.add_command(history)

from twinlink.cli_processors import blueprints, fmus, processors  # noqa: E402

main.add_command(blueprints)
main.add_command(processors)
main.add_command(fmus)

from twinlink.cli_connectors import apply_connectors, connector_file, connectors  # noqa: E402
from twinlink.cli_gateway import audit, service_accounts, services  # noqa: E402

main.add_command(services)
main.add_command(audit)
main.add_command(service_accounts)
main.add_command(connectors)
