"""Bad input over HTTP: malformed YAML, schema problems, the size limit, and bad documents or
parameters that must be refused with a problem, never a 500."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest

from tests.conftest import Server, start_server, stop_server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._util import (
    CRANE_SLUG,
    JSON_HEADERS,
    PROBLEM,
    YAML_HEADERS,
    apply,
    assert_problem,
    slug_of,
    twin_count,
    twin_doc,
    unique,
)
from twinlink.domain.jsontext import int64_problem

pytestmark = pytest.mark.integration

# -- bad documents -------------------------------------------------------------------------


def test_malformed_yaml_names_the_line_and_stores_nothing(server: Server) -> None:
    lines = [
        'version: "1.0"',
        "privacy: public",
        f"id: urn:test:{unique('broken')}",
        "name: Broken",
        "description: fine so far",
        "  oops: a key indented under a plain value",  # line 6: "mapping values not allowed"
        "features: []",
    ]
    before = twin_count(server)
    with server.admin as admin:
        r = admin.post("/api/v1/apply", content="\n".join(lines).encode(), headers=YAML_HEADERS)
    body = assert_problem(r, 422)
    assert body["errors"][0]["line"] == 6
    assert "line 6" in body["detail"]
    assert twin_count(server) == before


def test_all_schema_problems_are_reported_at_once_with_lines(server: Server) -> None:
    lines = [
        'version: "1.0"',
        "privacy: public",
        f"id: urn:test:{unique('multi')}",
        "name: Several problems",
        "relations:",
        "  - relationType: cousin",  # line 6: not parent/child/sibling
        "    id: urn:test:other",
        "features:",
        "  - name: Good",
        "  - description: a feature without a name",  # line 10: name missing
        "    keywords: [x]",
    ]
    before = twin_count(server)
    with server.admin as admin:
        r = admin.post("/api/v1/apply", content="\n".join(lines).encode(), headers=YAML_HEADERS)
    body = assert_problem(r, 422)
    found = {(e["path"], e["line"]) for e in body["errors"]}
    assert ("relations[0].relationType", 6) in found
    assert any(path.startswith("features[1]") and line == 10 for path, line in found), found
    assert twin_count(server) == before


def test_rule_problems_are_reported_together_with_type_problems(server: Server) -> None:
    """An unsupported version and a duplicate feature name are problems too; they must not wait
    until the type problems elsewhere in the document are fixed."""
    lines = [
        'version: "9.9"',  # line 1: unsupported version
        "privacy: public",
        f"id: urn:test:{unique('rules')}",
        "name: Rules and types",
        "relations:",
        "  - relationType: cousin",  # line 6
        "    id: urn:test:other",
        "features:",
        "  - name: Twice",
        "  - name: Twice",  # line 10: duplicate name
    ]
    with server.admin as admin:
        r = admin.post("/api/v1/apply", content="\n".join(lines).encode(), headers=YAML_HEADERS)
    body = assert_problem(r, 422)
    lines_reported = {e["line"] for e in body["errors"]}
    assert {1, 6, 10} <= lines_reported, body["errors"]


def test_stream_with_an_invalid_second_document_stores_nothing(server: Server) -> None:
    first_id, second_id = f"urn:test:{unique('s1')}", f"urn:test:{unique('s2')}"
    first = twin_doc(first_id, name="First of two")
    second = twin_doc(second_id, name="Second of two", relations=[("uncle", first_id)])
    stream = first + "---\n" + second
    bad_line = stream.splitlines().index("- relationType: uncle") + 1
    before = twin_count(server)
    with server.admin as admin:
        r = admin.post("/api/v1/apply", content=stream.encode(), headers=YAML_HEADERS)
        body = assert_problem(r, 422)
        [error] = body["errors"]
        assert error["document"] == 1
        assert error["line"] == bad_line
        assert twin_count(server) == before
        listed = admin.get("/api/v1/twins", params={"q": "of two"}).json()["items"]
    assert listed == []


# -- size limit -----------------------------------------------------------------------------


@pytest.fixture(scope="module")
def small_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    srv = start_server(
        tmp_path_factory.mktemp("small"), extra_env={"TWINLINK_MAX_DOCUMENT_BYTES": "2000"}
    )
    try:
        yield srv
    finally:
        stop_server(srv)


def _sized(n: int) -> bytes:
    head = f'version: "1.0"\nprivacy: public\nid: urn:test:sized-{n}\nname: Sized\nfiller: "'
    body = head + "x" * (n - len(head) - 2) + '"\n'
    assert len(body.encode()) == n
    return body.encode()


def test_document_size_limit(small_server: Server) -> None:
    with small_server.admin as admin:
        assert (
            admin.post("/api/v1/apply", content=_sized(2000), headers=YAML_HEADERS).status_code
            == 200
        )
        body = assert_problem(
            admin.post("/api/v1/apply", content=_sized(2001), headers=YAML_HEADERS), 413
        )
        assert "2000" in body["detail"]
        assert_problem(admin.post("/api/v1/twins", content=_sized(2001), headers=YAML_HEADERS), 413)
        assert_problem(
            admin.put("/api/v1/twins/sized-2000", content=_sized(2001), headers=YAML_HEADERS), 413
        )
        too_big_json = json.dumps({"version": "1.0", "name": "J", "pad": "y" * 2100}).encode()
        assert_problem(admin.post("/api/v1/apply", content=too_big_json, headers=JSON_HEADERS), 413)

    def chunks() -> Iterator[bytes]:  # no Content-Length: the limit must hold anyway
        data = _sized(4000)
        yield data[:1500]
        yield data[1500:]

    with small_server.admin as admin:
        assert_problem(admin.post("/api/v1/apply", content=chunks(), headers=YAML_HEADERS), 413)
        names = [t["slug"] for t in admin.get("/api/v1/twins").json()["items"]]
    assert names == ["sized-2000"]


# -- nothing answers 500 ---------------------------------------------------------------------


def _deep(levels: int) -> str:
    return 'version: "1.0"\nprivacy: public\nid: urn:test:deep\nname: Deep\nx: ' + (
        "[" * levels + "]" * levels + "\n"
    )


def _doc(line: str) -> bytes:
    return f"version: '1.0'\nprivacy: public\nname: Extreme\n{line}\n".encode()


BILLION_LAUGHS = (
    'version: "1.0"\nprivacy: public\nid: urn:test:laughs\nname: Laughs\n'
    "a: &a [x, x, x, x, x, x, x, x, x, x]\n"
    + "".join(
        f"{n}: &{n} [{', '.join([f'*{p}'] * 10)}]\n" for p, n in zip("abcde", "bcdef", strict=True)
    )
)

BAD_DOCUMENTS: dict[str, tuple[bytes, str]] = {
    "broken yaml": (b"version: '1.0'\nname: [unclosed\n", "application/yaml"),
    "not a mapping": (b"- just\n- a list\n", "application/yaml"),
    "scalar": (b"hello\n", "application/yaml"),
    "empty": (b"", "application/yaml"),
    "only comments": (b"# nothing here\n", "application/yaml"),
    "not utf-8": (b"\xff\xfe\x00v", "application/yaml"),
    "bad json": (b'{"version": ', "application/json"),
    "json scalar": (b"42", "application/json"),
    "json list of scalars": (b"[1, 2]", "application/json"),
    "no version": (b"privacy: public\nname: x\n", "application/yaml"),
    "unsupported version": (b"version: '7'\nprivacy: public\nname: x\n", "application/yaml"),
    "bad privacy": (b"version: '1.0'\nprivacy: 'a b'\nname: x\n", "application/yaml"),
    "no id nor name": (b"version: '1.0'\nprivacy: public\n", "application/yaml"),
    "id is a list": (b"version: '1.0'\nprivacy: public\nid: [1]\n", "application/yaml"),
    "features not a list": (
        b"version: '1.0'\nprivacy: public\nname: x\nfeatures: 3\n",
        "application/yaml",
    ),
    "non-text key": (b"version: '1.0'\nprivacy: public\nname: x\n123: y\n", "application/yaml"),
    "not a number": (b"version: '1.0'\nprivacy: public\nname: x\nv: .nan\n", "application/yaml"),
    "integer beyond 64 bits": (
        b"version: '1.0'\nprivacy: public\nname: bigint\nbig: 123456789012345678901234567890\n",
        "application/yaml",
    ),
    "slug is a list": (
        b"version: '1.0'\nprivacy: public\nname: x\nslug: [1]\n",
        "application/yaml",
    ),
    "slug is a mapping": (
        b"version: '1.0'\nprivacy: public\nname: x\nslug: {a: 1}\n",
        "application/yaml",
    ),
    "bad slug": (
        b"version: '1.0'\nprivacy: public\nname: x\nslug: Not A Slug\n",
        "application/yaml",
    ),
    "nested 100 deep": (_deep(100).encode(), "application/yaml"),
    "nested 300 deep": (_deep(300).encode(), "application/yaml"),
    "nested 5000 deep": (_deep(5000).encode(), "application/yaml"),
    "json nested 5000 deep": (
        b'{"version": "1.0", "x": ' + b"[" * 5000 + b"]" * 5000 + b"}",
        "application/json",
    ),
    "billion laughs": (BILLION_LAUGHS.encode(), "application/yaml"),
    "two public parts": (
        (
            twin_doc("urn:test:twice", name="a") + "---\n" + twin_doc("urn:test:twice", name="b")
        ).encode(),
        "application/yaml",
    ),
    "self parent": (
        twin_doc(
            "urn:test:selfish", name="Selfish", relations=[("parent", "urn:test:selfish")]
        ).encode(),
        "application/yaml",
    ),
    # Numbers and times beyond what the platform holds (issue 13, items 2 to 4).
    "createdMachine past 2262": (_doc("createdMachine: 9300000000"), "application/yaml"),
    "createdMachine before 1677": (_doc("createdMachine: -9300000000"), "application/yaml"),
    "createdHuman in 9999": (_doc("createdHuman: '9999-12-31T23:59:59Z'"), "application/yaml"),
    "createdHuman in 1000": (_doc("createdHuman: '1000-01-01'"), "application/yaml"),
    "modifiedMachine huge": (_doc("modifiedMachine: '1e999999'"), "application/yaml"),
    "integer of 5000 digits": (_doc("big: " + "7" * 5000), "application/yaml"),
    "base 60 integer": (_doc("big: 1" + ":30" * 100_000), "application/yaml"),
    "json integer beyond 64 bits": (
        b'{"version": "1.0", "name": "j", "createdMachine": 93000000000000000000000}',
        "application/json",
    ),
    "json integer of 5000 digits": (
        b'{"version": "1.0", "name": "j", "x": ' + b"7" * 5000 + b"}",
        "application/json",
    ),
    "json number beyond floats": (
        b'{"version": "1.0", "name": "j", "x": 1e400}',
        "application/json",
    ),
    "yaml key twice": (_doc("name: again"), "application/yaml"),
    "yaml feature key twice": (
        _doc("features:\n  - name: a\n    address: x\n    address: y"),
        "application/yaml",
    ),
    "json key twice": (b'{"version": "1.0", "name": "j", "name": "k"}', "application/json"),
    "interface min as text": (
        _doc("interface:\n  signals:\n    - {name: s, min: '5'}"),
        "application/yaml",
    ),
    "interface max infinite": (
        _doc("interface:\n  signals:\n    - {name: s, max: .inf}"),
        "application/yaml",
    ),
    "interface flag as a word": (
        _doc("interface:\n  properties:\n    - {name: p, writable: 'no'}"),
        "application/yaml",
    ),
}


# Unusual but not necessarily wrong: storing them (losslessly) or refusing them are both fine.
MAY_BE_ACCEPTED = {"nested 100 deep", "nested 300 deep"}
# PUT names the twin by its URL, so a document without an id or name (or with its own `slug`,
# which the URL overrides) is a fine update there.
PUT_MAY_ACCEPT = {"no id nor name", "bad slug", "slug is a list", "slug is a mapping"}


@pytest.fixture(scope="module")
def put_target(server: Server) -> str:
    with server.admin as admin:
        return slug_of(apply(admin, twin_doc(f"urn:test:{unique('target')}", name="PUT target")))


@pytest.mark.parametrize("case", sorted(BAD_DOCUMENTS))
def test_bad_documents_are_refused_with_a_problem_never_500(
    server: Server, put_target: str, case: str
) -> None:
    body, content_type = BAD_DOCUMENTS[case]
    before = twin_count(server)
    for method, path in (
        ("POST", "/api/v1/apply"),
        ("POST", "/api/v1/twins"),
        ("PUT", f"/api/v1/twins/{put_target}"),
    ):
        # A new connection each time: a 500 closes the connection it was sent on.
        with server.admin as admin:
            r = admin.request(method, path, content=body, headers={"Content-Type": content_type})
        assert r.status_code < 500, f"{method} {path}: {r.status_code} {r.text[:300]}"
        acceptable = MAY_BE_ACCEPTED | (PUT_MAY_ACCEPT if method == "PUT" else set())
        if case in acceptable and r.status_code < 300:
            continue
        assert 400 <= r.status_code < 500, f"{method} {path}: {r.status_code} {r.text[:300]}"
        assert r.headers["content-type"].startswith(PROBLEM)
        assert r.json()["detail"]
    if case not in MAY_BE_ACCEPTED:
        assert twin_count(server) == before


def test_bad_query_parameters_are_refused_with_a_problem(server: Server) -> None:
    with server.admin as admin:
        cases: list[tuple[str, dict[str, Any]]] = [
            ("/api/v1/twins", {"limit": 0}),
            ("/api/v1/twins", {"limit": "many"}),
            ("/api/v1/twins", {"cursor": "\x00weird"}),
            ("/api/v1/search", {"limit": 1000}),
            ("/api/v1/search", {"q": "x" * 300}),
            ("/api/v1/search", {"offset": -1}),
            (f"/api/v1/twins/{CRANE_SLUG}/relations", {"depth": 0}),
            (f"/api/v1/twins/{CRANE_SLUG}/relations", {"direction": "sideways"}),
            ("/api/v1/tokens", {"all": "perhaps"}),
        ]
        for path, params in cases:
            r = admin.get(path, params=params)
            assert r.status_code in (200, 422), f"{path} {params}: {r.status_code} {r.text[:300]}"
            if r.status_code == 422:
                assert r.headers["content-type"].startswith(PROBLEM)
        for body in (
            {"username": "has space", "password": "long-enough"},
            {"username": "ok", "password": "short"},
            {"username": "ok2", "password": "long-enough", "groups": ["bad group!"]},
            {"username": "ok3", "password": "long-enough", "is_admin": "maybe"},
        ):
            assert_problem(admin.post("/api/v1/users", json=body), 422)
        assert_problem(admin.post("/api/v1/users", content=b"{not json", headers=JSON_HEADERS), 422)


# -- the same message for the same problem, in YAML and JSON --------------------------------


def _problems(r: httpx.Response) -> list[dict[str, Any]]:
    return assert_problem(r, 422)["errors"]  # type: ignore[no-any-return]


def test_integers_beyond_64_bits_have_one_message_in_yaml_and_json(server: Server) -> None:
    big = 2**64
    with server.admin as admin:
        from_yaml = _problems(
            admin.post("/api/v1/apply", content=_doc(f"size: {big}"), headers=YAML_HEADERS)
        )
        from_json = _problems(
            admin.post(
                "/api/v1/apply",
                content=b'{"version": "1.0",\n "name": "j", "size": %d}' % big,
                headers=JSON_HEADERS,
            )
        )
    assert [(e["line"], e["path"], e["message"]) for e in from_yaml] == [
        (4, "size", int64_problem(big))
    ]
    [problem] = from_json
    assert problem["message"] == f"size: {int64_problem(big)}"


def test_keys_given_twice_are_refused_with_the_second_place(server: Server) -> None:
    yaml_text = b"version: '1.0'\nname: a\nfeatures:\n  - name: f\n    keywords: [x]\n    name: g\n"
    json_text = b'{"version": "1.0",\n "features": [{"name": "f",\n   "name": "g"}]}'
    with server.admin as admin:
        [in_yaml] = _problems(admin.post("/api/v1/apply", content=yaml_text, headers=YAML_HEADERS))
        [in_json] = _problems(admin.put("/api/v1/twins/x", content=json_text, headers=JSON_HEADERS))
    assert (in_yaml["line"], in_yaml["column"], in_yaml["path"]) == (6, 5, "features[0].name")
    assert "key 'name' is given twice" in in_yaml["message"]
    assert (in_json["line"], in_json["column"]) == (3, 4)
    assert "key 'name' is given twice" in in_json["message"]


def test_times_out_of_range_name_the_span_and_the_line(server: Server) -> None:
    text = _doc("createdMachine: 9300000000\ncreatedHuman: '1000-01-01'")
    with server.admin as admin:
        found = _problems(admin.post("/api/v1/twins", content=text, headers=YAML_HEADERS))
    assert [(e["line"], e["path"]) for e in found] == [(4, "createdMachine"), (5, "createdHuman")]
    assert "Unix seconds from -9223372036 to 9223372036" in found[0]["message"]
    assert "1677-09-21T00:12:44Z to 2262-04-11T23:47:16Z" in found[1]["message"]


def test_twinlink_apply_reports_a_refused_document_without_a_traceback(
    server: Server, tmp_path: Path
) -> None:
    path = tmp_path / "huge.yaml"
    path.write_bytes(_doc("big: " + "7" * 5000))
    env = {**os.environ, "XDG_CONFIG_HOME": str(tmp_path), "HOME": str(tmp_path)}
    cli = [sys.executable, "-m", "twinlink", "--url", server.url, "--token", server.admin_token]
    run = subprocess.run(
        [*cli, "apply", "-f", str(path)],
        capture_output=True,
        text=True,
        env=env,
        timeout=60,
    )
    assert run.returncode == 1, run.stderr
    assert "Traceback" not in run.stderr
    assert (
        "line 4, column 6" in run.stderr and "(5000 digits) does not fit in 64 bits" in run.stderr
    )
