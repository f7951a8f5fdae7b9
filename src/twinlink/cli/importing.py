"""`twinlink import`: documents of other systems brought into twinlink. `twinlink import
twinbase URL` mirrors a Twinbase site (or another twinlink) as read-only remote twins; the
server fetches them (docs/federation.md, "Mirroring a Twinbase site")."""

from __future__ import annotations

from typing import Any

import click

from twinlink.cli.client import Client
from twinlink.cli.common import HelpGroup, client_for, emit, table

# An import fetches every twin of the site, four at a time, each within the server's
# TWINLINK_FEDERATION_TIMEOUT_S: a large site takes longer than the client's usual 30 s.
IMPORT_TIMEOUT_S = 600.0


@click.group("import", cls=HelpGroup)
def import_() -> None:
    """Bring documents of other systems into twinlink."""


@import_.command("twinbase")
@click.argument("url")
@click.option("--json", "as_json", is_flag=True, help="Print the raw JSON answer.")
@click.pass_context
def twinbase(ctx: click.Context, url: str, as_json: bool) -> None:
    """Mirror the twins of the Twinbase site (or twinlink) at URL as read-only remote twins.

    URL is the site's root, whose index.json lists its twins, or that index.json itself.
    Importing again updates them. Exits with status 1 when a twin could not be fetched
    (the others are kept). Needs an admin's token.
    """
    root = client_for(ctx)
    client = Client(root.url, root.token, timeout=IMPORT_TIMEOUT_S)
    with client.http:  # closed after: the command may run inside another program
        answer: dict[str, Any] = client.json(
            "POST", "/api/v1/remote-twins/import", json={"url": url}
        )
    if as_json:
        emit(answer, True)
    else:
        _show(answer)
    if answer["failed"]:
        count = len(answer["failed"])
        raise click.ClickException(f"{count} twin{'s' if count != 1 else ''} could not be fetched")


def _show(answer: dict[str, Any]) -> None:
    rows = [[str(t["id"]), t["name"], t["state"], t["url"]] for t in answer["imported"]]
    if rows:
        table(["ID", "NAME", "STATE", "URL"], rows)
    for failure in answer["failed"]:
        click.echo(f"failed: {failure['url']}: {failure['error']}", err=True)
    count = len(answer["imported"])
    click.echo(f"({count} twin{'s' if count != 1 else ''} from {answer['source']})")
