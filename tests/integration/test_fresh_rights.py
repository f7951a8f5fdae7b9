"""Twins, roles, devices and tokens are cached by the server; every change counts from the
very next request. Each test first uses what it then changes, so the cache holds it."""

from __future__ import annotations

import asyncio

import httpx
import pytest

from tests.conftest import Server
from tests.integration._device import FakeDevice, make_twin
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._util import apply, assert_problem, make_user, twin_doc, unique

pytestmark = pytest.mark.integration


def grant(server: Server, slug: str, username: str, role: str | None) -> None:
    with server.admin as admin:
        if role is None:
            r = admin.delete(f"/api/v1/twins/{slug}/roles/{username}")
        else:
            r = admin.put(f"/api/v1/twins/{slug}/roles/{username}", json={"role": role})
    assert r.status_code == 200, r.text


def editor_of(server: Server, slug: str) -> tuple[str, str]:
    name = unique("ed")
    token = make_user(server, name)
    grant(server, slug, name, "editor")
    return name, token


async def post_command(server: Server, token: str, slug: str, **body: object) -> httpx.Response:
    headers = {"Authorization": f"Bearer {token}"}
    async with httpx.AsyncClient(base_url=server.url, headers=headers, timeout=30) as client:
        return await client.post(f"/api/v1/twins/{slug}/commands", json={"name": "go", **body})


async def test_a_role_taken_away_refuses_the_next_command_and_history_read(
    server: Server,
) -> None:
    slug, tokens = make_twin(server)
    name, token = editor_of(server, slug)
    async with FakeDevice(server, tokens["rig"]):
        assert (await post_command(server, token, slug)).json()["state"] == "succeeded"
        with server.client(token) as c:
            assert c.get(f"/api/v1/twins/{slug}/streams").status_code == 200
        grant(server, slug, name, None)
        assert_problem(await post_command(server, token, slug), 403)
        with server.client(token) as c:
            assert_problem(c.get(f"/api/v1/twins/{slug}/streams"), 403)
        grant(server, slug, name, "editor")
        assert (await post_command(server, token, slug)).json()["state"] == "succeeded"


async def test_a_device_added_or_removed_counts_at_once(server: Server) -> None:
    slug, tokens = make_twin(server)
    async with FakeDevice(server, tokens["rig"]):
        assert (await post_command(server, server.admin_token, slug)).status_code == 200
        with server.admin as admin:
            r = admin.post(f"/api/v1/twins/{slug}/devices", json={"name": "spare"})
            assert r.status_code == 201, r.text
        # Two devices, both connected: a command that names none has no target.
        async with FakeDevice(server, r.json()["token"]):
            refused = assert_problem(await post_command(server, server.admin_token, slug), 422)
            assert "several devices (rig, spare)" in refused["detail"]
        with server.admin as admin:
            assert admin.delete(f"/api/v1/twins/{slug}/devices/spare").status_code == 200
        r = await post_command(server, server.admin_token, slug)
        assert r.json()["state"] == "succeeded" and r.json()["device"] == "rig"


async def test_a_twin_deleted_and_made_again_is_a_new_twin(server: Server) -> None:
    slug, tokens = make_twin(server)
    async with FakeDevice(server, tokens["rig"]):
        assert (await post_command(server, server.admin_token, slug)).status_code == 200
    with server.admin as admin:
        assert admin.delete(f"/api/v1/twins/{slug}").status_code == 200
        apply(admin, twin_doc(f"urn:{slug}", name="Again", slug=slug))
    refused = assert_problem(await post_command(server, server.admin_token, slug), 409)
    assert "has no devices" in refused["detail"]


def api_token(server: Server, session: str) -> str:
    with server.client(session) as c:
        r = c.post("/api/v1/tokens", json={"name": "script"})
    assert r.status_code == 201, r.text
    return str(r.json()["token"])


def test_a_user_disabled_deleted_or_regrouped_counts_at_once(server: Server) -> None:
    names = [unique("dis"), unique("del"), unique("grp")]
    disabled, deleted, grouped = (api_token(server, make_user(server, n)) for n in names)
    crew = unique("crew")
    slug = unique("crewonly")
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Crew", slug=slug, privacy=crew))
        r = admin.patch(f"/api/v1/users/{names[2]}", json={"groups": [crew]})
        assert r.status_code == 200, r.text
    for token in (disabled, deleted):
        with server.client(token) as c:
            assert c.get("/api/v1/auth/me").status_code == 200
    with server.client(grouped) as c:
        assert c.get(f"/api/v1/twins/{slug}").status_code == 200
    with server.admin as admin:
        assert admin.patch(f"/api/v1/users/{names[0]}", json={"disabled": True}).status_code == 200
        assert admin.delete(f"/api/v1/users/{names[1]}").status_code == 200
        assert admin.patch(f"/api/v1/users/{names[2]}", json={"groups": []}).status_code == 200
    for token in (disabled, deleted):
        with server.client(token) as c:
            assert_problem(c.get("/api/v1/auth/me"), 401)
    with server.client(grouped) as c:
        assert_problem(c.get(f"/api/v1/twins/{slug}"), 404)
    with server.admin as admin:
        assert admin.patch(f"/api/v1/users/{names[0]}", json={"disabled": False}).status_code == 200
    with server.client(disabled) as c:  # an API token outlives disabling (sessions do not)
        assert c.get("/api/v1/auth/me").status_code == 200


async def test_a_new_user_given_a_deleted_user_s_id_has_none_of_its_roles(
    server: Server,
) -> None:
    slug, tokens = make_twin(server)
    name, token = editor_of(server, slug)  # the newest user: its id is given again
    async with FakeDevice(server, tokens["rig"]):
        assert (await post_command(server, token, slug)).status_code == 200
        with server.admin as admin:
            assert admin.delete(f"/api/v1/users/{name}").status_code == 200
        newcomer = make_user(server, unique("new"))
        assert_problem(await post_command(server, newcomer, slug), 403)


async def test_revoking_while_commands_run_refuses_the_rest(server: Server) -> None:
    slug, tokens = make_twin(server)
    name, token = editor_of(server, slug)
    async with FakeDevice(server, tokens["rig"]):
        first = await asyncio.gather(*(post_command(server, token, slug) for _ in range(10)))
        assert {r.status_code for r in first} == {200}
        grant(server, slug, name, "viewer")
        later = await asyncio.gather(*(post_command(server, token, slug) for _ in range(10)))
        assert {r.status_code for r in later} == {403}
