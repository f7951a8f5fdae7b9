"""A twin's document in the exchange formats, served by a real server: `/twins/{slug}?format=`
(WoT TD, DTDL, AAS JSON, and the document's own YAML, JSON and HTML) and
`/twins/{slug}/export.aasx`, each checked with its format's validator (the TD JSON Schema,
DTDL v3's rules, the BaSyx SDK), with the document's visibility rules."""

from __future__ import annotations

import io
import json
from collections.abc import Callable
from typing import Any

import httpx
import pytest
import yaml
from basyx.aas import model
from basyx.aas.adapter.aasx import AASXReader, DictSupplementaryFileContainer

from tests.conftest import EXAMPLES, Server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._util import apply, assert_problem, make_user, twin_doc, unique
from twinlink.formats import FORMATS
from twinlink.formats.aas import validate_aas
from twinlink.formats.dtdl import validate_dtdl
from twinlink.formats.wot import validate_wot

pytestmark = pytest.mark.integration

TINGEN = EXAMPLES / "tingen" / "tingen.yaml"
VALIDATORS: dict[str, Callable[[Any], list[str]]] = {
    "wot-td": validate_wot,
    "dtdl": validate_dtdl,
    "aas-json": validate_aas,
}
AASX = "application/asset-administration-shell-package+xml"
# A signal only the private part names: an export may show it only to who may read that part.
SECRET_SIGNAL = "Hidden_Strain_microstrain"


def _interface(*signals: str) -> dict[str, Any]:
    return {
        "signals": [{"name": s, "unit": "1", "type": "number"} for s in signals],
        "properties": [{"name": "gain", "type": "number", "writable": True}],
        "commands": [{"name": "reset", "parameters": []}],
    }


@pytest.fixture(scope="module")
def tingen(server: Server) -> str:
    with server.admin as admin:
        r = admin.post(
            "/api/v1/apply",
            content=TINGEN.read_bytes(),
            headers={"Content-Type": "application/yaml"},
        )
    assert r.status_code == 200, r.text
    return str(r.json()["results"][0]["slug"])


@pytest.fixture(scope="module")
def split(server: Server) -> str:
    """A twin with a public part and a private part that adds a signal."""
    slug = unique("split")
    dt_id = f"https://twins.example/{slug}"
    public = twin_doc(dt_id, name="Split rig", interface=_interface("Angle_rad"))
    private = twin_doc(dt_id, privacy="private", interface=_interface(SECRET_SIGNAL))
    with server.admin as admin:
        apply(admin, public, private)
    return slug


@pytest.fixture(scope="module")
def private(server: Server) -> str:
    """A twin with a private part only: not there for a reader without a token."""
    slug = unique("private")
    doc = twin_doc(f"https://twins.example/{slug}", privacy="private", name="Private rig",
                   interface=_interface("Pressure_Pa"))  # fmt: skip
    with server.admin as admin:
        apply(admin, doc)
    return slug


def _mqtt_url(server: Server) -> str:
    with server.admin as admin:
        status = admin.get("/api/v1/mqtt").json()
    return f"mqtt://{status['address']}"


@pytest.mark.parametrize("fmt", sorted(FORMATS))
def test_each_export_validates_and_points_at_this_server(
    server: Server, tingen: str, fmt: str
) -> None:
    with server.client() as anonymous:
        r = anonymous.get(f"/twins/{tingen}", params={"format": fmt})
    assert r.status_code == 200, r.text
    media_type = FORMATS[fmt][0]
    assert r.headers["content-type"].split(";")[0] == media_type
    assert r.headers["link"] == f'<{server.url}/twins/{tingen}>; rel="canonical"'
    exported = r.json()
    assert VALIDATORS[fmt](exported) == []
    text = json.dumps(exported)
    # Every name of the interface is in the export; its links are this server's.
    interface = yaml.safe_load(TINGEN.read_text("utf-8"))["interface"]
    for kind in ("signals", "properties", "commands"):
        for entry in interface.get(kind, []):
            assert entry["name"] in text, (kind, entry["name"])
    assert server.url in text
    if fmt == "wot-td":  # the forms name the embedded listener as it really listens
        assert _mqtt_url(server) in text


def test_format_wins_over_accept(server: Server, tingen: str) -> None:
    with server.client() as c:
        as_json = c.get(f"/twins/{tingen}?format=json", headers={"Accept": "application/yaml"})
        as_yaml = c.get(f"/twins/{tingen}?format=yaml", headers={"Accept": "application/json"})
        as_html = c.get(f"/twins/{tingen}?format=html", headers={"Accept": "application/json"})
        as_td = c.get(f"/twins/{tingen}?format=wot-td", headers={"Accept": "text/html"})
        by_accept = c.get(f"/twins/{tingen}", headers={"Accept": "application/json"})
    assert as_json.headers["content-type"].startswith("application/json")
    assert as_yaml.headers["content-type"].startswith("application/yaml")
    assert as_html.headers["content-type"].startswith("text/html")
    assert as_td.headers["content-type"].startswith("application/td+json")
    assert as_json.json() == by_accept.json() == yaml.safe_load(as_yaml.text)


def test_an_unknown_format_is_refused_with_the_valid_ones(server: Server, tingen: str) -> None:
    with server.client() as c:
        r = c.get(f"/twins/{tingen}", params={"format": "rdf"})
    body = assert_problem(r, 422)
    for name in ("yaml", "json", "html", *FORMATS):
        assert f"'{name}'" in body["detail"], body["detail"]


@pytest.mark.parametrize("fmt", sorted(FORMATS))
def test_a_private_twin_needs_a_token(server: Server, private: str, fmt: str) -> None:
    with server.client() as anonymous:
        hidden = anonymous.get(f"/twins/{private}", params={"format": fmt})
    assert_problem(hidden, 404)
    with server.admin as admin:
        shown = admin.get(f"/twins/{private}", params={"format": fmt})
    assert shown.status_code == 200, shown.text
    assert shown.headers["cache-control"] == "private, no-store"
    assert VALIDATORS[fmt](shown.json()) == []
    assert "Pressure_Pa" in shown.text


@pytest.mark.parametrize("fmt", sorted(FORMATS))
def test_an_export_holds_what_the_reader_may_see(server: Server, split: str, fmt: str) -> None:
    # Signed in, with no role on the twin: the public part, as anyone reads it.
    reader = make_user(server, unique("reader"))
    with server.admin as admin:
        full = admin.get(f"/twins/{split}", params={"format": fmt})
    with server.client() as anonymous:
        public = anonymous.get(f"/twins/{split}", params={"format": fmt})
    with server.client(reader) as signed_in:
        signed = signed_in.get(f"/twins/{split}", params={"format": fmt})
    for r in (full, public, signed):
        assert r.status_code == 200, r.text
        assert VALIDATORS[fmt](r.json()) == []
        assert "Angle_rad" in r.text
    assert SECRET_SIGNAL in full.text
    assert SECRET_SIGNAL not in public.text
    assert SECRET_SIGNAL not in signed.text
    assert "cache-control" not in public.headers or "private" not in public.headers["cache-control"]
    assert signed.headers["cache-control"] == "private, no-store"


def _read_aasx(package: bytes) -> model.DictIdentifiableStore:  # type: ignore[type-arg]
    objects: model.DictIdentifiableStore = model.DictIdentifiableStore()  # type: ignore[type-arg]
    files = DictSupplementaryFileContainer()  # type: ignore[no-untyped-call]
    with AASXReader(io.BytesIO(package)) as reader:
        reader.read_into(objects, files)
    return objects


def test_the_aasx_package_opens_with_basyx(server: Server, tingen: str) -> None:
    with server.client() as anonymous:
        r = anonymous.get(f"/twins/{tingen}/export.aasx")
    assert r.status_code == 200, r.text
    assert r.headers["content-type"] == AASX
    assert r.headers["content-disposition"] == f'attachment; filename="{tingen}.aasx"'
    objects = _read_aasx(r.content)
    shells = [o for o in objects if isinstance(o, model.AssetAdministrationShell)]
    submodels = [o for o in objects if isinstance(o, model.Submodel)]
    assert len(shells) == 1 and submodels
    # The package holds what the JSON export holds.
    with server.client() as anonymous:
        environment = anonymous.get(f"/twins/{tingen}?format=aas-json").json()
    assert {s["id"] for s in environment["submodels"]} == {str(s.id) for s in submodels}
    assert environment["assetAdministrationShells"][0]["id"] == str(shells[0].id)


def test_the_aasx_package_of_a_private_twin_needs_a_token(server: Server, private: str) -> None:
    with server.client() as anonymous:
        assert_problem(anonymous.get(f"/twins/{private}/export.aasx"), 404)
    with server.admin as admin:
        r = admin.get(f"/twins/{private}/export.aasx")
    assert r.status_code == 200, r.text
    assert r.headers["cache-control"] == "private, no-store"
    objects = _read_aasx(r.content)
    assert any(isinstance(o, model.Submodel) for o in objects)


def test_an_unknown_twin_is_a_404_in_every_format(server: Server) -> None:
    with server.admin as admin:
        answers: list[httpx.Response] = [
            admin.get("/twins/no-such-twin", params={"format": fmt}) for fmt in FORMATS
        ]
        answers.append(admin.get("/twins/no-such-twin/export.aasx"))
    for r in answers:
        assert_problem(r, 404)


@pytest.mark.parametrize("fmt", sorted(FORMATS))
def test_an_export_is_revalidated_by_its_etag(server: Server, tingen: str, fmt: str) -> None:
    """An export is the same bytes while the document is unchanged: a client (or cache)
    holding it gets 304."""
    with server.client() as c:
        first = c.get(f"/twins/{tingen}", params={"format": fmt})
        again = c.get(
            f"/twins/{tingen}",
            params={"format": fmt},
            headers={"If-None-Match": first.headers["etag"]},
        )
    assert first.status_code == 200
    assert again.status_code == 304 and again.content == b""
