"""`twinlink deploy`: deployments of twin packages (plan, create, start, stop, update,
terminate) and their lifecycle runs, followed live."""

from __future__ import annotations

import sys
from typing import Any

import click
import yaml

from twinlink.cli.common import HelpGroup, emit, show_value, table
from twinlink.cli.library import api_client
from twinlink.client import Client

SIGNS = {"create": "+", "update": "~", "delete": "-"}


def parse_parameters(pairs: tuple[str, ...]) -> dict[str, Any]:
    """`-p key=value` pairs; each value read as a YAML scalar (`0.7` a number, `true` a
    bool, `[1, 2]` a list), text when it is not YAML (and `yes`, `no`, `on`, `off`)."""
    out: dict[str, Any] = {}
    for pair in pairs:
        key, sep, text = pair.partition("=")
        if not sep or not key:
            raise click.BadParameter(f"{pair!r} is not key=value", param_hint="-p")
        try:
            value = yaml.safe_load(text) if text.strip() else text
        except yaml.YAMLError:
            value = text
        # YAML 1.1's other bools (yes, no, on, off) stay text: `-p mode=on` means "on".
        if isinstance(value, bool) and text.strip().lower() not in ("true", "false"):
            value = text
        out[key] = value
    return out


def print_plan(plan: dict[str, Any]) -> None:
    """A plan as terraform prints one: `+` created, `~` updated (each change), `-` deleted."""
    counts = {}
    for action, sign in SIGNS.items():
        items = plan.get(action) or []
        counts[action] = len(items)
        for item in items:
            click.echo(f"{sign} {item['type']:<10} {item['name']}")
            for change in item.get("changes") or []:
                before, after = show_value(change.get("from")), show_value(change.get("to"))
                click.echo(f"      {change['path']}: {before} -> {after}")
    kept = len(plan.get("keep") or [])
    click.echo(
        f"Plan: {counts['create']} to create, {counts['update']} to update, "
        f"{counts['delete']} to delete, {kept} unchanged."
    )


def _line(answer: dict[str, Any]) -> str:
    """A deployment's name and state, from it or from an answer holding it."""
    d = answer.get("deployment", answer)
    return f"{d['name']}: {d['state']}" + (f" ({d['error']})" if d.get("error") else "")


@click.group(cls=HelpGroup)
def deploy() -> None:
    """Deployments of twin packages: plan, create, start, stop, update, terminate, runs."""


@deploy.command("create")
@click.argument("package")
@click.option("--name", help="The deployment's name (its twin's slug).")
@click.option("-p", "--param", "params", multiple=True, help="A parameter, key=value (YAML).")
@click.option("--scope", help="Look the package up only in this scope.")
@click.option("--dry-run", is_flag=True, help="Print the plan only; nothing is made.")
@click.option("--start", is_flag=True, help="Start it once created.")
@click.option("--planned", is_flag=True, help="Record it as planned; make nothing yet.")
@click.pass_context
def deploy_create(
    ctx: click.Context, package: str, name: str | None, params: tuple[str, ...],
    scope: str | None, dry_run: bool, start: bool, planned: bool,
) -> None:  # fmt: skip
    """Deploy PACKAGE (a twins asset: rig@1.0.0, common/twins/rig) as --name, printing the
    plan. Without --name, PACKAGE is a planned deployment's name: its resources are made."""
    with api_client(ctx) as client:
        if name is None:
            if params or dry_run or start or planned or scope:
                raise click.UsageError("--name is needed to deploy a package")
            click.echo(_line(client.deployments.apply(package)))
            return
        parameters = parse_parameters(params)
        if dry_run:
            print_plan(client.deployments.plan(package, name, parameters, scope=scope))
            return
        made = client.deployments.create(
            package, name, parameters, scope=scope, start=start, planned=planned
        )
    print_plan(made["plan"])
    for device, token in sorted((made.get("device_tokens") or {}).items()):
        click.echo(f"device {device} token (shown once): {token}")
    click.echo(_line(made))


@deploy.command("plan")
@click.argument("package")
@click.option("--name", required=True, help="The deployment's name (its twin's slug).")
@click.option("-p", "--param", "params", multiple=True, help="A parameter, key=value (YAML).")
@click.option("--scope", help="Look the package up only in this scope.")
@click.pass_context
def deploy_plan(
    ctx: click.Context, package: str, name: str, params: tuple[str, ...], scope: str | None
) -> None:
    """What deploying PACKAGE as --name would make (the same as create --dry-run)."""
    with api_client(ctx) as client:
        print_plan(client.deployments.plan(package, name, parse_parameters(params), scope=scope))


@deploy.command("ls")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.pass_context
def deploy_ls(ctx: click.Context, as_json: bool) -> None:
    """The deployments."""
    with api_client(ctx) as client:
        found = client.deployments.ls()
    if as_json:
        emit(found, True)
        return
    rows = [[d["name"], d["state"], d.get("package_ref") or d["package"], d.get("twin") or ""]
            for d in found]  # fmt: skip
    table(["NAME", "STATE", "PACKAGE", "TWIN"], rows)


@deploy.command("show")
@click.argument("name")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.pass_context
def deploy_show(ctx: click.Context, name: str, as_json: bool) -> None:
    """A deployment: its package, parameters, state and resources."""
    with api_client(ctx) as client:
        emit(client.deployments.get(name), as_json)


@deploy.command("start")
@click.argument("name")
@click.pass_context
def deploy_start(ctx: click.Context, name: str) -> None:
    """Start its processors and connectors, and its execute phase if it has one."""
    with api_client(ctx) as client:
        click.echo(_line(client.deployments.start(name)))


@deploy.command("stop")
@click.argument("name")
@click.pass_context
def deploy_stop(ctx: click.Context, name: str) -> None:
    """Stop its processors, connectors and execute phase; the twin stays."""
    with api_client(ctx) as client:
        click.echo(_line(client.deployments.stop(name)))


@deploy.command("terminate")
@click.argument("name")
@click.option("--purge", is_flag=True, help="Delete the twin and its history too.")
@click.pass_context
def deploy_terminate(ctx: click.Context, name: str, purge: bool) -> None:
    """Remove what it made (devices, processors, connectors, services, tokens); the twin's
    document and history stay unless --purge."""
    with api_client(ctx) as client:
        click.echo(_line(client.deployments.terminate(name, purge)))


@deploy.command("update")
@click.argument("name")
@click.option("-p", "--param", "params", multiple=True, help="A parameter, key=value (YAML).")
@click.option("--package", help="Another version of the package (rig@1.1.0).")
@click.option("--dry-run", is_flag=True, help="Print the plan only; nothing changes.")
@click.pass_context
def deploy_update(
    ctx: click.Context, name: str, params: tuple[str, ...], package: str | None, dry_run: bool
) -> None:
    """Reconfigure NAME: new parameters (the others kept) or package version; what did not
    change keeps running."""
    if not params and not package:
        raise click.UsageError("give -p key=value or --package")
    with api_client(ctx) as client:
        answer = client.deployments.update(
            name, parse_parameters(params), package=package, dry_run=dry_run
        )
    print_plan(answer["plan"])
    if not dry_run:
        click.echo(_line(answer))


@deploy.command("run")
@click.argument("name")
@click.argument("phase")
@click.option("-f", "--follow", is_flag=True, help="Print the log as it comes; exit with the "
              "script's exit code.")  # fmt: skip
@click.pass_context
def deploy_run(ctx: click.Context, name: str, phase: str, follow: bool) -> None:
    """Run lifecycle PHASE (create, execute, analyze, evolve, save, terminate, clean) of NAME."""
    with api_client(ctx) as client:
        run = client.deployments.run(name, phase, follow=False)
        click.echo(f"run {run['id']}: {phase} {run['state']}", err=follow)
        if follow:
            _follow(client, run["id"])


def _follow(client: Client, run_id: str) -> None:
    """The log on stdout as it comes; then the end on stderr and the script's exit code."""
    client.deployments.follow(run_id, _write)
    run = client.deployments.get_run(run_id)
    code = run.get("exit_code")
    click.echo(f"run {run_id}: {run['state']} (exit code {code})", err=True)
    if run["state"] != "succeeded":
        sys.exit(code if isinstance(code, int) and 0 < code < 256 else 1)


def _write(text: str) -> None:
    click.echo(text, nl=False)


@deploy.command("runs")
@click.argument("name")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.pass_context
def deploy_runs(ctx: click.Context, name: str, as_json: bool) -> None:
    """Every lifecycle run of NAME, newest first."""
    with api_client(ctx) as client:
        runs = client.deployments.runs(name)
    if as_json:
        emit(runs, True)
        return
    rows = [[str(r["id"]), r["phase"], r["state"], show_value(r.get("exit_code")),
             r.get("started_by") or "", r.get("node") or ""] for r in runs]  # fmt: skip
    table(["RUN", "PHASE", "STATE", "EXIT", "BY", "NODE"], rows)


@deploy.command("logs")
@click.argument("run_id")
@click.option("-f", "--follow", is_flag=True, help="Keep printing until the run ends.")
@click.pass_context
def deploy_logs(ctx: click.Context, run_id: str, follow: bool) -> None:
    """The log of run RUN_ID (kept after the run, whoever started it)."""
    with api_client(ctx) as client:
        if follow:
            _follow(client, run_id)
        else:
            click.echo(client.deployments.logs(run_id), nl=False)
