"""`twinlink blueprints`, `twinlink processors` and `twinlink fmus` over the API."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import click
import yaml

from twinlink.cli.commands import parse_assignments
from twinlink.cli.common import HelpGroup, client_for, emit, table


def _base(twin: str) -> str:
    return f"/api/v1/twins/{twin}/processors"


def _parse_input(text: str) -> tuple[str, dict[str, Any]]:
    """`INPUT=SIGNAL[:SCALE[:OFFSET]]`."""
    name, sep, rest = text.partition("=")
    parts = rest.split(":")
    if not sep or not name or not parts[0] or len(parts) > 3:
        raise click.BadParameter(f"{text!r} is not INPUT=SIGNAL[:SCALE[:OFFSET]]")
    try:
        numbers = [float(p) for p in parts[1:]]
    except ValueError as err:
        raise click.BadParameter(f"{text!r}: scale and offset must be numbers") from err
    mapping: dict[str, Any] = {"signal": parts[0]}
    mapping.update(zip(("scale", "offset"), numbers, strict=False))
    return name, mapping


_HEADER = ["NAME", "BLUEPRINT", "STATE", "STREAMS", "SAMPLES IN", "OUT", "RESTARTS"]


def _row(p: dict[str, Any]) -> list[str]:
    stats = p.get("stats") or {}
    figures = [str(stats.get(k, "-")) for k in ("samples_in", "samples_out", "restarts")]
    flow = f"{p['source']} -> {p['output'] or p['name']}"
    return [p["name"], p["blueprint"], p["state"], flow, *figures]


def _line(p: dict[str, Any]) -> str:
    return "  ".join(_row(p))


@click.command()
@click.argument("name", required=False)
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.pass_context
def blueprints(ctx: click.Context, name: str | None, as_json: bool) -> None:
    """List blueprints, or show NAME with its parameters."""
    client = client_for(ctx)
    if name is None:
        for b in client.json("GET", "/api/v1/blueprints")["blueprints"]:
            title = b.get("title") or f"broken: {b.get('error')}"
            click.echo(f"{b['name']:<16} {b['source']:<9} {title}")
        return
    found = client.json("GET", f"/api/v1/blueprints/{name}")
    if as_json:
        emit(found, True)
        return
    click.echo(found["description"] or found["title"])
    schema = found["params_schema"]
    required = set(schema.get("required", []))
    for pname, prop in schema.get("properties", {}).items():
        kind = prop.get("type") or "/".join(
            str(x.get("type", "?")) for x in prop.get("anyOf", [])
        )  # fmt: skip
        default = "required" if pname in required else f"default {prop.get('default')!r}"
        click.echo(f"  {pname:<20} {kind:<16} {default:<20} {prop.get('description', '')}")


@click.group(cls=HelpGroup)
def processors() -> None:
    """Processors of a twin: blueprints running on its streams."""


@processors.command("ls")
@click.argument("twin")
@click.pass_context
def processors_ls(ctx: click.Context, twin: str) -> None:
    """List TWIN's processors with their state and figures."""
    found = client_for(ctx).json("GET", _base(twin))["processors"]
    if not found:
        click.echo(f"{twin} has no processors.")
        return
    table(_HEADER, [_row(p) for p in found])


@processors.command("create")
@click.argument("twin")
@click.argument("name", required=False)
@click.argument("blueprint", required=False)
@click.option(
    "-f",
    "--file",
    "spec_file",
    type=click.Path(exists=True, dir_okay=False),
    help="The whole processor as YAML or JSON (options below override it).",
)
@click.option("--source", help="Stream to read [telemetry].")
@click.option("--output", help="Stream to write [the processor's name].")
@click.option("-p", "--param", "params", multiple=True, help="A parameter, key=value (JSON).")
@click.option(
    "-i",
    "--input",
    "inputs",
    multiple=True,
    help="INPUT=SIGNAL[:SCALE[:OFFSET]]: feed a blueprint input from a signal.",
)
@click.option("--stopped", is_flag=True, help="Create it without starting it.")
@click.pass_context
def processors_create(
    ctx: click.Context, twin: str, name: str | None, blueprint: str | None,
    spec_file: str | None, source: str | None, output: str | None, params: tuple[str, ...],
    inputs: tuple[str, ...], stopped: bool,
) -> None:  # fmt: skip
    """Create processor NAME from BLUEPRINT on TWIN (or from a spec file)."""
    spec: dict[str, Any] = {}
    if spec_file:
        spec = yaml.safe_load(Path(spec_file).read_text()) or {}
    for key, value in (("name", name), ("blueprint", blueprint), ("source", source),
                       ("output", output)):  # fmt: skip
        if value is not None:
            spec[key] = value
    if params:
        spec["params"] = {**spec.get("params", {}), **parse_assignments(params)}
    if inputs:
        spec["inputs"] = {**spec.get("inputs", {}), **dict(_parse_input(i) for i in inputs)}
    if stopped:
        spec["enabled"] = False
    made = client_for(ctx).json("POST", _base(twin), json=spec)
    click.echo(_line(made))


@processors.command("show")
@click.argument("twin")
@click.argument("name")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.pass_context
def processors_show(ctx: click.Context, twin: str, name: str, as_json: bool) -> None:
    """Show a processor: its configuration, state and figures."""
    emit(client_for(ctx).json("GET", f"{_base(twin)}/{name}"), as_json)


@processors.command("set")
@click.argument("twin")
@click.argument("name")
@click.argument("params", nargs=-1, required=True)
@click.pass_context
def processors_set(ctx: click.Context, twin: str, name: str, params: tuple[str, ...]) -> None:
    """Change parameters of a running processor (key=value ...); state is kept if it can be."""
    client = client_for(ctx)
    current = client.json("GET", f"{_base(twin)}/{name}")["params"]
    changed = client.json(
        "PATCH", f"{_base(twin)}/{name}", json={"params": {**current, **parse_assignments(params)}}
    )
    kept = "state kept" if changed["kept_state"] else "restarted"
    click.echo(f"{name}: {kept}")


def _action(verb: str, help_text: str) -> click.Command:
    @click.argument("twin")
    @click.argument("name")
    @click.pass_context
    def run(ctx: click.Context, twin: str, name: str) -> None:
        answer = client_for(ctx).json("POST", f"{_base(twin)}/{name}/{verb}")
        click.echo(f"{name}: {answer['state']}")

    run.__doc__ = help_text
    return processors.command(verb)(run)


_action("start", "Start a processor (it also starts with the server from now on).")
_action("stop", "Stop a processor gracefully (and keep it stopped).")
_action("restart", "Restart a processor's worker.")


@processors.command("rm")
@click.argument("twin")
@click.argument("name")
@click.pass_context
def processors_rm(ctx: click.Context, twin: str, name: str) -> None:
    """Delete a processor (its output stream's history stays)."""
    client_for(ctx).request("DELETE", f"{_base(twin)}/{name}")
    click.echo(f"deleted processor {name} of {twin}")


@processors.command("events")
@click.argument("twin")
@click.argument("name")
@click.option("--kind", help="Only events of this kind (crashed, memory_limit, alarm...).")
@click.option("-n", "--limit", default=20, show_default=True)
@click.pass_context
def processors_events(
    ctx: click.Context, twin: str, name: str, kind: str | None, limit: int
) -> None:
    """What happened to a processor, newest first."""
    query: dict[str, Any] = {"limit": limit, **({"kind": kind} if kind else {})}
    for e in client_for(ctx).json("GET", f"{_base(twin)}/{name}/events", params=query)["events"]:
        when = time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(e["time_ns"] / 1e9))
        click.echo(f"{when}  {e['kind']:<14} {e['message']}")


@processors.command("logs")
@click.argument("twin")
@click.argument("name")
@click.pass_context
def processors_logs(ctx: click.Context, twin: str, name: str) -> None:
    """The last lines the processor's worker printed."""
    for line in client_for(ctx).json("GET", f"{_base(twin)}/{name}/logs")["lines"]:
        click.echo(line["text"])


@click.group(cls=HelpGroup)
def fmus() -> None:
    """FMUs uploaded to a twin, for the fmu blueprint."""


@fmus.command("ls")
@click.argument("twin")
@click.pass_context
def fmus_ls(ctx: click.Context, twin: str) -> None:
    """List TWIN's FMUs."""
    for f in client_for(ctx).json("GET", f"/api/v1/twins/{twin}/fmus")["fmus"]:
        click.echo(
            f"{f['name']:<28} FMI {f['fmi_version']:<4} {f['size']:>10} B  {f['model_name']}"
        )


@fmus.command("upload")
@click.argument("twin")
@click.argument("file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--name", help="Name to store it under [the file's name].")
@click.pass_context
def fmus_upload(ctx: click.Context, twin: str, file: Path, name: str | None) -> None:
    """Upload FILE (an .fmu) to TWIN; it is checked and its variables are listed."""
    with file.open("rb") as body:
        info = client_for(ctx).json(
            "PUT", f"/api/v1/twins/{twin}/fmus/{name or file.name}", content=body,
            headers={"Content-Type": "application/octet-stream"},
        )  # fmt: skip
    click.echo(f"uploaded {info['name']}: {info['model_name']}, FMI {info['fmi_version']}")
    _variables(info)


@fmus.command("show")
@click.argument("twin")
@click.argument("name")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.pass_context
def fmus_show(ctx: click.Context, twin: str, name: str, as_json: bool) -> None:
    """Show an FMU and its variables."""
    info = client_for(ctx).json("GET", f"/api/v1/twins/{twin}/fmus/{name}")
    if as_json:
        emit(info, True)
    else:
        _variables(info)


@fmus.command("rm")
@click.argument("twin")
@click.argument("name")
@click.pass_context
def fmus_rm(ctx: click.Context, twin: str, name: str) -> None:
    """Delete an FMU no processor uses."""
    client_for(ctx).request("DELETE", f"/api/v1/twins/{twin}/fmus/{name}")
    click.echo(f"deleted {name}")


def _variables(info: dict[str, Any]) -> None:
    for v in info.get("variables", []):
        limits = f"[{v.get('min', '')}, {v.get('max', '')}]" if "min" in v or "max" in v else ""
        click.echo(
            f"  {v['name']:<24} {v['causality']:<12} {v['type']:<8} {v.get('unit') or '':<6} "
            f"start {v.get('start')!s:<10} {limits}".rstrip()
        )
