"""The web app under /app/: its files, the fallback to index.html for the app's own routes,
cache headers, no token, path traversal, and the page shown when it is not built; the site's
icon; the server's own HTML page of a twin."""

from __future__ import annotations

import shutil
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.conftest import Server, start_server, stop_server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._gateway import raw_request
from tests.integration._util import apply, slug_of, twin_doc, unique

pytestmark = pytest.mark.integration

INDEX = b'<!doctype html><html><body><div id="root"></div>twinlink-test-index</body></html>'
SCRIPT = b"console.log('twinlink-test-asset');\n"


@pytest.fixture(scope="module")
def ui_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("ui") / "app"


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory, ui_dir: Path) -> Iterator[Server]:
    srv = start_server(tmp_path_factory.mktemp("data"), {"TWINLINK_UI_DIR": str(ui_dir)})
    try:
        yield srv
    finally:
        stop_server(srv)


@pytest.fixture
def built(ui_dir: Path) -> Path:
    """A fake build: what `npm run build` writes (the server reads the folder per request)."""
    shutil.rmtree(ui_dir, ignore_errors=True)
    (ui_dir / "assets").mkdir(parents=True)
    (ui_dir / "index.html").write_bytes(INDEX)
    (ui_dir / "assets" / "x.js").write_bytes(SCRIPT)
    (ui_dir / "favicon.svg").write_text("<svg xmlns='http://www.w3.org/2000/svg'/>")
    # Something next to the app's folder that traversal would reach.
    (ui_dir.parent / "secret.txt").write_text("twinlink-test-secret")
    return ui_dir


def test_index_without_a_token(server: Server, built: Path) -> None:
    with server.client() as anon:
        r = anon.get("/app/")
        assert r.status_code == 200, r.text
        assert r.content == INDEX
        assert r.headers["content-type"].startswith("text/html")
        assert r.headers["cache-control"] == "no-cache"

        r = anon.get("/app", follow_redirects=False)
        assert r.status_code in (301, 302, 307, 308)
        assert r.headers["location"] == "/app/"
        r = anon.get("/app?view=tree&q=crane", follow_redirects=False)
        assert r.headers["location"] == "/app/?view=tree&q=crane"

        # The landing page links to the app.
        assert 'href="/app/"' in anon.get("/").text


def test_client_routes_get_the_index(server: Server, built: Path) -> None:
    with server.client() as anon:
        for path in ("/app/twins/tingen", "/app/twins/tingen/live", "/app/index.html"):
            r = anon.get(path)
            assert r.status_code == 200, f"{path}: {r.text[:200]}"
            assert r.content == INDEX, path
            assert r.headers["cache-control"] == "no-cache"


def test_assets_are_immutable(server: Server, built: Path) -> None:
    with server.client() as anon:
        r = anon.get("/app/assets/x.js")
        assert r.status_code == 200, r.text
        assert r.content == SCRIPT
        media_type = r.headers["content-type"].split(";")[0]
        assert media_type in ("text/javascript", "application/javascript")
        assert r.headers["cache-control"] == "public, max-age=31536000, immutable"

        r = anon.get("/app/favicon.svg")
        assert r.status_code == 200
        assert r.headers["content-type"].startswith("image/svg+xml")
        assert r.headers["cache-control"] == "no-cache"

        # A missing asset is a 404, not the index served as a script.
        assert anon.get("/app/assets/gone-1234.js").status_code == 404


@pytest.mark.parametrize(
    "target",
    [
        "/app/../../etc/passwd",
        "/app/../secret.txt",
        "/app/assets/../../secret.txt",
        "/app/%2e%2e/secret.txt",
        "/app/%2e%2e%2fsecret.txt",
        "/app/assets%2f..%2f..%2fsecret.txt",
        "/app/..%5csecret.txt",
        "/app/%2E%2E/%2E%2E/etc/passwd",
    ],
)
def test_path_traversal_is_refused(server: Server, built: Path, target: str) -> None:
    status, body = raw_request(server, "GET", target)
    assert status in (400, 404), f"{target}: {status} {body[:200]!r}"
    assert b"twinlink-test-secret" not in body
    assert b"root:" not in body


def test_not_built(server: Server, ui_dir: Path) -> None:
    shutil.rmtree(ui_dir, ignore_errors=True)
    ui_dir.mkdir(parents=True)
    with server.client() as anon:
        for path in ("/app/", "/app/twins/tingen", "/app/assets/x.js"):
            r = anon.get(path)
            assert r.status_code == 503, path
            assert r.headers["content-type"].startswith("text/html")
            assert "not built" in r.text
            assert "make setup" in r.text
            assert "npm run build" in r.text


def test_the_icon_is_served_for_every_page(server: Server, built: Path) -> None:
    with server.client() as anon:
        r = anon.get("/favicon.svg")
        assert r.status_code == 200
        assert r.headers["content-type"].startswith("image/svg+xml")
        assert r.content.startswith(b"<svg")
        # What browsers ask for when a page names no icon
        r = anon.get("/favicon.ico", follow_redirects=False)
        assert r.status_code == 308
        assert r.headers["location"] == "/favicon.svg"
        # The server's pages name it, the not-built page too
        assert 'href="/favicon.svg"' in anon.get("/").text
        shutil.rmtree(built)
        assert 'href="/favicon.svg"' in anon.get("/app/").text


def test_the_twin_page_prints_values_as_yaml_and_links_to_the_app(server: Server) -> None:
    doc = twin_doc(
        f"urn:test:{unique('page')}",
        name="Beam",
        physicalProperties={"youngsModulus": {"value": 2.1e11, "unit": "Pa"}},
        interface={"signals": [{"name": "angle", "unit": "rad", "type": "number"}]},
        flags={"calibrated": True, "retired": False},
    )
    with server.admin as admin:
        slug = slug_of(apply(admin, doc))
    with server.client() as anon:
        r = anon.get(f"/twins/{slug}", headers={"Accept": "text/html"})
    assert r.status_code == 200, r.text
    assert f'<a href="/app/twins/{slug}"><b>Open in the web app</b></a>' in r.text
    assert "<dt>calibrated</dt><dd>true</dd>" in r.text
    assert "True" not in r.text and "False" not in r.text
    assert "2.1e11" in r.text and "210000000000" not in r.text
    assert "<td>angle</td><td>rad</td><td>number</td>" in r.text
