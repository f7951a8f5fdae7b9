"""The library's tables through the LibraryStore protocol: pushes land whole, a digest pushed
again is the same version, tags move, holds refuse deletes, blob references are counted.

Runs on SQLite here and on PostgreSQL in tests/integration/test_library_store_postgres.py."""

from __future__ import annotations

import hashlib

from tests.unit._storage import Stores
from tests.unit._storage import stores as stores
from twinlink.domain.library import FileEntry, VersionRecord
from twinlink.store.library import AssetFields


def _version(*contents: bytes, meta: dict[str, object] | None = None) -> VersionRecord:
    files = [
        FileEntry(f"f{i}.txt", hashlib.sha256(c).hexdigest(), len(c))
        for i, c in enumerate(contents)
    ]
    # Any distinct digest will do: the store keeps what it is given (manifest.py computes it).
    digest = "sha256:" + hashlib.sha256(b"".join(contents) + bytes(len(contents))).hexdigest()
    return VersionRecord(0, digest, files, sum(f.size for f in files),
                         meta or {}, "alice", 0)  # fmt: skip


async def test_a_push_creates_the_asset_its_version_and_tags(stores: Stores) -> None:
    store = stores.metadata
    v1 = _version(b"one")
    asset, version, created = await store.put_version(
        "user:alice", "data", "beam", v1, ["latest", "1.0"], AssetFields(description="d"), 10
    )
    assert created
    assert (asset.scope, asset.kind, asset.name, asset.description) == (
        "user:alice", "data", "beam", "d"
    )  # fmt: skip
    assert asset.tags == {"1.0": v1.digest, "latest": v1.digest}
    assert asset.versions == 1
    assert version.files == v1.files and version.asset_id == asset.id
    assert version.created_by == "alice" and version.created_ns == 10

    again, same, created_again = await store.put_version(
        "user:alice", "data", "beam", v1, ["again"], AssetFields(), 20
    )
    assert not created_again and same.created_ns == 10  # the first push's version
    assert again.tags == {"1.0": v1.digest, "again": v1.digest, "latest": v1.digest}
    assert again.description == "d"  # fields not given are kept


async def test_tags_move_and_versions_list_newest_first(stores: Stores) -> None:
    store = stores.metadata
    v1, v2 = _version(b"one"), _version(b"two")
    asset, _, _ = await store.put_version("common", "models", "m", v1, ["latest"], AssetFields(), 1)
    await store.put_version("common", "models", "m", v2, ["latest"], AssetFields(), 2)
    assert [v.digest for v in await store.list_versions(asset.id)] == [v2.digest, v1.digest]
    await store.set_tag(asset.id, "stable", v1.digest, 3)
    got = await store.get_asset("common", "models", "m")
    assert got is not None and got.tags == {"latest": v2.digest, "stable": v1.digest}
    assert got.versions == 2
    assert await store.delete_tag(asset.id, "stable")
    assert not await store.delete_tag(asset.id, "stable")
    assert await store.find_digests(asset.id, v1.digest[:19]) == [v1.digest]
    assert await store.find_digests(asset.id, "sha256:") == sorted([v1.digest, v2.digest])


async def test_a_held_version_is_not_deleted(stores: Stores) -> None:
    store = stores.metadata
    v1, v2 = _version(b"one"), _version(b"two")
    asset, _, _ = await store.put_version("common", "data", "d", v1, ["latest"], AssetFields(), 1)
    await store.put_version("common", "data", "d", v2, ["latest"], AssetFields(), 2)
    await store.add_holds("processor:7", [(asset.id, v1.digest)])
    await store.add_holds("processor:7", [(asset.id, v1.digest)])  # twice is no error
    await store.add_holds("deployment:1", [(asset.id, v1.digest)])
    assert await store.delete_version(asset.id, v1.digest) == ["deployment:1", "processor:7"]
    assert await store.delete_asset(asset.id) == ["deployment:1", "processor:7"]
    assert await store.delete_version(asset.id, v2.digest) is None  # not held: gone, tags too
    got = await store.get_asset("common", "data", "d")
    assert got is not None and got.tags == {} and got.versions == 1

    assert await store.release_holds("processor:7") == 1
    assert await store.list_holders(asset.id) == ["deployment:1"]
    await store.release_holds("deployment:1")
    assert await store.delete_asset(asset.id) is None
    assert await store.get_asset("common", "data", "d") is None


async def test_blob_references_count_every_asset(stores: Stores) -> None:
    store = stores.metadata
    shared, own = _version(b"shared"), _version(b"shared", b"own")
    a, _, _ = await store.put_version("common", "data", "a", shared, [], AssetFields(), 1)
    b, _, _ = await store.put_version("common", "data", "b", own, [], AssetFields(), 1)
    hashes = {f.sha256 for f in own.files}
    assert await store.referenced_blobs(hashes | {"0" * 64}) == hashes
    await store.delete_asset(b.id)
    assert await store.referenced_blobs(hashes) == {shared.files[0].sha256}
    await store.delete_asset(a.id)
    assert await store.referenced_blobs(hashes) == set()


async def test_listing_filters_by_scope_kind_and_text(stores: Stores) -> None:
    store = stores.metadata
    v = _version(b"x")
    for scope, kind, name, fields in [
        ("common", "models", "beam", AssetFields(keywords=["fmu", "Tingen"])),
        ("common", "data", "runs_50%", AssetFields(description="fifty")),
        ("user:bob", "models", "secret", AssetFields(description="tingen copy")),
        ("group:ntnu", "tools", "plot", AssetFields()),
    ]:
        await store.put_version(scope, kind, name, v, ["latest"], fields, 1)

    def refs(assets: list[object]) -> list[str]:
        return [a.ref for a in assets]  # type: ignore[attr-defined]

    everything = await store.list_assets(None, kind=None, text=None, limit=10, after=None)
    assert refs(everything) == [
        "common/data/runs_50%", "common/models/beam", "group:ntnu/tools/plot",
        "user:bob/models/secret",
    ]  # fmt: skip
    mine = await store.list_assets(
        ["common", "group:ntnu"], kind=None, text=None, limit=10, after=None
    )
    assert refs(mine) == ["common/data/runs_50%", "common/models/beam", "group:ntnu/tools/plot"]
    found = await store.list_assets(None, kind="models", text="TINGEN", limit=10, after=None)
    assert refs(found) == ["common/models/beam", "user:bob/models/secret"]
    assert refs(await store.list_assets(None, kind=None, text="50%", limit=10, after=None)) == [
        "common/data/runs_50%"
    ]
    assert refs(await store.list_assets(None, kind=None, text="_", limit=10, after=None)) == [
        "common/data/runs_50%"
    ]
    page = await store.list_assets(
        None, kind=None, text=None, limit=2, after=("common", "models", "beam")
    )
    assert refs(page) == ["group:ntnu/tools/plot", "user:bob/models/secret"]
    assert await store.list_assets([], kind=None, text=None, limit=10, after=None) == []


async def test_update_asset_changes_only_the_fields_given(stores: Stores) -> None:
    store = stores.metadata
    asset, _, _ = await store.put_version(
        "common", "data", "d", _version(b"x"), [], AssetFields(author="Ann", licence="MIT"), 1
    )
    updated = await store.update_asset(asset.id, AssetFields(keywords=["a", "b"]), 5)
    assert updated is not None
    assert (updated.author, updated.licence, updated.keywords) == ("Ann", "MIT", ["a", "b"])
    assert updated.updated_ns == 5
    assert await store.update_asset(asset.id + 100, AssetFields(author="x"), 6) is None


async def test_search_needs_every_term_and_ranks_names_first(stores: Stores) -> None:
    store = stores.metadata
    v = _version(b"x")
    for scope, name, fields in [
        ("common", "beam-model", AssetFields(description="a cantilever", keywords=["FMU"])),
        ("common", "crane", AssetFields(description="the beam of a crane model")),
        ("user:bob", "beam-secret", AssetFields(description="model")),
        ("common", "other", AssetFields(description="nothing to see")),
    ]:
        await store.put_version(scope, "models", name, v, [], fields, 1)

    async def names(scopes: list[str] | None, terms: list[str], **kw: object) -> list[str]:
        kw.setdefault("limit", 10)
        kw.setdefault("offset", 0)
        kw.setdefault("keyword", None)
        found, total = await store.search_assets(scopes, terms, **kw)  # type: ignore[arg-type]
        assert total >= len(found)
        return [a.name for a in found]

    # every term in the name first, then by scope, kind, name
    assert await names(None, ["beam", "model"]) == ["beam-model", "crane", "beam-secret"]
    assert await names(["common"], ["beam", "model"]) == ["beam-model", "crane"]
    assert await names(["common"], ["beam"], keyword="FMU") == ["beam-model"]
    assert await names(["common"], ["beam"], keyword="fmu") == []  # keywords match whole
    assert await names(["common"], []) == ["beam-model", "crane", "other"]
    assert await names(["common"], ["beam", "model"], limit=1, offset=1) == ["crane"]
    assert await store.search_assets([], ["beam"], keyword=None, limit=5, offset=0) == ([], 0)
    assert (await store.search_assets(None, ["beam"], keyword=None, limit=0, offset=0))[1] == 3
