"""`twinlink services`, `twinlink audit` and `twinlink service-accounts` over the API."""

from __future__ import annotations

import sys
import time
from pathlib import Path
from typing import Any

import click
import httpx
import orjson
import yaml

from twinlink.cli.common import HelpGroup, client_for, emit, table


def _base(twin: str) -> str:
    return f"/api/v1/twins/{twin}/services"


def _auth_value(text: str) -> Any:
    """`@path` reads a file (so secrets stay out of shell history); JSON objects and lists are
    parsed; anything else is a string."""
    if text.startswith("@"):
        return Path(text[1:]).read_text().strip()
    if text[:1] in "{[":
        try:
            return orjson.loads(text)
        except orjson.JSONDecodeError as err:
            raise click.BadParameter(f"{text!r} is not valid JSON: {err}") from err
    return text


def _settings(
    spec_file: str | None,
    method: str | None,
    auth: tuple[str, ...],
    methods: str | None,
    health: str | None,
) -> dict[str, Any]:
    body: dict[str, Any] = {}
    if spec_file:
        body = yaml.safe_load(Path(spec_file).read_text()) or {}
    if method or auth:
        given: dict[str, Any] = {"method": method} if method else {}
        for item in auth:
            key, sep, value = item.partition("=")
            if not sep or not key:
                raise click.BadParameter(f"{item!r} is not KEY=VALUE")
            given[key] = _auth_value(value)
        body["auth"] = {**body.get("auth", {}), **given}
    if methods:
        body["methods"] = [m.strip().upper() for m in methods.split(",") if m.strip()]
    if health is not None:
        body["health_path"] = health or None
    return body


_HEADER = ["NAME", "SOURCE", "AUTH", "HEALTH", "BASE URL"]


def _row(s: dict[str, Any]) -> list[str]:
    health = (s.get("health") or {}).get("status", "-")
    state = "blocked" if s.get("blocked") else health
    return [s["name"], s["source"], s["auth"]["method"], state, s["base_url"] or "-"]


def _line(s: dict[str, Any]) -> str:
    return "  ".join(_row(s))


_SETTINGS_OPTIONS = [
    click.option(
        "-f",
        "--file",
        "spec_file",
        type=click.Path(exists=True, dir_okay=False),
        help="Settings as YAML or JSON (options below override it).",
    ),
    click.option(
        "--auth",
        "method",
        help="Credential method: none, basic, bearer, api_key, "
        "oauth2_client_credentials, oauth2_password, custom_login.",
    ),
    click.option(
        "-a",
        "auth",
        multiple=True,
        help="A credential field, KEY=VALUE "
        "(VALUE @file reads the file, so secrets stay out of shell history).",
    ),
    click.option("--methods", help="Allowed methods, comma separated."),
    click.option("--health", help="Health-check path below the base URL ('' for none)."),
]


def _with_settings(fn: Any) -> Any:
    for option in reversed(_SETTINGS_OPTIONS):
        fn = option(fn)
    return fn


@click.group(cls=HelpGroup)
def services() -> None:
    """A twin's gateway services: the Data Link's one entry point to its features."""


@services.command("ls")
@click.argument("twin")
@click.pass_context
def services_ls(ctx: click.Context, twin: str) -> None:
    """List TWIN's gateway services (from its DT document and added by API).

    HEALTH is the last health check's result (- until the first). Features of the document
    without an `apiAddress` are not gateway services: they are described only, and named
    after the list.
    """
    client = client_for(ctx)
    found = client.json("GET", _base(twin))["services"]
    if found:
        table(_HEADER, [_row(s) for s in found])
    else:
        click.echo(f"{twin} has no gateway services.")
    document = client.json("GET", f"/api/v1/twins/{twin}")["document"]
    described = [
        str(f.get("name"))
        for f in document.get("features") or []
        if isinstance(f, dict) and not f.get("apiAddress")
    ]
    if described:
        click.echo(f"Described only (no apiAddress): {', '.join(described)}")


@services.command("show")
@click.argument("twin")
@click.argument("name")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.pass_context
def services_show(ctx: click.Context, twin: str, name: str, as_json: bool) -> None:
    """Show a service's settings (secrets only as *_set), health and figures."""
    emit(client_for(ctx).json("GET", f"{_base(twin)}/{name}"), as_json)


@services.command("add")
@click.argument("twin")
@click.argument("name")
@click.argument("url")
@_with_settings
@click.pass_context
def services_add(
    ctx: click.Context,
    twin: str,
    name: str,
    url: str,
    spec_file: str | None,
    method: str | None,
    auth: tuple[str, ...],
    methods: str | None,
    health: str | None,
) -> None:
    """Add service NAME at base URL to TWIN (owners)."""
    body = {**_settings(spec_file, method, auth, methods, health), "name": name, "base_url": url}
    click.echo(_line(client_for(ctx).json("POST", _base(twin), json=body)))


@services.command("set")
@click.argument("twin")
@click.argument("name")
@_with_settings
@click.pass_context
def services_set(
    ctx: click.Context,
    twin: str,
    name: str,
    spec_file: str | None,
    method: str | None,
    auth: tuple[str, ...],
    methods: str | None,
    health: str | None,
) -> None:
    """Change a service's settings or credentials (owners)."""
    body = _settings(spec_file, method, auth, methods, health)
    click.echo(_line(client_for(ctx).json("PATCH", f"{_base(twin)}/{name}", json=body)))


@services.command("rm")
@click.argument("twin")
@click.argument("name")
@click.pass_context
def services_rm(ctx: click.Context, twin: str, name: str) -> None:
    """Delete an API service, or reset a document service's settings (owners)."""
    done = client_for(ctx).json("DELETE", f"{_base(twin)}/{name}")
    click.echo(f"{name}: {done['outcome']}")


@services.command("health")
@click.argument("twin")
@click.argument("name")
@click.pass_context
def services_health(ctx: click.Context, twin: str, name: str) -> None:
    """Check a service now."""
    h = client_for(ctx).json("GET", f"{_base(twin)}/{name}/health")
    extra = f" ({h['error']})" if h.get("error") else ""
    click.echo(f"{name}: {h['status']} HTTP {h.get('http_status')} in {h['ms']} ms{extra}")


@services.command("call")
@click.argument("twin")
@click.argument("name")
@click.argument("path", default="")
@click.option("-X", "--method", default="GET", show_default=True)
@click.option("-d", "--data", help="Request body (@file reads a file, - reads stdin).")
@click.option("-H", "--header", "headers", multiple=True, help="A header, 'Name: value'.")
@click.pass_context
def services_call(
    ctx: click.Context,
    twin: str,
    name: str,
    path: str,
    method: str,
    data: str | None,
    headers: tuple[str, ...],
) -> None:
    """Send a request to a service through the gateway and print the answer.

    On a terminal a JSON answer is indented; piped or redirected, the answer's bytes are
    written as they came (a CAD file stays a CAD file).
    """
    body: bytes | None = None
    if data is not None:
        body = (
            sys.stdin.buffer.read()
            if data == "-"
            else (Path(data[1:]).read_bytes() if data.startswith("@") else data.encode())
        )
    sent = dict(h.split(":", 1) for h in headers)
    response = client_for(ctx).request(
        method.upper(),
        f"/twins/{twin}/services/{name}/{path.lstrip('/')}",
        content=body,
        headers={k.strip(): v.strip() for k, v in sent.items()},
    )
    if not sys.stdout.isatty():
        sys.stdout.buffer.write(response.content)
        sys.stdout.flush()
        return
    click.echo(_readable(response))


def _readable(response: httpx.Response) -> str:
    """The answer for a person: JSON indented, other text as it is."""
    if "json" in response.headers.get("content-type", ""):
        try:
            return orjson.dumps(orjson.loads(response.content), option=orjson.OPT_INDENT_2).decode()
        except orjson.JSONDecodeError:
            pass  # not what it says it is (or integers beyond 64 bits): show it as sent
    return response.text


@click.command()
@click.option("--twin", help="Only this twin (needed unless you are an admin).")
@click.option("--service", help="Only this service.")
@click.option("--user", help="Only requests of this user.")
@click.option("--status", type=int, help="Only answers with this status.")
@click.option("--since", type=float, help="Only the last SINCE seconds.")
@click.option("-n", "--limit", type=int, default=50, show_default=True)
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.pass_context
def audit(
    ctx: click.Context,
    twin: str | None,
    service: str | None,
    user: str | None,
    status: int | None,
    since: float | None,
    limit: int,
    as_json: bool,
) -> None:
    """The gateway's audit log: requests forwarded to services, newest first."""
    params: dict[str, Any] = {
        "twin": twin,
        "service": service,
        "user": user,
        "status": status,
        "limit": limit,
    }
    if since is not None:
        params["since"] = time.time() - since
    found = client_for(ctx).json(
        "GET", "/api/v1/gateway/audit", params={k: v for k, v in params.items() if v is not None}
    )
    if as_json:
        emit(found, True)
        return
    for e in found["entries"]:
        up = "-" if e["upstream_ms"] is None else f"{e['upstream_ms']:.1f}"
        click.echo(
            f"{e['time_iso']} {e['caller']:<16} {e['method']:<7} {e['status']:<4} "
            f"{e['twin']}/{e['service']}{e['path']}  {e['bytes_out']} B "
            f"upstream {up} ms total {e['total_ms']:.1f} ms {e['outcome']}"
        )


@click.group("service-accounts", cls=HelpGroup)
def service_accounts() -> None:
    """Identities for features that call other services through the gateway."""


@service_accounts.command("ls")
@click.argument("twin")
@click.pass_context
def accounts_ls(ctx: click.Context, twin: str) -> None:
    """List TWIN's service accounts."""
    for a in client_for(ctx).json("GET", f"/api/v1/twins/{twin}/service-accounts")[
        "service_accounts"
    ]:
        click.echo(f"{a['name']:<20} {a['role']:<8} {a['user']}")


@service_accounts.command("create")
@click.argument("twin")
@click.argument("name")
@click.option("--role", type=click.Choice(["viewer", "editor"]), default="viewer")
@click.pass_context
def accounts_create(ctx: click.Context, twin: str, name: str, role: str) -> None:
    """Make service account NAME on TWIN; prints its token once."""
    made = client_for(ctx).json(
        "POST", f"/api/v1/twins/{twin}/service-accounts", json={"name": name, "role": role}
    )
    click.echo(f"service account {made['user']} ({made['role']}); its token, shown once:")
    click.echo(made["token"])


@service_accounts.command("rm")
@click.argument("twin")
@click.argument("name")
@click.pass_context
def accounts_rm(ctx: click.Context, twin: str, name: str) -> None:
    """Delete a service account and its tokens."""
    client_for(ctx).request("DELETE", f"/api/v1/twins/{twin}/service-accounts/{name}")
    click.echo(f"deleted {name}")
