"""`twinlink twins|devices|users|tokens`: registry and account administration over the API."""

from __future__ import annotations

import click

from twinlink.cli.client import Client
from twinlink.cli.common import HelpGroup, client_for, emit, table

# -- twins ---------------------------------------------------------------------------------


@click.group(cls=HelpGroup)
def twins() -> None:
    """List, show and delete twins."""


@twins.command("ls")
@click.option("-k", "--keyword", help="Only twins with a feature of this keyword.")
@click.option("-q", "--name", help="Only twins whose name contains this text.")
@click.option("--mine", is_flag=True, help="Only twins you have a role on.")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.pass_context
def twins_ls(
    ctx: click.Context, keyword: str | None, name: str | None, mine: bool, as_json: bool
) -> None:
    """List the twins you may see (all pages)."""
    client = client_for(ctx)
    items, cursor = [], None
    while True:
        page = client.json(
            "GET",
            "/api/v1/twins",
            params={"limit": 500, "cursor": cursor, "keyword": keyword, "q": name, "mine": mine},
        )
        items.extend(page["items"])
        cursor = page["next_cursor"]
        if not cursor:
            break
    if as_json:
        emit(items, True)
        return
    for t in items:
        click.echo(f"{t['slug']:<28} {t['name']:<32} {','.join(t['levels'])}")


@twins.command("get")
@click.argument("slug")
@click.option(
    "-o", "--output", type=click.Choice(["yaml", "json"]), default="yaml", show_default=True
)
@click.pass_context
def twins_get(ctx: click.Context, slug: str, output: str) -> None:
    """Print a twin's DT document as you may see it."""
    answer = client_for(ctx).json("GET", f"/api/v1/twins/{slug}")
    emit(answer["document"], output == "json")


@twins.command("rm")
@click.argument("slugs", nargs=-1, required=True)
@click.option("--cascade", is_flag=True, help="Also delete every descendant.")
@click.pass_context
def twins_rm(ctx: click.Context, slugs: tuple[str, ...], cascade: bool) -> None:
    """Delete twins."""
    client = client_for(ctx)
    for slug in slugs:
        answer = client.json("DELETE", f"/api/v1/twins/{slug}", params={"cascade": cascade})
        click.echo(f"deleted {', '.join(answer['deleted'])}")


@twins.command("tree")
@click.argument("slug")
@click.option("--up", is_flag=True, help="Show ancestors instead of descendants.")
@click.option("-d", "--depth", default=3, show_default=True)
@click.pass_context
def twins_tree(ctx: click.Context, slug: str, up: bool, depth: int) -> None:
    """Show the composition tree below (or above) a twin."""
    node = client_for(ctx).json(
        "GET",
        f"/api/v1/twins/{slug}/relations",
        params={"direction": "up" if up else "down", "depth": depth},
    )

    def show(n: dict[str, object], indent: int) -> None:
        label = n.get("slug") or f"{n['id']} (not registered here)"
        click.echo(f"{'  ' * indent}{label}  {n.get('name', '')}".rstrip())
        for child in n.get("nodes", []):  # type: ignore[attr-defined]
            show(child, indent + 1)

    show(node, 0)


@twins.command("roles")
@click.argument("slug")
@click.pass_context
def twins_roles(ctx: click.Context, slug: str) -> None:
    """Show who has which role on a twin."""
    for r in client_for(ctx).json("GET", f"/api/v1/twins/{slug}/roles")["roles"]:
        click.echo(f"{r['username']:<24} {r['role']}")


@twins.command("grant")
@click.argument("slug")
@click.argument("username")
@click.argument("role", type=click.Choice(["owner", "editor", "viewer"]))
@click.pass_context
def twins_grant(ctx: click.Context, slug: str, username: str, role: str) -> None:
    """Give USERNAME a ROLE on a twin (owners only)."""
    client_for(ctx).json("PUT", f"/api/v1/twins/{slug}/roles/{username}", json={"role": role})
    click.echo(f"{username} is {role} of {slug}")


@twins.command("revoke")
@click.argument("slug")
@click.argument("username")
@click.pass_context
def twins_revoke(ctx: click.Context, slug: str, username: str) -> None:
    """Take USERNAME's role on a twin away (owners only)."""
    client_for(ctx).json("DELETE", f"/api/v1/twins/{slug}/roles/{username}")
    click.echo(f"{username} has no role on {slug}")


# -- users ---------------------------------------------------------------------------------


@click.group(cls=HelpGroup)
def users() -> None:
    """Manage users (admins)."""


@users.command("ls")
@click.pass_context
def users_ls(ctx: click.Context) -> None:
    """List users."""
    for u in client_for(ctx).json("GET", "/api/v1/users")["users"]:
        flags = [
            x for x in ("admin" if u["is_admin"] else "", "disabled" if u["disabled"] else "") if x
        ]
        click.echo(f"{u['username']:<24} {','.join(u['groups']):<20} {' '.join(flags)}".rstrip())


@users.command("add")
@click.argument("username")
@click.option("--password", help="Password (at least 8 characters; prompted if left out).")
@click.option(
    "--no-password",
    is_flag=True,
    help="No password: the user signs in only with tokens an admin creates (service accounts).",
)
@click.option("--admin", is_flag=True, help="Make the user a platform admin.")
@click.option("-g", "--group", "groups", multiple=True, help="User group (repeatable).")
@click.pass_context
def users_add(
    ctx: click.Context,
    username: str,
    password: str | None,
    no_password: bool,
    admin: bool,
    groups: tuple[str, ...],
) -> None:
    """Create a user."""
    if password is None and not no_password:
        password = click.prompt("Password", hide_input=True, confirmation_prompt=True)
    client_for(ctx).json(
        "POST",
        "/api/v1/users",
        json={
            "username": username,
            "password": password,
            "is_admin": admin,
            "groups": list(groups),
        },
    )
    click.echo(f"created user {username}")


@users.command("set")
@click.argument("username")
@click.option("--password", help="New password.")
@click.option(
    "--current-password",
    help="Your current password, when you change your own (prompted if left out).",
)
@click.option("--admin/--no-admin", default=None, help="Grant or take away platform admin.")
@click.option("-g", "--group", "groups", multiple=True, help="Replace the user's groups.")
@click.option("--no-groups", is_flag=True, help="Remove the user from every group.")
@click.option("--disable/--enable", "disabled", default=None, help="Disable or enable sign-in.")
@click.pass_context
def users_set(
    ctx: click.Context,
    username: str,
    password: str | None,
    current_password: str | None,
    admin: bool | None,
    groups: tuple[str, ...],
    no_groups: bool,
    disabled: bool | None,
) -> None:
    """Change a user. A new password or --disable ends the user's login sessions."""
    client = client_for(ctx)
    body: dict[str, object] = {"password": password, "is_admin": admin, "disabled": disabled}
    if groups or no_groups:
        body["groups"] = [] if no_groups else list(groups)
    if password is not None:
        # The server ignores it unless the change is your own: ask only then.
        asked = current_password is None and _is_me(client, username)
        body["current_password"] = _ask_current_password() if asked else current_password
    client.json(
        "PATCH", f"/api/v1/users/{username}", json={k: v for k, v in body.items() if v is not None}
    )
    click.echo(f"updated user {username}")


def _is_me(client: Client, username: str) -> bool:
    me: str = client.json("GET", "/api/v1/auth/me")["username"]
    return me.lower() == username.lower()


def _ask_current_password() -> str | None:
    # A user without a password (tokens only) has none to give: an empty answer sends none.
    answer: str = click.prompt("Current password", hide_input=True, default="", show_default=False)
    return answer or None


@users.command("rm")
@click.argument("username")
@click.pass_context
def users_rm(ctx: click.Context, username: str) -> None:
    """Delete a user."""
    client_for(ctx).json("DELETE", f"/api/v1/users/{username}")
    click.echo(f"deleted user {username}")


# -- tokens --------------------------------------------------------------------------------


@click.group(cls=HelpGroup)
def tokens() -> None:
    """Manage API tokens."""


@tokens.command("ls")
@click.option("--all", "all_users", is_flag=True, help="Everyone's tokens (admins).")
@click.pass_context
def tokens_ls(ctx: click.Context, all_users: bool) -> None:
    """List your API tokens (never their secrets)."""
    for t in client_for(ctx).json("GET", "/api/v1/tokens", params={"all": all_users})["tokens"]:
        state = t["state"]
        if state == "active":
            state = f"expires {t['expires']}" if t["expires"] else "no expiry"
        owner = f"{t['username']:<16} " if all_users else ""
        this = "  (this token)" if t["current"] else ""
        click.echo(
            f"{t['id']:>5}  {t['prefix']}…  {owner}{t['name']:<24} {t['kind']:<8} {state}{this}"
        )


@tokens.command("create")
@click.argument("name")
@click.option("--expires-in", type=int, help="Lifetime in seconds.")
@click.option("--user", help="Create it for another user, e.g. a service account (admins).")
@click.pass_context
def tokens_create(ctx: click.Context, name: str, expires_in: int | None, user: str | None) -> None:
    """Create an API token; its secret is printed once."""
    path = f"/api/v1/users/{user}/tokens" if user else "/api/v1/tokens"
    answer = client_for(ctx).json("POST", path, json={"name": name, "expires_in_s": expires_in})
    click.echo(answer["token"])
    click.echo(f"(token {answer['id']} '{name}': shown once, store it now)", err=True)


@tokens.command("revoke")
@click.argument("token_id", type=int)
@click.pass_context
def tokens_revoke(ctx: click.Context, token_id: int) -> None:
    """Revoke an API token by its id."""
    client_for(ctx).json("DELETE", f"/api/v1/tokens/{token_id}")
    click.echo(f"revoked token {token_id}")


# -- devices -------------------------------------------------------------------------------


@click.group(cls=HelpGroup)
def devices() -> None:
    """Manage the devices of a twin and their tokens."""


@devices.command("ls")
@click.argument("slug")
@click.pass_context
def devices_ls(ctx: click.Context, slug: str) -> None:
    """List a twin's devices (never their tokens).

    SEEN is `connected` while the device (or the connector speaking for it) is connected,
    else when it was last seen. The last line says where a command that names no device goes.
    """
    answer = client_for(ctx).json("GET", f"/api/v1/twins/{slug}/devices")
    if not answer["devices"]:
        click.echo(f"{slug} has no devices; add one with `twinlink devices add {slug} NAME`.")
        return
    rows = [
        [
            d["name"],
            f"{d['token_prefix']}…",
            "connected" if d.get("connected") else d["last_seen"] or "never seen",
            d["description"],
        ]
        for d in answer["devices"]
    ]
    table(["NAME", "TOKEN", "SEEN", "DESCRIPTION"], rows)
    if "default_device" not in answer:
        return  # a server from before default devices
    if answer["default_device"]:
        click.echo(f"Commands that name no device go to {answer['default_device']}.")
    else:
        click.echo("Commands must name their device (twinlink send ... --device NAME).")


@devices.command("add")
@click.argument("slug")
@click.argument("name")
@click.option("-d", "--description", default="", help="What the device is.")
@click.pass_context
def devices_add(ctx: click.Context, slug: str, name: str, description: str) -> None:
    """Add device NAME to a twin; its token is printed once."""
    answer = client_for(ctx).json(
        "POST", f"/api/v1/twins/{slug}/devices", json={"name": name, "description": description}
    )
    click.echo(answer["token"])
    click.echo(f"(device {name} of {slug}: token shown once, store it now)", err=True)


@devices.command("token")
@click.argument("slug")
@click.argument("name")
@click.pass_context
def devices_token(ctx: click.Context, slug: str, name: str) -> None:
    """Give device NAME a new token (printed once); the old one stops working."""
    answer = client_for(ctx).json("POST", f"/api/v1/twins/{slug}/devices/{name}/token")
    click.echo(answer["token"])
    click.echo(f"(new token for {name}: shown once; the old token no longer works)", err=True)


@devices.command("rm")
@click.argument("slug")
@click.argument("name")
@click.pass_context
def devices_rm(ctx: click.Context, slug: str, name: str) -> None:
    """Remove device NAME and its token."""
    client_for(ctx).json("DELETE", f"/api/v1/twins/{slug}/devices/{name}")
    click.echo(f"removed device {name} of {slug}")
