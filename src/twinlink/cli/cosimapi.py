"""`twinlink cosim create|start|status|stop|results|list|rm`: co-simulations run on the
server (/api/v1/cosims, docs/cosim.md), each in a process of its own there.

`create FILE` uploads the file as the API takes it: a Maestro multi-model (.json) or the YAML
form (.yaml) whose FMUs are files beside it goes as a tar of the document and those FMUs (so
they need not be uploaded first); one that names its FMUs in the library (`lib:`) or among
the processors' uploaded files goes alone; an SSP archive (.ssp, .zip), a tar, or a folder
(packed as tar) goes as it is.
"""

from __future__ import annotations

import io
import tarfile
from pathlib import Path, PurePosixPath
from typing import Any

import click

from twinlink.cli.client import Client
from twinlink.cli.common import client_for, emit, table
from twinlink.cosim.model import CosimFormatError, System

BASE = "/api/v1/cosims"
TYPES = {
    ".json": "application/json",
    ".yaml": "application/yaml",
    ".yml": "application/yaml",
    ".ssp": "application/zip",
    ".zip": "application/zip",
    ".tar": "application/x-tar",
    ".tgz": "application/gzip",
    ".gz": "application/gzip",
}
MODES = click.Choice(["batch", "realtime"])


class FileError(click.ClickException):
    """A co-simulation file that cannot be run as written: exit status 2 (as click's usage
    errors), the message naming the file and the key, line or instance."""

    exit_code = 2


def _tar(files: dict[str, Path]) -> bytes:
    """A tar of `files` (name in the archive -> file), without owners or times."""
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w") as archive:
        for name, path in sorted(files.items()):
            info = tarfile.TarInfo(name)
            info.size = path.stat().st_size
            info.mode = 0o644
            with path.open("rb") as data:
                archive.addfile(info, data)
    return buffer.getvalue()


def _folder(top: Path) -> dict[str, Path]:
    return {p.relative_to(top).as_posix(): p for p in sorted(top.rglob("*")) if p.is_file()}


def _with_local_fmus(path: Path, system: System) -> dict[str, Path]:
    """The document and each FMU it names that is a file beside it (inside its folder)."""
    files = {path.name: path}
    base = path.parent.resolve()
    for instance in system.instances:
        relative = PurePosixPath(instance.fmu)
        if instance.fmu.startswith("lib:") or relative.is_absolute() or ".." in relative.parts:
            continue
        fmu = base / relative
        if fmu.is_file():
            files[relative.as_posix()] = fmu
    return files


def upload(path: Path) -> tuple[bytes, str]:
    """The body and its Content-Type for FILE (see the module's docstring)."""
    if path.is_dir():
        return _tar(_folder(path)), "application/x-tar"
    suffix = path.suffix.lower()
    if suffix not in TYPES:
        raise click.BadParameter(
            f"{path}: give a .json, .yaml, .ssp, .zip, .tar or .tar.gz file, or a folder",
            param_hint="FILE",
        )
    if suffix in (".json", ".yaml", ".yml"):
        from twinlink.cosim.reading import read_system  # as cosim.py's commands: not at start-up

        try:
            system = read_system(path)
        except CosimFormatError as err:
            raise FileError(str(err)) from err
        files = _with_local_fmus(path, system)
        if len(files) > 1:
            return _tar(files), "application/x-tar"
    return path.read_bytes(), TYPES[suffix]


def _status(c: dict[str, Any]) -> str:
    """`3 msd: running 42% t = 4.2 s` (a cosim not run yet has neither)."""
    progress, sim_time = c.get("progress"), c.get("sim_time")
    ran = c["state"] != "created"
    done = f" {progress:.0%}" if ran and isinstance(progress, int | float) else ""
    at = f" t = {sim_time:g} s" if ran and isinstance(sim_time, int | float) else ""
    message = f" ({c['message']})" if c.get("message") else ""
    return f"{c['id']} {c['name']}: {c['state']}{done}{at}{message}"


@click.command("create")
@click.argument("file", type=click.Path(path_type=Path, exists=True))
@click.option("--name", help="Its name [default: the file's name].")
@click.option("--twin", help="Write its results to this twin's history.")
@click.option("--prefix", help="Put this before each signal's name in the twin's history.")
@click.option("--mode", type=MODES, help="batch (as fast as possible) or realtime.")
@click.option("--factor", type=click.FloatRange(min=0, min_open=True),
              help="Real time: the wall clock times FACTOR (1.0 real time).")  # fmt: skip
@click.option("--start", is_flag=True, help="Start it once created.")
@click.pass_context
def cosim_create(
    ctx: click.Context, file: Path, name: str | None, twin: str | None, prefix: str | None,
    mode: str | None, factor: float | None, start: bool,
) -> None:  # fmt: skip
    """Create a co-simulation on the server from FILE (a Maestro multi-model with the FMUs
    beside it, the YAML form, an SSP archive, or a folder); prints its id."""
    body, content_type = upload(file)
    params = {"name": name or file.stem, "twin": twin, "prefix": prefix, "mode": mode,
              "factor": factor}  # fmt: skip
    client = client_for(ctx)
    made = client.json(
        "POST",
        BASE,
        params={k: v for k, v in params.items() if v is not None},
        content=body,
        headers={"Content-Type": content_type},
    )
    if start:
        made = client.json("POST", f"{BASE}/{made['id']}/start")
    click.echo(_status(made))


@click.command("start")
@click.argument("cosim_id")
@click.option("--mode", type=MODES, help="batch or realtime [default: as created].")
@click.option("--factor", type=click.FloatRange(min=0, min_open=True),
              help="Real time: the wall clock times FACTOR.")  # fmt: skip
@click.pass_context
def cosim_start(ctx: click.Context, cosim_id: str, mode: str | None, factor: float | None) -> None:
    """Start COSIM_ID (again, with new results, once it has ended)."""
    body = {k: v for k, v in (("mode", mode), ("factor", factor)) if v is not None}
    kwargs: dict[str, Any] = {"json": body} if body else {}
    click.echo(_status(client_for(ctx).json("POST", f"{BASE}/{cosim_id}/start", **kwargs)))


@click.command("stop")
@click.argument("cosim_id")
@click.pass_context
def cosim_stop(ctx: click.Context, cosim_id: str) -> None:
    """Stop COSIM_ID after its current step; the rows so far are kept."""
    click.echo(_status(client_for(ctx).json("POST", f"{BASE}/{cosim_id}/stop")))


@click.command("status")
@click.argument("cosim_id")
@click.option("--json", "as_json", is_flag=True, help="Print the whole view as JSON.")
@click.pass_context
def cosim_status(ctx: click.Context, cosim_id: str, as_json: bool) -> None:
    """COSIM_ID's state, progress and simulated time (--json: its system too)."""
    found = client_for(ctx).json("GET", f"{BASE}/{cosim_id}")
    if as_json:
        emit(found, True)
    else:
        click.echo(_status(found))


@click.command("results")
@click.argument("cosim_id")
@click.option("-o", "--output", type=click.Path(path_type=Path, dir_okay=False),
              help="Write the CSV here [default: stdout].")  # fmt: skip
@click.pass_context
def cosim_results(ctx: click.Context, cosim_id: str, output: Path | None) -> None:
    """COSIM_ID's results as CSV (Maestro's outputs.csv), as far as it has run."""
    _download(client_for(ctx), f"{BASE}/{cosim_id}/results.csv", output)


def _download(client: Client, path: str, output: Path | None) -> None:
    response = client.request("GET", path)
    if output is None:
        click.echo(response.text, nl=False)
    else:
        output.write_bytes(response.content)


@click.command("list")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.pass_context
def cosim_list(ctx: click.Context, as_json: bool) -> None:
    """The co-simulations you may see."""
    found = client_for(ctx).json("GET", BASE)
    items = found["cosims"] if isinstance(found, dict) else found
    if as_json:
        emit(items, True)
        return
    rows = [[str(c["id"]), c["name"], c["state"], _percent(c.get("progress")),
             c.get("twin") or "", c.get("mode") or ""] for c in items]  # fmt: skip
    table(["ID", "NAME", "STATE", "PROGRESS", "TWIN", "MODE"], rows)


def _percent(progress: Any) -> str:
    return f"{progress:.0%}" if isinstance(progress, int | float) else ""


@click.command("rm")
@click.argument("cosim_id")
@click.pass_context
def cosim_rm(ctx: click.Context, cosim_id: str) -> None:
    """Delete COSIM_ID and its results (not while it runs: stop it first)."""
    client_for(ctx).request("DELETE", f"{BASE}/{cosim_id}")
    click.echo(f"{cosim_id}: deleted")


api_commands = (
    cosim_create, cosim_start, cosim_stop, cosim_status, cosim_results, cosim_list, cosim_rm,
)  # fmt: skip
