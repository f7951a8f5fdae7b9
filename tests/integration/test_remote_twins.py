"""Remote twins: a Twinbase site (a real one's layout and published documents, served over
HTTP on loopback) and a second twinlink instance mirrored by `POST
/api/v1/remote-twins/import` and `twinlink import twinbase URL`; read-only copies kept with
their hosting-iri, source and fetch times, a twin that fails listed with why while the
others are kept, importing again answered 304 for what did not change.

The server allows loopback fetches explicitly (TWINLINK_FEDERATION_ALLOW_PRIVATE=true); the
second instance keeps the default, and refuses them."""

from __future__ import annotations

import json
import os
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from click.testing import CliRunner

from tests.conftest import Server, start_server, stop_server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._twinbase_site import TWINS, Site, twinbase_site
from tests.integration._util import apply, assert_problem, make_user, twin_doc, unique
from twinlink.cli.root import main

pytestmark = pytest.mark.integration

IMPORT = "/api/v1/remote-twins/import"
MISSING, BROKEN = "missing-twin", "broken-twin"  # listed in the index: a 404, not JSON


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    srv = start_server(
        tmp_path_factory.mktemp("data"), {"TWINLINK_FEDERATION_ALLOW_PRIVATE": "true"}
    )
    try:
        yield srv
    finally:
        stop_server(srv)


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Site]:
    with twinbase_site(tmp_path_factory.mktemp("site"), (MISSING, BROKEN)) as served:
        (served.root / BROKEN).mkdir()
        (served.root / BROKEN / "index.json").write_text("{not json", "utf-8")
        yield served


@pytest.fixture(scope="module")
def peer(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    """A second twinlink with two public twins and a private one (default fetch policy)."""
    srv = start_server(tmp_path_factory.mktemp("peer"))
    try:
        with srv.admin as admin:
            apply(admin, twin_doc("https://peer.example/pump", name="Peer pump"))
            apply(admin, twin_doc("https://peer.example/tank", name="Peer tank"))
            apply(admin, twin_doc("https://peer.example/safe", name="Peer safe",
                                  privacy="private"))  # fmt: skip
        yield srv
    finally:
        stop_server(srv)


def _import(server: Server, url: str) -> dict[str, Any]:
    with server.admin as admin:
        r = admin.post(IMPORT, json={"url": url}, timeout=120)
    assert r.status_code == 200, r.text
    return r.json()  # type: ignore[no-any-return]


def _by_name(answer: dict[str, Any]) -> dict[str, dict[str, Any]]:
    return {t["name"]: t for t in answer["imported"]}


def _remote(client: httpx.Client, remote_id: int) -> dict[str, Any]:
    r = client.get(f"/api/v1/remote-twins/{remote_id}")
    assert r.status_code == 200, r.text
    return r.json()  # type: ignore[no-any-return]


def test_a_twinbase_site_is_mirrored_and_a_twin_that_fails_says_why(
    server: Server, site: Site
) -> None:
    answer = _import(server, site.url)
    assert answer["source"] == site.url
    imported = {t["url"]: t for t in answer["imported"]}
    assert set(imported) == {site.folder_url(name) for name in TWINS}
    failed = {f["url"]: f for f in answer["failed"]}
    assert set(failed) == {site.folder_url(MISSING), site.folder_url(BROKEN)}
    assert "404" in failed[site.folder_url(MISSING)]["error"]
    assert "not a DT document" in failed[site.folder_url(BROKEN)]["error"]
    with server.admin as admin:
        for name in TWINS:
            published = site.document(name)
            got = _remote(admin, imported[site.folder_url(name)]["id"])
            assert got["document"] == published  # every key, as published
            assert got["dt_id"] == published["dt-id"]
            assert got["name"] == published["name"]
            assert got["source"] == site.url and got["state"] == "reachable"
            assert got["last_modified"] and got["fetched_at"] == got["checked_at"]
        crane = _remote(admin, imported[site.folder_url("crane-ilmatar")]["id"])
    assert crane["document"]["hosting-iri"] == "https://dtw.dtp.fi/crane-ilmatar"  # kept


def test_importing_again_keeps_what_did_not_change_and_updates_the_rest(
    server: Server, site: Site
) -> None:
    first = _by_name(_import(server, site.url + "/index.json"))  # the index's URL works too
    crane_doc = site.document("crane-ilmatar")
    crane_doc["description"] = "Moved to hall 4."
    site.write_twin("crane-ilmatar", crane_doc)
    later = time.time() + 10  # Last-Modified has whole seconds: make the change show
    os.utime(site.root / "crane-ilmatar" / "index.json", (later, later))
    again = _by_name(_import(server, site.url))
    assert {n: t["id"] for n, t in again.items()} == {n: t["id"] for n, t in first.items()}
    juuso, crane = again["Juuso Autiosalo"], again["Ilmatar crane"]
    # Unchanged: a 304, the copy kept and the check recorded.
    assert juuso["fetched_at"] == first["Juuso Autiosalo"]["fetched_at"]
    assert juuso["checked_at"] > first["Juuso Autiosalo"]["checked_at"]
    # Changed: fetched again.
    assert crane["fetched_at"] > first["Ilmatar crane"]["fetched_at"]
    with server.admin as admin:
        assert _remote(admin, crane["id"])["document"]["description"] == "Moved to hall 4."


def test_a_twin_gone_from_its_site_keeps_its_copy_marked_gone(
    server: Server, site: Site, tmp_path: Path
) -> None:
    with twinbase_site(tmp_path / "other") as other:
        [room] = [
            t
            for t in _import(server, other.url)["imported"]
            if t["name"] == "AIIC mechatronics hall"
        ]
        for path in (other.root / "lab-room-K3-143").iterdir():
            path.unlink()
        answer = _import(server, other.url)
    assert [f["url"] for f in answer["failed"]] == [other.folder_url("lab-room-K3-143")]
    with server.admin as admin:
        got = _remote(admin, room["id"])
    assert got["state"] == "gone" and "404" in got["error"]
    assert got["document"]["name"] == "AIIC mechatronics hall"  # the copy is kept
    _import(server, site.url)  # back to the module's site for the tests after this


def test_remote_twins_are_listed_searched_and_read_by_users_and_changed_by_admins(
    server: Server, site: Site
) -> None:
    _import(server, site.url)
    token = make_user(server, unique("reader"))
    with server.client(token) as user:
        r = user.get("/api/v1/remote-twins")
        assert r.status_code == 200, r.text
        names = [t["name"] for t in r.json()["remote_twins"]]
        assert names == sorted(names) and "Ilmatar crane" in names
        found = user.get("/api/v1/remote-twins", params={"q": "MINDSPHERE"}).json()
        assert [t["name"] for t in found["remote_twins"]] == ["Ilmatar crane"]
        crane_id = found["remote_twins"][0]["id"]
        assert _remote(user, crane_id)["document"]["manufacturer"]["name"] == "Konecranes"
        assert_problem(user.post(IMPORT, json={"url": site.url}), 403)
        assert_problem(user.post(f"/api/v1/remote-twins/{crane_id}/refresh"), 403)
        assert_problem(user.delete(f"/api/v1/remote-twins/{crane_id}"), 403)
        # Read-only: no route writes a remote twin's document.
        assert user.put(f"/api/v1/remote-twins/{crane_id}", json={}).status_code == 405
    with server.client() as anonymous:
        assert_problem(anonymous.get("/api/v1/remote-twins"), 401)


def test_an_admin_refreshes_and_deletes_a_remote_twin(server: Server, site: Site) -> None:
    crane = _by_name(_import(server, site.url))["Ilmatar crane"]
    url = f"/api/v1/remote-twins/{crane['id']}"
    with server.admin as admin:
        r = admin.post(f"{url}/refresh")
        assert r.status_code == 200, r.text
        assert r.json()["checked_at"] > crane["checked_at"] and r.json()["state"] == "reachable"
        assert admin.delete(url).status_code == 204
        assert "remote twin" in assert_problem(admin.get(url), 404)["detail"]
        assert_problem(admin.delete(url), 404)
        assert_problem(admin.get("/api/v1/remote-twins/0"), 422)
    _import(server, site.url)  # back for the tests after this


def test_a_site_that_cannot_be_imported_is_a_problem_saying_why(
    server: Server, site: Site, peer: Server
) -> None:
    with server.admin as admin:
        not_index = admin.post(IMPORT, json={"url": site.folder_url("juuso") + "/index.json"})
        assert "`twins`" in assert_problem(not_index, 502)["detail"]
        nobody = admin.post(IMPORT, json={"url": site.url + "/nothing-here"})
        assert "404" in assert_problem(nobody, 502)["detail"]
        assert_problem(admin.post(IMPORT, json={"url": "ftp://127.0.0.1/x"}), 422)
        assert_problem(admin.post(IMPORT, json={"url": ""}), 422)
        assert_problem(admin.post(IMPORT, json={"site": site.url}), 422)
    # The default policy refuses loopback: the site is never asked.
    with peer.admin as admin:
        refused = assert_problem(admin.post(IMPORT, json={"url": site.url}), 422)
        assert "loopback" in refused["detail"]
        assert admin.get("/api/v1/remote-twins").json() == {"remote_twins": []}


def test_another_twinlink_is_mirrored_with_its_public_twins(server: Server, peer: Server) -> None:
    answer = _import(server, peer.url)
    assert answer["failed"] == []
    twins = _by_name(answer)
    assert set(twins) == {"Peer pump", "Peer tank"}  # not its private twin
    with server.admin as admin:
        pump = _remote(admin, twins["Peer pump"]["id"])
    assert pump["dt_id"] == "https://peer.example/pump"
    assert pump["url"].startswith(f"{peer.url}/twins/") and pump["source"] == peer.url
    assert pump["etag"]  # twinlink's documents have ETags: importing again costs a 304
    again = _by_name(_import(server, peer.url))["Peer pump"]
    assert again["fetched_at"] == pump["fetched_at"] and again["checked_at"] > pump["checked_at"]


def test_the_cli_imports_a_site_and_says_what_failed(
    server: Server, site: Site, peer: Server
) -> None:
    runner = CliRunner()
    base = ["--url", server.url, "--token", server.admin_token, "import", "twinbase"]
    result = runner.invoke(main, [*base, site.url], catch_exceptions=False)
    assert result.exit_code == 1, result.output
    assert "Ilmatar crane" in result.output and f"from {site.url}" in result.output
    assert f"failed: {site.folder_url(MISSING)}" in result.output
    assert "2 twins could not be fetched" in result.output
    result = runner.invoke(main, [*base, peer.url, "--json"], catch_exceptions=False)
    assert result.exit_code == 0, result.output
    assert {t["name"] for t in json.loads(result.output)["imported"]} == {"Peer pump", "Peer tank"}
