"""Who may do what once signed in: admin and non-admin users, roles on a twin, and twins
hidden from those who may not see them."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import httpx
import pytest

from tests.conftest import Server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._util import (
    YAML_HEADERS,
    _not_found_shape,
    apply,
    assert_problem,
    make_user,
    twin_doc,
    unique,
)

pytestmark = pytest.mark.integration

# -- users: admin and non-admin -------------------------------------------------------------


def test_non_admin_cannot_manage_users(server: Server) -> None:
    victim = unique("victim")
    token = make_user(server, unique("plain"))
    make_user(server, victim)
    with server.client(token) as c:
        assert_problem(c.get("/api/v1/users"), 403)
        assert_problem(
            c.post("/api/v1/users", json={"username": unique("new"), "password": "long-enough"}),
            403,
        )
        assert_problem(c.patch(f"/api/v1/users/{victim}", json={"disabled": True}), 403)
        assert_problem(c.delete(f"/api/v1/users/{victim}"), 403)
        assert_problem(c.post(f"/api/v1/users/{victim}/tokens", json={"name": "stolen"}), 403)
    with server.admin as admin:
        users = {u["username"]: u for u in admin.get("/api/v1/users").json()["users"]}
    assert victim in users and users[victim]["disabled"] is False


def test_admin_manages_users(server: Server) -> None:
    name = unique("managed")
    with server.admin as admin:
        r = admin.post(
            "/api/v1/users",
            json={"username": name, "password": "long-enough", "groups": ["a-team"]},
        )
        assert r.status_code == 201, r.text
        assert_problem(
            admin.post("/api/v1/users", json={"username": name.upper(), "password": "long-enough"}),
            409,
        )
        r = admin.patch(f"/api/v1/users/{name}", json={"groups": ["b-team"], "is_admin": True})
        assert r.status_code == 200 and r.json()["groups"] == ["b-team"] and r.json()["is_admin"]
        assert name in [u["username"] for u in admin.get("/api/v1/users").json()["users"]]
        assert admin.delete(f"/api/v1/users/{name}").status_code == 200
        assert_problem(admin.delete(f"/api/v1/users/{name}"), 404)
        # The admin does not delete itself by accident.
        assert_problem(admin.delete("/api/v1/users/admin"), 403)
        assert admin.get("/api/v1/auth/me").status_code == 200


# -- roles on a twin -----------------------------------------------------------------------


@dataclass
class Team:
    slug: str
    public_slug: str
    tokens: dict[str, str]  # role (or "none") -> token
    names: dict[str, str]


@pytest.fixture(scope="module")
def team(server: Server) -> Team:
    """A non-public twin (a group part and a private part) and a public twin, with users that
    hold each role on both, and one user with no role."""
    slug, public_slug = unique("roles"), unique("roles-pub")
    with server.admin as admin:
        apply(
            admin,
            twin_doc(f"urn:test:{slug}", name="Role twin", privacy="crew", slug=slug),
            twin_doc(
                f"urn:test:{slug}",
                privacy="private",
                features=[{"name": "Vault", "requirement": "vault-combination"}],
            ),
        )
        apply(admin, twin_doc(f"urn:test:{public_slug}", name="Public role twin", slug=public_slug))
    names = {role: unique(role) for role in ("viewer", "editor", "owner", "none")}
    tokens = {role: make_user(server, name) for role, name in names.items()}
    with server.admin as admin:
        for role in ("viewer", "editor", "owner"):
            for s in (slug, public_slug):
                r = admin.put(f"/api/v1/twins/{s}/roles/{names[role]}", json={"role": role})
                assert r.status_code == 200, r.text
    return Team(slug, public_slug, tokens, names)


def _update(c: httpx.Client, slug: str, name: str) -> httpx.Response:
    return c.put(
        f"/api/v1/twins/{slug}",
        content=twin_doc(f"urn:test:{slug}", name=name, privacy="crew").encode(),
        headers=YAML_HEADERS,
    )


def test_viewer_reads_but_cannot_change(server: Server, team: Team) -> None:
    with server.client(team.tokens["viewer"]) as c:
        r = c.get(f"/api/v1/twins/{team.slug}")
        assert r.status_code == 200, r.text
        assert r.json()["role"] == "viewer"
        assert r.json()["document"]["name"] == "Role twin"
        assert "vault-combination" not in r.text  # private is for owners and editors
        assert c.get(f"/api/v1/twins/{team.slug}/roles").status_code == 200
        assert_problem(_update(c, team.slug, "Changed by viewer"), 403)
        assert_problem(c.delete(f"/api/v1/twins/{team.slug}"), 403)
        assert_problem(
            c.put(f"/api/v1/twins/{team.slug}/roles/{team.names['none']}", json={"role": "viewer"}),
            403,
        )
    with server.admin as admin:
        assert admin.get(f"/api/v1/twins/{team.slug}").json()["document"]["name"] == "Role twin"


def test_editor_changes_but_cannot_delete_or_grant(server: Server, team: Team) -> None:
    with server.client(team.tokens["editor"]) as c:
        r = c.get(f"/api/v1/twins/{team.slug}")
        assert r.json()["role"] == "editor"
        assert "vault-combination" in r.text
        r = _update(c, team.slug, "Renamed by editor")
        assert r.status_code == 200, r.text
        assert r.json()["outcome"] == "updated"
        assert c.get(f"/api/v1/twins/{team.slug}").json()["document"]["name"] == (
            "Renamed by editor"
        )
        assert_problem(c.delete(f"/api/v1/twins/{team.slug}"), 403)
        assert_problem(
            c.put(f"/api/v1/twins/{team.slug}/roles/{team.names['none']}", json={"role": "viewer"}),
            403,
        )
        assert_problem(c.delete(f"/api/v1/twins/{team.slug}/roles/{team.names['viewer']}"), 403)
    with server.client(team.tokens["none"]) as c:
        assert_problem(c.get(f"/api/v1/twins/{team.slug}"), 404)  # still not granted


def test_user_without_role_does_not_learn_a_non_public_twin_exists(
    server: Server, team: Team
) -> None:
    """Every route that names a twin by its slug answers as if a twin the caller may not see
    did not exist. (Applying a document whose *id* is taken is another matter: the id cannot be
    hidden. Here the documents carry no id; the caller only knows the slug.)"""
    missing = unique("missing")
    with server.client(team.tokens["none"]) as c:
        cases: list[tuple[str, str, dict[str, Any]]] = [
            ("GET", "/api/v1/twins/{}", {}),
            ("GET", "/twins/{}", {}),
            ("GET", "/api/v1/twins/{}/parts", {}),
            ("GET", "/api/v1/twins/{}/relations", {}),
            ("GET", "/api/v1/twins/{}/roles", {}),
            ("DELETE", "/api/v1/twins/{}", {}),
            ("PUT", "/api/v1/twins/{}/roles/" + team.names["none"], {"json": {"role": "owner"}}),
            (
                "PUT",
                "/api/v1/twins/{}",
                {"content": b'version: "1.0"\nprivacy: crew\nname: x\n', "headers": YAML_HEADERS},
            ),
        ]
        for method, path, kwargs in cases:
            hidden = c.request(method, path.format(team.slug), **kwargs)
            absent = c.request(method, path.format(missing), **kwargs)
            assert hidden.status_code == 404, (
                f"{method} {path}: {hidden.status_code} {hidden.text[:200]} "
                "(a twin the caller may not see must look like one that does not exist)"
            )
            assert _not_found_shape(hidden, team.slug) == _not_found_shape(absent, missing)
        listed = c.get("/api/v1/twins", params={"limit": 500}).json()["items"]
        assert team.slug not in [t["slug"] for t in listed]


def test_user_without_role_cannot_change_a_public_twin(server: Server, team: Team) -> None:
    slug = team.public_slug
    with server.client(team.tokens["none"]) as c:
        r = c.get(f"/api/v1/twins/{slug}")
        assert r.status_code == 200 and r.json()["role"] is None
        doc = twin_doc(f"urn:test:{slug}", name="Defaced").encode()
        assert_problem(c.put(f"/api/v1/twins/{slug}", content=doc, headers=YAML_HEADERS), 403)
        assert_problem(c.post("/api/v1/apply", content=doc, headers=YAML_HEADERS), 403)
        assert_problem(c.delete(f"/api/v1/twins/{slug}"), 403)
        assert_problem(c.delete(f"/api/v1/twins/{slug}/parts/public"), 403)
        assert_problem(
            c.put(f"/api/v1/twins/{slug}/roles/{team.names['none']}", json={"role": "owner"}), 403
        )
        assert_problem(c.get(f"/api/v1/twins/{slug}/roles"), 403)
    with server.admin as admin:
        assert admin.get(f"/api/v1/twins/{slug}").json()["name"] == "Public role twin"


def test_owner_grants_roles_and_deletes(server: Server) -> None:
    owner_name, friend_name = unique("own"), unique("friend")
    owner, friend = make_user(server, owner_name), make_user(server, friend_name)
    slug = unique("owned")
    with server.client(owner) as c:
        # A user who creates a twin owns it.
        r = c.post(
            "/api/v1/twins",
            content=twin_doc(
                f"urn:test:{slug}", name="Mine", privacy="private", slug=slug
            ).encode(),
            headers=YAML_HEADERS,
        )
        assert r.status_code == 201, r.text
        roles = c.get(f"/api/v1/twins/{slug}/roles").json()["roles"]
        assert {"username": owner_name, "role": "owner"} in roles
    with server.client(friend) as f:
        assert_problem(f.get(f"/api/v1/twins/{slug}"), 404)
    with server.client(owner) as c:
        r = c.put(f"/api/v1/twins/{slug}/roles/{friend_name}", json={"role": "editor"})
        assert r.status_code == 200, r.text
        assert_problem(
            c.put(f"/api/v1/twins/{slug}/roles/{friend_name}", json={"role": "god"}), 422
        )
        assert_problem(
            c.put(f"/api/v1/twins/{slug}/roles/{unique('ghost')}", json={"role": "viewer"}), 404
        )
    with server.client(friend) as f:
        assert f.get(f"/api/v1/twins/{slug}").json()["role"] == "editor"
    with server.client(owner) as c:
        assert c.delete(f"/api/v1/twins/{slug}/roles/{friend_name}").status_code == 200
    with server.client(friend) as f:
        assert_problem(f.get(f"/api/v1/twins/{slug}"), 404)
    with server.client(owner) as c:
        r = c.delete(f"/api/v1/twins/{slug}")
        assert r.status_code == 200, r.text
        assert r.json()["deleted"] == [slug]
        assert_problem(c.get(f"/api/v1/twins/{slug}"), 404)


def test_admin_can_do_everything_on_any_twin(server: Server) -> None:
    owner = make_user(server, unique("solo"))
    someone = unique("someone")
    make_user(server, someone)
    slug = unique("admin-target")
    with server.client(owner) as c:
        apply(
            c,
            twin_doc(
                f"urn:test:{slug}",
                name="Solo",
                privacy="private",
                slug=slug,
                features=[{"name": "Safe", "requirement": "solo-secret"}],
            ),
        )
    with server.admin as admin:
        r = admin.get(f"/api/v1/twins/{slug}")
        assert r.status_code == 200 and r.json()["role"] == "admin"
        assert "solo-secret" in r.text
        assert admin.get(f"/api/v1/twins/{slug}/roles").status_code == 200
        assert (
            admin.put(f"/api/v1/twins/{slug}/roles/{someone}", json={"role": "viewer"}).status_code
            == 200
        )
        r = admin.put(
            f"/api/v1/twins/{slug}",
            content=twin_doc(
                f"urn:test:{slug}", name="Solo (admin edit)", privacy="private"
            ).encode(),
            headers=YAML_HEADERS,
        )
        assert r.status_code == 200 and r.json()["outcome"] == "updated"
        assert admin.delete(f"/api/v1/twins/{slug}").status_code == 200
        assert_problem(admin.get(f"/api/v1/twins/{slug}"), 404)


def test_a_taken_id_does_not_reveal_the_hidden_twin(server: Server) -> None:
    """Creating or applying a document whose id belongs to a twin the caller may not see has to
    be refused (ids are unique), but the answer must not tell the twin's slug or name."""
    secret_slug, dt_id = unique("secret-slug"), f"urn:test:{unique('taken-id')}"
    with server.admin as admin:
        apply(admin, twin_doc(dt_id, name="Secret name", privacy="private", slug=secret_slug))
    outsider = make_user(server, unique("outsider"))
    body = twin_doc(dt_id, name="Mine now", privacy="public").encode()
    with server.client(outsider) as c:
        for path in ("/api/v1/twins", "/api/v1/apply"):
            r = c.post(path, content=body, headers=YAML_HEADERS)
            assert r.status_code in (403, 409), f"{path}: {r.status_code} {r.text}"
            assert r.headers["content-type"].startswith("application/problem+json")
            assert secret_slug not in r.text, f"{path} revealed the slug: {r.text}"
            assert "Secret name" not in r.text
    with server.admin as admin:
        assert admin.get(f"/api/v1/twins/{secret_slug}").json()["document"]["name"] == (
            "Secret name"
        )
