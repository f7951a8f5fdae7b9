"""Helpers shared by the integration tests: users, documents, problem+json checks."""

from __future__ import annotations

import secrets
import time
from collections.abc import Callable
from datetime import datetime
from pathlib import Path
from typing import Any

import httpx
import yaml

from tests.conftest import EXAMPLES, Server

PROBLEM = "application/problem+json"
YAML_HEADERS = {"Content-Type": "application/yaml"}
JSON_HEADERS = {"Content-Type": "application/json"}
ILMATAR = EXAMPLES / "ilmatar"
CRANE_SLUG = "ilmatar-k16052"  # derived from the id http://d-t.fi/ilmatar-K16052
HALL_SLUG = "aalto-industrial-hall"


def unique(prefix: str) -> str:
    """A slug-safe name no other test uses, so tests sharing a server do not collide."""
    return f"{prefix}-{secrets.token_hex(4)}"


def assert_problem(r: httpx.Response, status: int) -> dict[str, Any]:
    assert r.status_code == status, f"expected {status}, got {r.status_code}: {r.text[:500]}"
    assert r.headers["content-type"].startswith(PROBLEM), r.headers.get("content-type")
    body = r.json()
    assert body["status"] == status
    assert isinstance(body["detail"], str) and body["detail"]
    if status == 401:
        assert r.headers.get("www-authenticate", "").lower().startswith("bearer"), r.headers
    return body  # type: ignore[no-any-return]


def make_user(
    server: Server,
    username: str,
    *,
    groups: list[str] | None = None,
    is_admin: bool = False,
    password: str | None = None,
) -> str:
    """Create a user as admin and log them in; returns their session token."""
    password = password or f"pw-{secrets.token_hex(8)}"
    with server.admin as admin:
        r = admin.post(
            "/api/v1/users",
            json={
                "username": username,
                "password": password,
                "groups": groups or [],
                "is_admin": is_admin,
            },
        )
        assert r.status_code == 201, r.text
    return login(server, username, password)


def login(server: Server, username: str, password: str) -> str:
    with server.client() as c:
        r = c.post("/api/v1/auth/login", json={"username": username, "password": password})
    assert r.status_code == 200, r.text
    return str(r.json()["token"])


def twin_doc(
    dt_id: str,
    *,
    name: str | None = None,
    privacy: str = "public",
    relations: list[tuple[str, str]] = (),  # type: ignore[assignment]
    features: list[dict[str, Any]] | None = None,
    **extra: Any,
) -> str:
    """A DT document as YAML text. `relations` are (relationType, other id) pairs."""
    doc: dict[str, Any] = {"version": "1.0", "privacy": privacy, "id": dt_id}
    if name is not None:
        doc["name"] = name
    doc.update(extra)
    if relations:
        doc["relations"] = [{"relationType": t, "id": other} for t, other in relations]
    if features is not None:
        doc["features"] = features
    return yaml.safe_dump(doc, sort_keys=False, allow_unicode=True)


def get_doc(c: httpx.Client, slug: str) -> dict[str, Any]:
    r = c.get(f"/api/v1/twins/{slug}")
    assert r.status_code == 200, r.text
    return r.json()["document"]  # type: ignore[no-any-return]


def slug_of(r: httpx.Response) -> str:
    return str(r.json()["results"][0]["slug"])


def _feature(doc: dict[str, Any], name: str) -> dict[str, Any]:
    [found] = [f for f in doc.get("features", []) if f["name"] == name]
    return dict(found)


def apply(client: httpx.Client, *docs: str, expect: int | None = 200) -> httpx.Response:
    """POST /api/v1/apply of one or several YAML documents as one stream."""
    r = client.post("/api/v1/apply", content="---\n".join(docs).encode(), headers=YAML_HEADERS)
    if expect is not None:
        assert r.status_code == expect, r.text
    return r


def apply_file(client: httpx.Client, path: Path) -> httpx.Response:
    r = client.post("/api/v1/apply", content=path.read_bytes(), headers=YAML_HEADERS)
    assert r.status_code == 200, f"{path.name}: {r.text}"
    return r


def example_documents() -> list[Path]:
    """Every example DT document: the YAML files under examples/ but the library's packages
    (examples/library: twin.yaml and document templates, pushed to the library, not applied)."""
    return sorted(
        p for p in EXAMPLES.rglob("*.yaml") if p.relative_to(EXAMPLES).parts[0] != "library"
    )


def apply_examples(server: Server) -> None:
    """Every example document, one file per request (as `twinlink apply -f examples/` does)."""
    with server.admin as admin:
        for path in example_documents():
            apply_file(admin, path)


def load_yaml(path: Path) -> dict[str, Any]:
    data = yaml.safe_load(path.read_text("utf-8"))
    assert isinstance(data, dict)
    return data


def _not_found_shape(r: httpx.Response, slug: str) -> dict[str, Any]:
    body = assert_problem(r, 404)
    body["detail"] = body["detail"].replace(slug, "<slug>")
    return body


def twin_count(server: Server) -> int:
    with server.admin as admin:
        r = admin.get("/api/v1/twins", params={"limit": 500})
    assert r.status_code == 200, r.text
    assert r.json()["next_cursor"] is None
    return len(r.json()["items"])


def parse_time(human: str) -> float:
    return datetime.fromisoformat(human.replace("Z", "+00:00")).timestamp()


def wait_for_clock_past(human: str) -> None:
    """Spin (at most a few ms) until the wall clock is past a millisecond timestamp the server
    reported, so a later write is guaranteed a later time. Server and tests share the clock."""
    deadline = parse_time(human) + 0.002
    while time.time() < deadline:
        pass


def unhandled_errors(server: Server) -> int:
    return server.log().count("unhandled error")


def last_error(server: Server) -> str:
    """The last exception line the server logged, for a short failure message."""
    lines = [ln for ln in server.log().splitlines() if "Error" in ln and len(ln) < 300]
    return lines[-1] if lines else "(no error line found)"


def poll_until(check: Callable[[], Any], what: str, timeout_s: float = 20.0) -> Any:
    """Poll `check` (which reads the real state) until it gives a true value; return it."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        value = check()
        if value:
            return value
        time.sleep(0.05)  # polling the real state, not waiting for it to happen
    raise AssertionError(f"timed out waiting for {what}")
