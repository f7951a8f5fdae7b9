"""`twinlink connectors` over the API, and connector files for `twinlink apply`."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click
import yaml

from twinlink.cli.client import ApiCallError, Client
from twinlink.cli.commands import parse_assignments
from twinlink.cli.common import HelpGroup, client_for, emit, table


def _base(twin: str) -> str:
    return f"/api/v1/twins/{twin}/connectors"


_HEADER = ["NAME", "KIND", "DEVICE", "STATE", "MESSAGES", "SAMPLES", "ERRORS"]


def _row(c: dict[str, Any]) -> list[str]:
    s = c["status"]
    state = s["state"] if c["enabled"] else "disabled"
    figures = [str(s["messages"]), str(s["samples"]), str(s["error_count"])]
    return [c["name"], c["kind"], c["device"], state, *figures]


def _line(c: dict[str, Any]) -> str:
    return "  ".join(_row(c))


@click.group(cls=HelpGroup)
def connectors() -> None:
    """Connectors of a twin: UDP datasources and OPC UA servers feeding one of its devices."""


@connectors.command("kinds")
@click.option("--json", "as_json", is_flag=True, help="Print JSON with each kind's schema.")
@click.pass_context
def connectors_kinds(ctx: click.Context, as_json: bool) -> None:
    """The kinds of connector and their settings."""
    kinds = client_for(ctx).json("GET", "/api/v1/connector-kinds")["kinds"]
    if as_json:
        emit(kinds, True)
        return
    for k in kinds:
        if "error" in k:
            click.echo(f"{k['kind']}: {k['error']}")
            continue
        title = (k["description"].splitlines() or [""])[0]
        click.echo(f"{k['kind']}: {title}")
        for name, prop in k["schema"].get("properties", {}).items():
            click.echo(f"  {name:<24} {prop.get('description', '')}")


@connectors.command("ls")
@click.argument("twin")
@click.pass_context
def connectors_ls(ctx: click.Context, twin: str) -> None:
    """List TWIN's connectors with their state and figures."""
    found = client_for(ctx).json("GET", _base(twin))["connectors"]
    if not found:
        click.echo(f"{twin} has no connectors.")
        return
    table(_HEADER, [_row(c) for c in found])


@connectors.command("show")
@click.argument("twin")
@click.argument("name")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.pass_context
def connectors_show(ctx: click.Context, twin: str, name: str, as_json: bool) -> None:
    """Show a connector: its settings (never its secrets) and status."""
    emit(client_for(ctx).json("GET", f"{_base(twin)}/{name}"), as_json)


@connectors.command("add")
@click.argument("twin")
@click.argument("name")
@click.argument("kind")
@click.option(
    "-f", "--file", "config_file", type=click.Path(exists=True, dir_okay=False),
    help="The connector's config as YAML or JSON (-s settings override it).",
)  # fmt: skip
@click.option("-s", "--set", "settings", multiple=True, help="A setting, key=value (JSON).")
@click.option("--device", help="The device it speaks for [a device named after it, made now].")
@click.option("--stopped", is_flag=True, help="Create it without starting it.")
@click.pass_context
def connectors_add(
    ctx: click.Context, twin: str, name: str, kind: str, config_file: str | None,
    settings: tuple[str, ...], device: str | None, stopped: bool,
) -> None:  # fmt: skip
    """Create connector NAME of KIND on TWIN; it starts at once."""
    config: dict[str, Any] = {}
    if config_file:
        config = yaml.safe_load(Path(config_file).read_text()) or {}
    config.update(parse_assignments(settings))
    body: dict[str, Any] = {"name": name, "kind": kind, "config": config}
    if device:
        body["device"] = device
    if stopped:
        body["enabled"] = False
    click.echo(_line(client_for(ctx).json("POST", _base(twin), json=body)))


@connectors.command("set")
@click.argument("twin")
@click.argument("name")
@click.option("-s", "--set", "settings", multiple=True, help="A setting, key=value (JSON).")
@click.pass_context
def connectors_set(ctx: click.Context, twin: str, name: str, settings: tuple[str, ...]) -> None:
    """Change settings of a connector; it restarts with them."""
    changes = {"config": parse_assignments(settings)}
    click.echo(_line(client_for(ctx).json("PATCH", f"{_base(twin)}/{name}", json=changes)))


def _action(verb: str, help_text: str) -> None:
    @connectors.command(verb, help=help_text)
    @click.argument("twin")
    @click.argument("name")
    @click.pass_context
    def run(ctx: click.Context, twin: str, name: str) -> None:
        click.echo(_line(client_for(ctx).json("POST", f"{_base(twin)}/{name}/{verb}")))


_action("start", "Enable and start a connector.")
_action("stop", "Stop and disable a connector.")
_action("restart", "Restart a connector.")


@connectors.command("rm")
@click.argument("twin")
@click.argument("name")
@click.pass_context
def connectors_rm(ctx: click.Context, twin: str, name: str) -> None:
    """Delete a connector (its device and the device's data stay)."""
    client_for(ctx).request("DELETE", f"{_base(twin)}/{name}")
    click.echo(f"deleted connector {name}")


# -- connector files for `twinlink apply` --------------------------------------------------


def connector_file(text: str) -> list[dict[str, Any]] | None:
    """The documents of a connector file (each with `twin` and `connectors` at the top), or
    None when the text is something else (DT documents)."""
    try:
        docs = [d for d in yaml.safe_load_all(text) if d is not None]
    except (yaml.YAMLError, ValueError, RecursionError):
        return None  # the server names the line (ValueError: an integer of over 4 300 digits)
    if docs and all(isinstance(d, dict) and set(d) == {"twin", "connectors"} for d in docs):
        return docs
    return None


def apply_connectors(client: Client, docs: list[dict[str, Any]]) -> list[str]:
    """Create or change each connector of `docs` (idempotent); a line per connector."""
    lines = []
    for doc in docs:
        twin, items = doc["twin"], doc["connectors"]
        if not isinstance(items, list):
            raise ApiCallError(f"twin {twin}: `connectors` is a list")
        have = {c["name"] for c in client.json("GET", _base(twin))["connectors"]}
        for item in items:
            name = item.get("name") if isinstance(item, dict) else None
            if name in have:
                changes = {k: item[k] for k in ("config", "enabled") if k in item}
                client.json("PATCH", f"{_base(twin)}/{name}", json=changes)
                lines.append(f"connector/{twin}/{name} updated")
            else:
                client.json("POST", _base(twin), json=item)
                lines.append(f"connector/{twin}/{name} created")
    return lines
