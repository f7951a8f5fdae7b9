"""twinlink looks like a Twinbase site to Twinbase's own client code: the `dtweb` package
(PyPI 0.0.1, the client Twinbase's publishing workflow uses) follows a twin's dt-id and reads
`<url>/index.json`; the root `/index.json` and `/index.yaml` are in the shape Twinbase's
workflow writes (`baseurl`, `owner: {dt-id}`, `twins: [{url, name}]`); the files a Twinbase
twin folder has (`index.yaml`, `index.json`, `index.html`) are there; and all of it answers
conditional requests and HEAD."""

from __future__ import annotations

from collections.abc import Iterator
from urllib.parse import urljoin

import dtweb.client  # type: ignore[import-untyped]
import pytest
import requests
import yaml

from tests.conftest import Server, start_server, stop_server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._util import YAML_HEADERS, apply, make_user, twin_doc, unique

pytestmark = pytest.mark.integration

OWNER = "https://dtid.example.org/acme-lab"


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    srv = start_server(tmp_path_factory.mktemp("data"), {"TWINLINK_SITE_OWNER": OWNER})
    try:
        yield srv
    finally:
        stop_server(srv)


def _create(server: Server, name: str, privacy: str = "public") -> str:
    """A twin made from a document without an id, as Twinbase's template makes one: its id
    is then its canonical URL. Returns the slug."""
    slug = unique("tb")
    body = yaml.safe_dump({"version": "1.0", "privacy": privacy, "name": name, "slug": slug})
    with server.admin as admin:
        r = admin.post("/api/v1/apply", content=body.encode(), headers=YAML_HEADERS)
    assert r.status_code == 200, r.text
    [result] = r.json()["results"]
    assert result["id"] == f"{server.url}/twins/{slug}"
    return slug


def test_dtweb_follows_a_dt_id_and_reads_the_document(server: Server) -> None:
    slug = _create(server, "Pump seven")
    dt_id = f"{server.url}/twins/{slug}"
    with server.client() as anon:
        negotiated = anon.get(dt_id, headers={"Accept": "application/json"})
    assert negotiated.status_code == 200
    document = negotiated.json()
    assert document["dt-id"] == dt_id
    # dtweb: GET the dt-id (redirects followed) for the hosting URL, then <url>/index.json.
    host_url = dtweb.client.fetch_host_url(dt_id)
    assert host_url == document["hosting-iri"] == dt_id
    assert dtweb.client.fetch_dt_doc(dt_id) == document
    # A dt-id written with Twinbase's trailing slash is redirected to the same place.
    assert dtweb.client.fetch_host_url(dt_id + "/") == dt_id
    assert dtweb.client.fetch_dt_doc(dt_id + "/") == document


def test_the_root_index_has_twinbases_shape_and_only_what_the_caller_may_see(
    server: Server,
) -> None:
    public = _create(server, "Listed crane")
    hidden = _create(server, "Hidden crane", privacy="private")
    with server.client() as anon:
        as_json = anon.get("/index.json")
        as_yaml = anon.get("/index.yaml")
        page = anon.get("/index.html")
    with server.admin as admin:
        signed_in = admin.get("/index.json")
    assert 'href="/index.json"' in page.text and "Listed crane" in page.text
    assert as_json.headers["content-type"] == "application/json"
    assert as_yaml.headers["content-type"].startswith("application/yaml")
    index = as_json.json()
    assert yaml.safe_load(as_yaml.text) == index
    # The keys Twinbase's generate-base-yaml-json.py writes, less its two GitHub links.
    assert list(index) == ["baseurl", "owner", "twins"]
    assert index["baseurl"] == server.url
    assert index["owner"] == {"dt-id": OWNER}
    urls = {t["url"]: t for t in index["twins"]}
    assert urls[f"{server.url}/twins/{public}"] == {
        "url": f"{server.url}/twins/{public}",
        "name": "Listed crane",
    }
    assert all(list(t) == ["url", "name"] for t in index["twins"])
    assert f"{server.url}/twins/{hidden}" not in urls
    assert "Hidden crane" not in as_json.text
    # A token sees more; the hidden twin's name comes from a private part, so the list shows
    # its slug, as every list does.
    listed = {t["url"]: t["name"] for t in signed_in.json()["twins"]}
    assert listed[f"{server.url}/twins/{hidden}"] == hidden
    assert "private" in signed_in.headers["cache-control"]
    # As Twinbase's index.html does: each entry's url, then <url>/index.json (dtweb).
    for url in urls:
        assert dtweb.client.fetch_dt_doc(url)["hosting-iri"] == url


def test_a_twin_folder_has_twinbases_files(server: Server) -> None:
    slug = _create(server, "Folder twin <b>")
    hidden = _create(server, "Folder secret", privacy="private")
    url = f"{server.url}/twins/{slug}"
    with server.client() as anon:
        page = anon.get(f"{url}/index.html", headers={"Accept": "application/json"})
        # Twinbase's twin page (static/dt-page.html) fetches the relative `index.json`.
        beside = anon.get(urljoin(f"{url}/index.html", "index.json"))
        as_yaml = anon.get(f"{url}/index.yaml")
        missing = anon.get(f"{server.url}/twins/{hidden}/index.html")
    assert page.status_code == 200
    assert page.headers["content-type"].startswith("text/html")
    assert "Folder twin &lt;b&gt;" in page.text
    assert beside.json()["name"] == "Folder twin <b>" == yaml.safe_load(as_yaml.text)["name"]
    assert missing.status_code == 404


@pytest.mark.parametrize(
    "path", ["/index.json", "/index.yaml", "/twins/{slug}", "/twins/{slug}/index.json"]
)
def test_answers_carry_an_etag_and_a_matching_one_gets_304(server: Server, path: str) -> None:
    slug = _create(server, "Cached twin")
    url = path.format(slug=slug)
    with server.client() as anon:
        first = anon.get(url)
        etag = first.headers["etag"]
        again = anon.get(url, headers={"If-None-Match": f'"other", W/{etag}'})
        head = anon.head(url)
        with server.admin as admin:
            apply(admin, twin_doc(f"{server.url}/twins/{slug}", name="Renamed twin"))
        changed = anon.get(url, headers={"If-None-Match": etag})
    assert first.status_code == 200
    assert first.headers["cache-control"] == "no-cache"
    assert "Authorization" in first.headers["vary"]
    assert again.status_code == 304
    assert again.content == b""
    assert again.headers["etag"] == etag
    assert head.status_code == 200
    assert head.content == b""
    assert head.headers["etag"] == etag
    assert head.headers["content-length"] == str(len(first.content))
    # A change to the twin (its listed name in the index) gives a new ETag and a full answer.
    assert changed.status_code == 200
    assert changed.headers["etag"] != etag
    assert "Renamed twin" in changed.text


def test_a_renamed_twins_dt_id_still_leads_to_it(server: Server) -> None:
    old = _create(server, "Moving twin")
    dt_id = f"{server.url}/twins/{old}"
    new = unique("moved")
    with server.admin as admin:
        renamed = {"dt-id": dt_id, "privacy": "public", "name": "Moving twin", "slug": new}
        apply(admin, yaml.safe_dump(renamed))  # Twinbase's key for the id: it comes back so
    with server.client() as anon:
        moved = anon.get(f"{dt_id}/index.json", params={"x": "1"})
        gone = anon.get(f"{server.url}/twins/{unique('never')}")
    assert moved.status_code == 308
    assert moved.headers["location"] == f"{server.url}/twins/{new}/index.json?x=1"
    assert moved.headers["cache-control"] == "no-cache"
    assert gone.status_code == 404
    # dtweb (requests) follows the redirect: the host URL is the new one.
    assert dtweb.client.fetch_host_url(dt_id) == f"{server.url}/twins/{new}"
    assert dtweb.client.fetch_dt_doc(dt_id)["dt-id"] == dt_id


def test_a_renamed_twin_the_caller_may_not_see_is_not_revealed(server: Server) -> None:
    old = _create(server, "Moving secret", privacy="private")
    dt_id = f"{server.url}/twins/{old}"
    new = unique("moved")
    with server.admin as admin:
        apply(admin, twin_doc(dt_id, privacy="private", slug=new))
    outsider = make_user(server, unique("outsider"))
    for token in (None, outsider):
        with server.client(token) as c:
            r = c.get(dt_id)
        assert r.status_code == 404, r.text
        assert new not in r.text
    with server.admin as admin:
        shown = admin.get(dt_id)
    assert shown.headers["location"] == f"{server.url}/twins/{new}"
    # A redirect a token was shown stays out of shared caches, as the document would.
    assert shown.headers["cache-control"] == "private, no-store"
    assert "Authorization" in shown.headers["vary"]


def test_dtweb_reads_nothing_that_needs_a_token(server: Server) -> None:
    """dtweb sends no credentials: a twin without a public part is not found by it, as by
    any reader without a token (requests raises on the 404's problem document, not JSON
    in Twinbase's shape)."""
    slug = _create(server, "Token-only twin", privacy="private")
    r = requests.get(f"{server.url}/twins/{slug}/index.json", timeout=30)
    assert r.status_code == 404
    assert r.headers["content-type"] == "application/problem+json"
    assert "dt-id" not in r.json()


def test_head_and_304_on_a_twin_seen_with_a_token_stay_private(server: Server) -> None:
    slug = _create(server, "Private cached", privacy="private")
    with server.admin as admin:
        first = admin.get(f"/twins/{slug}/index.yaml")
        again = admin.get(f"/twins/{slug}/index.yaml", headers={"If-None-Match": "*"})
    assert first.status_code == 200
    assert first.headers["cache-control"] == "private, no-store"
    assert again.status_code == 304
    assert again.headers["cache-control"] == "private, no-store"
