"""`twinlink login` and `twinlink logout`: the session token the other commands use."""

from __future__ import annotations

import click

from twinlink.cli.client import ApiCallError, forget_credentials, save_credentials
from twinlink.cli.common import client_for


@click.command()
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


@click.command()
@click.pass_context
def logout(ctx: click.Context) -> None:
    """Revoke the saved session token and forget it."""
    client = client_for(ctx)
    if client.token:
        try:
            client.json("POST", "/api/v1/auth/logout")
        except ApiCallError as err:
            click.echo(
                f"note: the server did not revoke the token ({err.args[0].splitlines()[0]})",
                err=True,
            )
    path = forget_credentials()
    click.echo(f"Signed out; {path} removed." if path else "Signed out.")
