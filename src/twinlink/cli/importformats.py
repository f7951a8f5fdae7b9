"""`twinlink import wot-td|dtdl|aas FILE`: a WoT Thing Description, a DTDL Interface or an
Asset Administration Shell environment read into a DT document (printed as YAML), or with
`--twin SLUG` its `interface` merged into a twin's part (checked by a dry run; stored with
`--apply`). The commands join `twinlink import` (cli/importing.py).

The file is converted here, by the same code the server exports with (twinlink.formats), and
the twin is changed through the API like any edit: `PUT /api/v1/twins/{slug}` with the part
as stored, so the server's document checks and the caller's rights apply as they always do.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any
from urllib.parse import quote

import click
import orjson

from twinlink.cli.client import Client
from twinlink.cli.common import client_for
from twinlink.domain.errors import InvalidInputError
from twinlink.domain.yamlsource import dump_yaml

# The interface's lists, merged entry by entry by `name`, as privacy parts merge them.
LISTS = ("signals", "properties", "commands")
# Each format's importer and validator take the parsed JSON (a DTDL model may be a list).
Reader = Callable[[Any], dict[str, Any]]
Checker = Callable[[Any], list[str]]


def _converters(kind: str) -> tuple[Checker, Reader]:
    """The format's validator and importer, imported on use: `twinlink --help` and every other
    command start without the formats' libraries (the AAS SDK above all)."""
    if kind == "wot-td":
        from twinlink.formats.wot import import_wot, validate_wot

        return validate_wot, import_wot
    if kind == "dtdl":
        from twinlink.formats.dtdl import import_dtdl, validate_dtdl

        return validate_dtdl, import_dtdl
    from twinlink.formats.aas import import_aas, validate_aas

    return validate_aas, import_aas


ZIP_MAGIC = b"PK\x03\x04"  # an AASX package is a zip file


def read_source(path: str) -> bytes:
    """FILE, or standard input for -, or a ClickException saying why not."""
    try:
        return sys.stdin.buffer.read() if path == "-" else Path(path).read_bytes()
    except OSError as err:
        raise click.ClickException(f"cannot read {path}: {err.strerror}") from err


def convert(kind: str, path: str, check: bool) -> dict[str, Any]:
    """The DT document fragment of FILE: checked against the format's rules first (unless
    `check` is off), so a file that is not what it claims is refused with its problems."""
    raw = read_source(path)
    if kind == "aas" and raw.startswith(ZIP_MAGIC):
        from twinlink.formats.aas import import_aasx

        # The SDK's AASX reader refuses, strictly, what it cannot read as it reads it.
        return _read(import_aasx, raw, path)
    try:
        data = orjson.loads(raw)
    except orjson.JSONDecodeError as err:
        raise click.ClickException(f"{path} is not JSON: {err}") from err
    validate, read = _converters(kind)
    if check:
        problems = validate(data) if isinstance(data, dict | list) else ["not a JSON object"]
        if problems:
            listed = "\n".join(f"  - {p}" for p in problems[:20])
            more = f"\n  ... and {len(problems) - 20} more" if len(problems) > 20 else ""
            raise click.ClickException(
                f"{path} is not a valid {kind} document:\n{listed}{more}\n"
                "  (--no-check imports it anyway, as far as it can be read)"
            )
    return _read(read, data, path)


def _read(read: Callable[[Any], dict[str, Any]], data: Any, path: str) -> dict[str, Any]:
    try:
        return read(data)
    except (InvalidInputError, TypeError, ValueError) as err:
        raise click.ClickException(f"{path}: {err}") from err


def as_document(fragment: dict[str, Any]) -> dict[str, Any]:
    """A DT document `twinlink apply` takes: the fragment with a version (the dt-document's
    `1.0`, unless it names a dt-id as a Twinbase document does). No `privacy`: applied as it
    is, it is a private part until the reader decides otherwise."""
    if "version" in fragment or "dt-id" in fragment:
        return fragment
    return {"version": "1.0", **fragment}


def merge_interface(current: Any, imported: dict[str, Any]) -> tuple[dict[str, Any], list[str]]:
    """`imported` merged into the part's `current` interface: an entry of a list replaces the
    entry of the same name, a new one is added at the end, the others stay; the import's
    other keys (policies) replace the part's, but `default_device`, which names a device of
    the twin the file describes. Answers the interface and what changed."""
    merged = dict(current) if isinstance(current, dict) else {}
    changes: list[str] = []
    for key, value in imported.items():
        if key == "default_device":
            continue
        if key not in LISTS:
            if merged.get(key) != value:
                changes.append(f"{key} set")
            merged[key] = value
            continue
        entries = [e for e in merged.get(key) or [] if isinstance(e, dict)]
        where = {e.get("name"): i for i, e in enumerate(entries)}
        for entry in value:
            at = where.get(entry.get("name"))
            if at is None:
                where[entry.get("name")] = len(entries)
                entries.append(entry)
                changes.append(f"{_singular(key)} {entry.get('name')} added")
            elif entries[at] != entry:
                entries[at] = entry
                changes.append(f"{_singular(key)} {entry.get('name')} replaced")
        merged[key] = entries
    return merged, changes


def _singular(key: str) -> str:
    return {"signals": "signal", "properties": "property", "commands": "command"}[key]


def _choose_part(client: Client, slug: str, level: str | None) -> str:
    """The part to merge into: the one asked for, else the most public part that has an
    interface, else the most public part the caller sees."""
    path = f"/api/v1/twins/{quote(slug, safe='')}/parts"
    levels: list[str] = client.json("GET", path)["levels"]
    if level is not None:
        if level not in levels:
            raise click.ClickException(
                f"twin {slug} has no part {level!r} you may see; its parts: {', '.join(levels)}"
            )
        return level
    if not levels:
        raise click.ClickException(f"you may see no part of twin {slug}")
    for candidate in levels:
        if "interface" in _part(client, slug, candidate):
            return candidate
    return levels[0]


def _part(client: Client, slug: str, level: str) -> dict[str, Any]:
    path = f"/api/v1/twins/{quote(slug, safe='')}/parts/{quote(level, safe='')}"
    part: dict[str, Any] = client.json("GET", path)
    return part


def merge_into_twin(
    client: Client, slug: str, level: str | None, fragment: dict[str, Any], apply: bool
) -> None:
    """Merge the fragment's interface into the twin's part and PUT it back (a dry run unless
    `apply`); prints what changed and the server's outcome."""
    chosen = _choose_part(client, slug, level)
    part = _part(client, slug, chosen)
    part["interface"], changes = merge_interface(part.get("interface"), fragment["interface"])
    answer = client.json(
        "PUT",
        f"/api/v1/twins/{quote(slug, safe='')}",
        params={} if apply else {"dry_run": "true"},
        content=orjson.dumps(part),
        headers={"Content-Type": "application/json"},
    )
    for change in changes:
        click.echo(f"  {change}")
    outcome = answer.get("outcome", "?")
    if apply:
        click.echo(f"twin/{slug} part {chosen}: {outcome}")
    else:
        click.echo(f"twin/{slug} part {chosen}: would be {outcome} (dry run: add --apply to store)")


def _run(
    ctx: click.Context,
    kind: str,
    file: str,
    twin: str | None,
    part: str | None,
    apply: bool,
    check: bool,
) -> None:
    if (apply or part is not None) and twin is None:
        raise click.UsageError("--apply and --part need --twin SLUG: the twin to merge into.")
    fragment = convert(kind, file, check)
    if twin is None:
        click.echo(dump_yaml(as_document(fragment)), nl=False)
        return
    merge_into_twin(client_for(ctx), twin, part, fragment, apply)


def _format_command(kind: str, what: str) -> click.Command:
    short = f"Read {what} as a DT document, or merge its interface into a twin."

    @click.command(kind, short_help=short)
    @click.argument("file")
    @click.option("--twin", metavar="SLUG", help="Merge the interface into this twin's part.")
    @click.option(
        "--part",
        metavar="LEVEL",
        help="With --twin: the privacy part to merge into [default: the most public part "
        "with an interface, else the most public].",
    )
    @click.option("--apply", is_flag=True, help="With --twin: store it (else a dry run).")
    @click.option(
        "--check/--no-check",
        default=True,
        show_default=True,
        help="Refuse a file that breaks the format's rules.",
    )
    @click.pass_context
    def command(
        ctx: click.Context,
        file: str,
        twin: str | None,
        part: str | None,
        apply: bool,
        check: bool,
    ) -> None:
        _run(ctx, kind, file, twin, part, apply, check)

    source = "JSON, or an AASX package" if kind == "aas" else "JSON"
    command.help = (
        f"Read {what} FILE ({source}; - for standard input) and print it as a DT document "
        "(YAML), "
        "which `twinlink apply` takes.\n\nWith --twin SLUG, merge its interface into that "
        "twin's part instead: signals, properties and commands replace those of the same "
        "name and the others stay; checked by the server, stored only with --apply."
    )
    return command


FORMAT_COMMANDS: tuple[click.Command, ...] = (
    _format_command("wot-td", "a W3C WoT Thing Description"),
    _format_command("dtdl", "a DTDL Interface"),
    _format_command("aas", "an Asset Administration Shell environment"),
)
