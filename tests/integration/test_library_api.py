"""The library's REST API on a real server: pushes streamed in as tar, zip or one file and
fetched back as archives and files, rights per scope (a private asset is a 404, common
needs a curator), tags, held versions, FMUs checked at push, and problem+json for every
kind of bad input."""

from __future__ import annotations

import hashlib
import io
import tarfile
import zipfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest

from tests.conftest import FmuFiles, Server, start_server, stop_server
from tests.integration._util import YAML_HEADERS, assert_problem, make_user, twin_doc, unique

pytestmark = pytest.mark.integration
LIB = "/api/v1/library"
MAX_MB = 2


def library_server(data_dir: Path, **env: str) -> Server:
    return start_server(data_dir, {"TWINLINK_LIBRARY_MAX_MB": str(MAX_MB), **env})


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    srv = library_server(tmp_path_factory.mktemp("data"))
    try:
        yield srv
    finally:
        stop_server(srv)


def _tar(files: dict[str, bytes], executable: tuple[str, ...] = ()) -> bytes:
    out = io.BytesIO()
    with tarfile.open(fileobj=out, mode="w") as tar:
        for path, data in files.items():
            info = tarfile.TarInfo(path)
            info.size = len(data)
            info.mode = 0o755 if path in executable else 0o644
            tar.addfile(info, io.BytesIO(data))
    return out.getvalue()


def _zip(files: dict[str, bytes], executable: tuple[str, ...] = ()) -> bytes:
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w") as z:
        for path, data in files.items():
            info = zipfile.ZipInfo(path)
            info.external_attr = (0o100755 if path in executable else 0o100644) << 16
            z.writestr(info, data)
    return out.getvalue()


def _chunks(data: bytes) -> Iterator[bytes]:
    for i in range(0, len(data), 64 * 1024):  # a streamed body, not one Content-Length blob
        yield data[i : i + 64 * 1024]


def _push(c: httpx.Client, ref: str, body: bytes, **params: Any) -> httpx.Response:
    params.setdefault("format", "tar")
    return c.post(f"{LIB}/{ref}/versions", params=params, content=_chunks(body))


def _ok(r: httpx.Response, status: int = 200) -> Any:
    assert r.status_code == status, f"{r.request.method} {r.request.url}: {r.text[:500]}"
    return r.json() if r.content else None


def test_a_pushed_tree_comes_back_as_tar_zip_and_files(server: Server) -> None:
    name = unique("tree")
    files = {"run.sh": b"#!/bin/sh\necho hi\n", "data/values.csv": b"t,x\n0,1\n"}
    with server.admin as admin:
        pushed = _ok(_push(admin, f"me/tools/{name}", _tar(files, ("run.sh",)), tag="1.0"), 201)
        version = pushed["version"]
        assert pushed["created"] is True
        assert pushed["asset"]["ref"] == f"user:admin/tools/{name}"
        assert pushed["asset"]["latest"] == version["digest"]
        assert sorted(version["tags"]) == ["1.0", "latest"]
        assert version["files"] == [
            {"path": "data/values.csv", "sha256": hashlib.sha256(files["data/values.csv"])
             .hexdigest(), "size": 8, "executable": False},
            {"path": "run.sh", "sha256": hashlib.sha256(files["run.sh"]).hexdigest(),
             "size": 18, "executable": True},
        ]  # fmt: skip

        base = f"{LIB}/me/tools/{name}/versions/1.0"
        r = admin.get(f"{base}/archive", params={"format": "tar"})
        assert r.status_code == 200 and r.headers["content-type"] == "application/x-tar"
        assert (
            f'filename="{name}-{version["digest"][7:19]}.tar"' in r.headers["content-disposition"]
        )
        with tarfile.open(fileobj=io.BytesIO(r.content)) as tar:
            got = {m.name: tar.extractfile(m).read() for m in tar if m.isfile()}  # type: ignore[union-attr]
            assert tar.getmember("run.sh").mode & 0o100
        assert got == files
        r = admin.get(f"{base}/archive", params={"format": "zip"})
        with zipfile.ZipFile(io.BytesIO(r.content)) as z:
            assert {n: z.read(n) for n in z.namelist() if not n.endswith("/")} == files

        r = admin.get(f"{base}/files/data/values.csv")
        assert r.status_code == 200 and r.content == files["data/values.csv"]
        assert r.headers["content-type"] == "application/octet-stream"
        assert r.headers["x-content-type-options"] == "nosniff"
        assert r.headers["content-disposition"].startswith("attachment")

        # the same content again: no new version, its tags set
        again = _ok(_push(admin, f"me/tools/{name}", _tar(files, ("run.sh",)), tag="again"))
        assert again["created"] is False and again["version"]["digest"] == version["digest"]
        assert sorted(again["version"]["tags"]) == ["1.0", "again", "latest"]

        # a zip of the same files is the same version too (the digest is the content's)
        same = _ok(_push(admin, f"me/tools/{name}", _zip(files, ("run.sh",)), format="zip"))
        assert same["created"] is False and same["version"]["digest"] == version["digest"]


def test_tags_move_and_latest_follows_pushes(server: Server) -> None:
    ref = f"me/data/{unique('tags')}"
    with server.admin as admin:
        one = _ok(_push(admin, ref, b"one", format="file", filename="v.txt", tag="stable"), 201)
        two = _ok(_push(admin, ref, b"two", format="file", filename="v.txt"), 201)
        quiet = _ok(
            _push(admin, ref, b"three", format="file", filename="v.txt", latest="false"), 201
        )
        d1, d2 = one["version"]["digest"], two["version"]["digest"]
        asset = _ok(admin.get(f"{LIB}/{ref}"))
        assert asset["tags"] == {"latest": d2, "stable": d1}
        assert [v["digest"] for v in asset["versions"]] == [
            quiet["version"]["digest"], d2, d1
        ]  # fmt: skip
        assert "files" not in asset["versions"][0]

        moved = _ok(admin.put(f"{LIB}/{ref}/tags/stable", json={"version": d2[:19]}))
        assert moved["tags"]["stable"] == d2
        assert admin.get(f"{LIB}/{ref}/versions/stable/files/v.txt").content == b"two"
        assert admin.delete(f"{LIB}/{ref}/tags/stable").status_code == 204
        assert_problem(admin.delete(f"{LIB}/{ref}/tags/stable"), 404)
        assert_problem(admin.get(f"{LIB}/{ref}/versions/stable"), 404)
        assert_problem(admin.put(f"{LIB}/{ref}/tags/x", json={"version": "nope"}), 404)
        assert_problem(admin.put(f"{LIB}/{ref}/tags/-bad", json={"version": d1}), 422)

        # deleting the version `latest` is on moves it to the newest one left
        assert admin.delete(f"{LIB}/{ref}/versions/latest").status_code == 204
        assert _ok(admin.get(f"{LIB}/{ref}"))["latest"] == quiet["version"]["digest"]


def test_a_private_asset_is_a_404_to_others_and_common_needs_a_curator(server: Server) -> None:
    group = unique("g")
    alice = make_user(server, unique("alice"), groups=[group])
    bob = make_user(server, unique("bob"), groups=[group])
    eve = make_user(server, unique("eve"))
    curator = make_user(server, unique("cur"), groups=["curators"])
    name = unique("secret")
    with server.client(alice) as a, server.client(bob) as b, server.client(eve) as e:
        pushed = _ok(_push(a, f"me/data/{name}", b"x", format="file", filename="x"), 201)
        mine = pushed["asset"]["scope"]
        for path in (f"{LIB}/{mine}/data/{name}", f"{LIB}/{mine}/data/{name}/versions",
                     f"{LIB}/{mine}/data/{name}/versions/latest/files/x"):  # fmt: skip
            missing = assert_problem(b.get(path), 404)
            nothing = assert_problem(b.get(path.replace(name, name + "-nothing")), 404)
            assert missing["detail"].replace(name, "") == nothing["detail"].replace(
                name + "-nothing", ""
            )  # the same answer: the asset's existence does not leak
        assert_problem(_push(b, f"{mine}/data/{name}", b"y", format="file", filename="x"), 404)
        assert_problem(b.delete(f"{LIB}/{mine}/data/{name}"), 404)
        assert [x["name"] for x in _ok(b.get(LIB, params={"q": name}))["assets"]] == []

        problem = assert_problem(
            _push(a, f"common/data/{name}", b"y", format="file", filename="x"), 403
        )
        assert "curators" in problem["detail"]
        _ok(_push(b, f"group:{group}/data/{name}", b"g", format="file", filename="x"), 201)
        assert a.get(f"{LIB}/group:{group}/data/{name}/versions/latest/files/x").content == b"g"
        assert_problem(e.get(f"{LIB}/group:{group}/data/{name}"), 404)
    with server.client(curator) as c, server.client(eve) as e:
        _ok(_push(c, f"common/data/{name}", b"c", format="file", filename="x"), 201)
        assert e.get(f"{LIB}/common/data/{name}/versions/latest/files/x").content == b"c"
        assert_problem(e.patch(f"{LIB}/common/data/{name}", json={"author": "E"}), 403)
        changed = _ok(c.patch(f"{LIB}/common/data/{name}", json={"keywords": ["k"]}))
        assert changed["keywords"] == ["k"]


def test_blobs_no_version_lists_are_removed(server: Server) -> None:
    """(A held version's 409 is tests/integration/test_processors_libref.py's.)"""
    ref = f"me/data/{unique('blobs')}"
    shared, own = unique("shared").encode(), unique("own").encode()
    shared_sha, own_sha = hashlib.sha256(shared).hexdigest(), hashlib.sha256(own).hexdigest()
    with server.admin as admin:
        _ok(_push(admin, ref, _tar({"a": shared})), 201)
        second = _ok(_push(admin, ref, _tar({"a": shared, "b": own})), 201)
        assert {shared_sha, own_sha} <= _blob_files(server.data_dir)
        assert admin.delete(f"{LIB}/{ref}/versions/{second['version']['digest']}").status_code
        blobs = _blob_files(server.data_dir)
        assert shared_sha in blobs and own_sha not in blobs  # the first version lists `a`
        assert admin.delete(f"{LIB}/{ref}").status_code == 204
        assert shared_sha not in _blob_files(server.data_dir)
        assert_problem(admin.get(f"{LIB}/{ref}"), 404)


def test_bad_input_is_a_problem_never_a_500(server: Server) -> None:
    name = unique("bad")
    with server.admin as admin:
        good = _ok(_push(admin, f"me/data/{name}", b"x", format="file", filename="x"), 201)
        digest = good["version"]["digest"]
        cases = [
            (_push(admin, f"me/toys/{name}", b"x"), 422, "asset kind"),
            (_push(admin, f"everyone/data/{name}", b"x"), 422, "library scope"),
            (_push(admin, "me/data/Bad_Name", b"x"), 422, "asset name"),
            (_push(admin, f"me/data/{name}", b"x", format="rar"), 422, "format"),
            (_push(admin, f"me/data/{name}", b"not a tar at all"), 422, ""),
            (_push(admin, f"me/data/{name}", b"x", format="file"), 422, "filename"),
            (_push(admin, f"me/data/{name}", b"x", format="file", filename="../x"), 422, ".."),
            (_push(admin, f"me/data/{name}", b""), 422, "empty"),
            (_push(admin, f"me/data/{name}", b"x", format="file", filename="x", tag="-t"), 422,
             "tag"),
            (_push(admin, f"me/data/{name}", b"\0" * (MAX_MB * 2**20 + 1), format="file",
                   filename="big"), 413, "library_max_mb"),
            (admin.get(f"{LIB}/me/data/{name}/versions/sha256:zz"), 422, "digest"),
            (admin.get(f"{LIB}/me/data/{name}/versions/sha256:{'0' * 12}"), 404, ""),
            (admin.get(f"{LIB}/me/data/{name}/versions/{digest}/archive",
                       params={"format": "rar"}), 422, ""),
            (admin.get(f"{LIB}/me/data/{name}/versions/latest/files/nope"), 404, "x"),
            (admin.get(LIB, params={"kind": "toys"}), 422, "asset kind"),
            (admin.get(LIB, params={"scope": "nobody"}), 422, "library scope"),
            (admin.get(LIB, params={"after": "a/b"}), 422, "after"),
            (admin.get(LIB, params={"limit": 0}), 422, ""),
            (admin.patch(f"{LIB}/me/data/{name}", json={"keywords": "k"}), 422, ""),
            (admin.patch(f"{LIB}/me/data/{name}", json={"colour": "red"}), 422, ""),
            (admin.put(f"{LIB}/me/data/{name}/tags/t", json={}), 422, ""),
        ]  # fmt: skip
        for r, status, words in cases:
            body = assert_problem(r, status)
            assert words in body["detail"], (r.request.url, body)
        assert _ok(admin.get(f"{LIB}/me/data/{name}"))["version_count"] == 1
    with server.client() as anonymous:
        assert_problem(anonymous.get(LIB), 401)


def test_fmus_are_checked_at_push(server: Server, fmu_files: FmuFiles) -> None:
    name = unique("beam")
    fmu = fmu_files("tingen").read_bytes()
    user = make_user(server, unique("modeller"))
    with server.admin as admin, server.client(user) as modeller:
        forbidden = _push(modeller, f"me/models/{name}", fmu, format="file", filename="b.fmu")
        assert "only admins push FMUs" in assert_problem(forbidden, 403)["detail"]
        corrupt = fmu[: len(fmu) // 2]
        refused = assert_problem(
            _push(admin, f"me/models/{name}", corrupt, format="file", filename="beam.fmu"), 422
        )
        assert refused["detail"].startswith("beam.fmu: ")
        assert_problem(admin.get(f"{LIB}/me/models/{name}"), 404)  # nothing kept
        tree = _tar({"beam.fmu": fmu, "asset.yaml": b"description: The Tingen beam\n"})
        pushed = _ok(_push(admin, f"me/models/{name}", tree), 201)
        info = pushed["version"]["meta"]["fmus"]["beam.fmu"]
        assert info["fmi_version"] == "2.0"
        assert any(v["name"] == "theta" for v in info["variables"])
        assert pushed["asset"]["description"] == "The Tingen beam"


def _blob_files(data_dir: Path) -> set[str]:
    root = data_dir / "library" / "blobs"
    return {p.parent.name + p.name for p in root.glob("??/*") if p.is_file()}


def test_search_finds_assets_the_caller_may_read_beside_twins(server: Server) -> None:
    word = unique("gyro").replace("-", "")
    owner = make_user(server, unique("owner"))
    other = make_user(server, unique("other"))
    with server.admin as admin, server.client(owner) as mine:
        _ok(_push(admin, f"common/data/{word}-table", b"t", format="file", filename="t"), 201)
        _ok(admin.patch(f"{LIB}/common/data/{word}-table", json={"keywords": ["calibration"]}))
        _ok(_push(mine, f"me/data/{word}-private", b"p", format="file", filename="p"), 201)
        twin = f"{word} rig"
        doc = twin_doc(f"urn:{word}", name=twin, description=f"holds the {word}")
        _ok(admin.post("/api/v1/apply", content=doc, headers=YAML_HEADERS))

    def search(token: str, **params: Any) -> dict[str, Any]:
        with server.client(token) as c:
            return _ok(c.get("/api/v1/search", params={"q": word, **params}))  # type: ignore[no-any-return]

    found = search(owner)
    assert [(h["kind"], h["name"]) for h in found["hits"]] == [
        ("twin", twin),
        ("asset", f"{word}-table"),
        ("asset", f"{word}-private"),
    ]  # fmt: skip: twins first, then assets by scope (common before user:...)
    assert found["total"] == 3
    asset = found["hits"][1]
    assert (asset["ref"], asset["scope"], asset["asset_kind"], asset["slug"]) == (
        f"common/data/{word}-table", "common", "data", None
    )  # fmt: skip
    others = search(other)
    assert [h["name"] for h in others["hits"]] == [twin, f"{word}-table"]  # not owner's
    assert [h["name"] for h in search(other, keyword="calibration")["hits"]] == [f"{word}-table"]
    pages = [search(owner, limit=1, offset=i)["hits"][0]["name"] for i in range(3)]
    assert pages == [h["name"] for h in found["hits"]]
