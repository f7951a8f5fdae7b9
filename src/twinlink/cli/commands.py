"""`twinlink send`, `twinlink commands` and `twinlink properties`: commands to devices and
device properties over the API."""

from __future__ import annotations

from typing import Any

import click
import orjson

from twinlink.cli.client import ApiCallError
from twinlink.cli.common import HelpGroup, client_for, emit
from twinlink.domain.jsontext import JsonTextError, loads

_HTTP_MARGIN_S = 30.0  # the HTTP request outlives the command's own timeout by this much


def parse_assignments(pairs: tuple[str, ...]) -> dict[str, Any]:
    """`key=value` pairs; a value is JSON when it parses as JSON (50, true, null, [1, 2],
    "50"), else the text as it is."""
    out: dict[str, Any] = {}
    for pair in pairs:
        key, sep, text = pair.partition("=")
        if not sep or not key:
            raise click.BadParameter(f"{pair!r} is not key=value", param_hint="ARGS")
        try:
            out[key] = loads(text)  # integers exact: the server refuses, not rounds, 2**80
        except JsonTextError:
            out[key] = text
    return out


def _json(value: Any) -> str:
    return orjson.dumps(value, option=orjson.OPT_INDENT_2).decode()


@click.command(short_help="Send COMMAND to a device of TWIN and print the result.")
@click.argument("twin")
@click.argument("command")
@click.argument("args", nargs=-1)
@click.option(
    "-d", "--device", metavar="NAME",
    help="The device [default: the twin's only device, else the `default_device` of its "
    "interface, else its only connected device].",
)  # fmt: skip
@click.option(
    "-t", "--timeout", type=click.FloatRange(min=0, min_open=True),
    help="Seconds until the command expires [default: the server's, 10].",
)  # fmt: skip
@click.option("--queue", is_flag=True, help="Keep it for an offline device until it connects.")
@click.option("--no-wait", is_flag=True, help="Print the id at once instead of the result.")
@click.option("--json", "as_json", is_flag=True, help="Print the whole command record as JSON.")
@click.pass_context
def send(
    ctx: click.Context,
    twin: str,
    command: str,
    args: tuple[str, ...],
    device: str | None,
    timeout: float | None,
    queue: bool,
    no_wait: bool,
    as_json: bool,
) -> None:
    """Send COMMAND with ARGS (key=value ...) to a device of TWIN and print the result.

    A value is JSON when it parses as JSON (value=50, on=true, steps=[1,2]), else text
    (mode=eco); write label='"50"' for the text 50. Exits 1 when the command failed or
    expired.
    """
    body: dict[str, Any] = {"name": command, "args": parse_assignments(args)}
    body.update(device=device, timeout_s=timeout, queue=queue, wait=not no_wait)
    client = client_for(ctx)
    client.http.timeout = (timeout or 3600.0) + _HTTP_MARGIN_S
    try:
        record = client.json("POST", f"/api/v1/twins/{twin}/commands", json=body)
    except ApiCallError as err:
        reason = (err.problem or {}).get("reason") if device is None else None
        if not isinstance(reason, str):
            raise
        # The server could not choose a device; it names the API's field, this names ours.
        raise ApiCallError(f"{reason}; name one with --device NAME") from err
    if as_json:
        click.echo(_json(record))
    else:
        click.echo(f"{record['id']} {record['state']}")
        if record["result"] is not None:
            click.echo(_json(record["result"]))
    if record["error"]:
        click.echo(f"Error: {record['error']}", err=True)
    if record["state"] in ("failed", "expired"):
        ctx.exit(1)


# -- the command log -------------------------------------------------------------------------


@click.group(cls=HelpGroup)
def commands() -> None:
    """The command log of a twin."""


@commands.command("ls")
@click.argument("twin")
@click.option(
    "-s", "--state",
    type=click.Choice(["pending", "delivered", "succeeded", "failed", "expired"]),
    help="Only commands in this state.",
)  # fmt: skip
@click.option("--name", help="Only commands of this name.")
@click.option("-d", "--device", help="Only commands to this device.")
@click.option("-n", "--limit", default=50, show_default=True, help="Most commands to show.")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.pass_context
def commands_ls(
    ctx: click.Context,
    twin: str,
    state: str | None,
    name: str | None,
    device: str | None,
    limit: int,
    as_json: bool,
) -> None:
    """List a twin's commands, newest first."""
    given = {"state": state, "name": name, "device": device, "limit": limit}
    params = {k: v for k, v in given.items() if v is not None}
    found = client_for(ctx).json("GET", f"/api/v1/twins/{twin}/commands", params=params)
    if as_json:
        emit(found["commands"], True)
        return
    for c in found["commands"]:
        outcome = c["error"] or ("" if c["result"] is None else orjson.dumps(c["result"]).decode())
        click.echo(
            f"{c['id']:<17} {c['created']}  {c['device']:<12} {c['name']:<20} "
            f"{c['state']:<10} {outcome[:60]}".rstrip()
        )


@commands.command("get")
@click.argument("twin")
@click.argument("command_id")
@click.option("--json", "as_json", is_flag=True, help="Print JSON instead of YAML.")
@click.pass_context
def commands_get(ctx: click.Context, twin: str, command_id: str, as_json: bool) -> None:
    """Show one command: its arguments, state, times and result."""
    emit(client_for(ctx).json("GET", f"/api/v1/twins/{twin}/commands/{command_id}"), as_json)


# -- properties ------------------------------------------------------------------------------


@click.group(cls=HelpGroup)
def properties() -> None:
    """Reported and desired properties of a device."""


@properties.command("show")
@click.argument("twin")
@click.argument("device")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.pass_context
def properties_show(ctx: click.Context, twin: str, device: str, as_json: bool) -> None:
    """Show reported and desired values; * marks a desired value the device has not reported."""
    answer = client_for(ctx).json("GET", f"/api/v1/twins/{twin}/devices/{device}/properties")
    if as_json:
        emit(answer, True)
        return
    _print_properties(answer)


@properties.command("set")
@click.argument("twin")
@click.argument("device")
@click.argument("values", nargs=-1, required=True)
@click.pass_context
def properties_set(ctx: click.Context, twin: str, device: str, values: tuple[str, ...]) -> None:
    """Set desired VALUES (key=value ...; key=null removes one); the device is told the change."""
    answer = client_for(ctx).json(
        "PATCH",
        f"/api/v1/twins/{twin}/devices/{device}/properties/desired",
        json=parse_assignments(values),
    )
    _print_properties(answer)


def _print_properties(answer: dict[str, Any]) -> None:
    reported, desired, delta = answer["reported"], answer["desired"], answer["delta"]
    click.echo(f"{'property':<24} {'reported':<20} {'desired':<20} reported at")
    for name in sorted({*reported, *desired}):
        got, want = reported.get(name), desired.get(name)
        shown = orjson.dumps(got["value"]).decode() if got else "-"
        wanted = "-"
        if want:
            wanted = orjson.dumps(want["value"]).decode() + ("*" if name in delta else "")
        click.echo(f"{name:<24} {shown:<20} {wanted:<20} {got['time'] if got else ''}".rstrip())
    click.echo(f"(desired version {answer['version']})")
