"""`twinlink history`: a twin's stored telemetry over the API (streams, latest, show, export)."""

from __future__ import annotations

import sys
from datetime import UTC, datetime
from pathlib import Path
from typing import IO, Any

import click
import httpx

from twinlink.cli.client import ApiCallError, Client, explain
from twinlink.cli.common import HelpGroup, client_for, emit, show_value, table

_TIME_HELP = "ISO 8601, ns since the epoch, now, or back from now (-1h, -15m, -7d)."


def _streams_path(twin: str) -> str:
    return f"/api/v1/twins/{twin}/streams"


def show_time(ns: int | None) -> str:
    """ns since the epoch as ISO 8601 UTC with the fraction it needs (µs or ns)."""
    if ns is None:
        return "-"
    seconds, fraction = divmod(ns, 1_000_000_000)
    text = datetime.fromtimestamp(seconds, UTC).strftime("%Y-%m-%dT%H:%M:%S")
    if fraction % 1000:
        return f"{text}.{fraction:09d}Z"
    return f"{text}.{fraction // 1000:06d}Z" if fraction else f"{text}Z"


@click.group(cls=HelpGroup)
def history() -> None:
    """Read a twin's stored telemetry (needs a role on the twin)."""


@history.command("streams")
@click.argument("twin")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.pass_context
def history_streams(ctx: click.Context, twin: str, as_json: bool) -> None:
    """List a twin's streams and signals.

    For each signal: its kind, how many values are stored, and the first and last time. For
    each stream: its samples (rows joined on time, as `history show` prints them) and values.
    """
    answer = client_for(ctx).json("GET", _streams_path(twin))
    if as_json:
        emit(answer, True)
        return
    rows = [
        [
            s["name"],
            sig["name"],
            sig["kind"],
            str(sig.get("values", sig["count"])),
            show_time(sig["first"]),
            show_time(sig["last"]),
        ]
        for s in answer["streams"]
        for sig in s["signals"]
    ]
    if not rows:
        click.echo(f"{twin} has no stored telemetry.")
        return
    table(["STREAM", "SIGNAL", "KIND", "VALUES", "FIRST", "LAST"], rows)
    for s in answer["streams"]:
        if "samples" in s:  # a server before issue 13 had only `count` (values)
            samples = "an unknown number of" if s["samples"] is None else s["samples"]
            click.echo(f"{s['name']}: {samples} samples, {s['values']} values")


@history.command("latest")
@click.argument("twin")
@click.argument("stream", required=False)
@click.option("-s", "--signals", help="Comma-separated signal names [default: all].")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.pass_context
def history_latest(
    ctx: click.Context, twin: str, stream: str | None, signals: str | None, as_json: bool
) -> None:
    """Print the newest value of each signal.

    Of STREAM, or of every stream of TWIN when STREAM is left out. Numbers with a fraction
    are shown to 6 significant digits; --json prints them whole.
    """
    client = client_for(ctx)
    if stream is None:
        streams = [s["name"] for s in client.json("GET", _streams_path(twin))["streams"]]
    else:
        streams = [stream]
    answers = [
        client.json("GET", f"{_streams_path(twin)}/{name}/latest", params={"signals": signals})
        for name in streams
    ]
    if as_json:
        emit(answers[0] if stream is not None else answers, True)
        return
    rows = [
        [a["stream"], name, show_time(v["time"]), show_value(v["value"])]
        for a in answers
        for name, v in a["values"].items()
    ]
    table(["STREAM", "SIGNAL", "TIME", "VALUE"], rows)


@history.command("show")
@click.argument("twin")
@click.argument("stream")
@click.option("-s", "--signals", help="Comma-separated signal names [default: all].")
@click.option("--start", help=f"From this time [default: the first sample]. {_TIME_HELP}")
@click.option("--end", help=f"To this time [default: the last sample]. {_TIME_HELP}")
@click.option("-n", "--limit", default=100, show_default=True, help="Most rows to print.")
@click.option("--cursor", help="Continue where a previous page ended (printed after it).")
@click.option("--json", "as_json", is_flag=True, help="Print the raw JSON answer.")
@click.pass_context
def history_show(
    ctx: click.Context,
    twin: str,
    stream: str,
    signals: str | None,
    start: str | None,
    end: str | None,
    limit: int,
    cursor: str | None,
    as_json: bool,
) -> None:
    """Print stored samples as a table.

    One row per time and one column per signal; samples sent together share a row. At most
    --limit rows; the command to print the next ones is shown after them. Numbers with a
    fraction are shown to 6 significant digits; --json and `history export` give them whole.
    """
    params = {"signals": signals, "start": start, "end": end, "limit": limit, "cursor": cursor}
    answer = client_for(ctx).json("GET", f"{_streams_path(twin)}/{stream}/samples", params=params)
    if as_json:
        emit(answer, True)
        return
    names = list(dict.fromkeys(n for row in answer["rows"] for n in row["values"]))
    rows = [
        [show_time(row["time"]), *(show_value(row["values"].get(n)) for n in names)]
        for row in answer["rows"]
    ]
    table(["TIME", *names], rows)
    if not rows:
        click.echo("(no samples in this range)", err=True)
    if answer["next_cursor"]:
        click.echo(f"(more rows: add --cursor {answer['next_cursor']})", err=True)


@history.command("export")
@click.argument("twin")
@click.argument("stream")
@click.option(
    "-f",
    "--format",
    "fmt",
    type=click.Choice(["csv", "jsonl", "json"]),
    default="csv",
    show_default=True,
    help="CSV, JSON lines (one object a line) or one JSON array.",
)
@click.option("-o", "--output", help="File to write [default: standard output].")
@click.option("-s", "--signals", help="Comma-separated signal names [default: all].")
@click.option("--start", help=f"From this time [default: the first sample]. {_TIME_HELP}")
@click.option("--end", help=f"To this time [default: the last sample]. {_TIME_HELP}")
@click.option(
    "--time",
    "time_format",
    type=click.Choice(["iso", "ns"]),
    help="Times as ISO 8601 UTC or ns since the epoch [default: iso for csv, else ns].",
)
@click.pass_context
def history_export(
    ctx: click.Context,
    twin: str,
    stream: str,
    fmt: str,
    output: str | None,
    signals: str | None,
    start: str | None,
    end: str | None,
    time_format: str | None,
) -> None:
    """Write stored samples to a file (CSV, JSON lines or JSON).

    The file is written as the server streams it, so a range of any size fits; it appears
    under its name only when complete. CSV has a header `time,<signals...>` and an empty
    cell where a signal has no value at that time.
    """
    params = {"format": fmt, "signals": signals, "start": start, "end": end, "time": time_format}
    client = client_for(ctx)
    client.http.timeout = httpx.Timeout(30.0, read=None)  # a long range streams for long
    path = f"{_streams_path(twin)}/{stream}/export"
    if output is None or output == "-":
        _download(client, path, params, sys.stdout.buffer)
        sys.stdout.flush()
        return
    target = Path(output)
    partial = target.with_name(target.name + ".part")
    try:
        with partial.open("wb") as out:
            written = _download(client, path, params, out)
        partial.replace(target)
    except BaseException:
        partial.unlink(missing_ok=True)
        raise
    click.echo(f"wrote {written} bytes to {target}", err=True)


def _download(client: Client, path: str, params: dict[str, Any], out: IO[bytes]) -> int:
    """Stream the answer of GET `path` into `out`; the number of bytes written."""
    try:
        with client.http.stream("GET", path, params=params) as response:
            if response.status_code >= 400:
                response.read()
                raise ApiCallError(explain(response))
            written = 0
            for chunk in response.iter_bytes():
                out.write(chunk)
                written += len(chunk)
            return written
    except httpx.HTTPError as err:
        raise ApiCallError(f"cannot reach twinlink at {client.url}: {err}") from err
