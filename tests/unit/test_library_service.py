"""LibraryService on a real SQLite store and blob folder: resolve's lookup order and refs,
rights per scope, pushes (same content, tags, asset.yaml, meta), holds, and blobs swept when
no version lists them any more."""

from __future__ import annotations

import hashlib
import io
import tarfile
from collections.abc import AsyncIterator
from pathlib import Path
from typing import Any

import pytest

from tests.unit._storage import Stores
from tests.unit._storage import stores as stores
from twinlink.auth.rights import ANONYMOUS, Principal
from twinlink.domain.errors import (
    ConflictError,
    ForbiddenError,
    InvalidInputError,
    NotFoundError,
    PayloadTooLargeError,
)
from twinlink.domain.records import User
from twinlink.library.blobs import FileBlobStore
from twinlink.library.rights import LibraryRights
from twinlink.library.service import LibraryService


def _who(name: str, *groups: str, admin: bool = False) -> Principal:
    return Principal(User(id=hash(name) % 1000, username=name, is_admin=admin,
                          groups=list(groups), created_ns=0))  # fmt: skip


ADMIN = _who("root", admin=True)
ALICE = _who("alice", "ntnu", "zeta")
BOB = _who("bob", "ntnu")
CURATOR = _who("carol", "curators")


async def _body(data: bytes) -> AsyncIterator[bytes]:
    for i in range(0, len(data), 7):
        yield data[i : i + 7]


def _tar(files: dict[str, bytes]) -> bytes:
    out = io.BytesIO()
    with tarfile.open(fileobj=out, mode="w") as tar:
        for path, data in files.items():
            info = tarfile.TarInfo(path)
            info.size = len(data)
            tar.addfile(info, io.BytesIO(data))
    return out.getvalue()


@pytest.fixture
def library(stores: Stores, tmp_path: Path) -> LibraryService:
    blobs = FileBlobStore(tmp_path / "blobs")
    return LibraryService(stores.metadata, blobs, 1 << 20, LibraryRights("curators", "admins"))


async def _push(
    lib: LibraryService, who: Principal, scope: str, kind: str, name: str, text: str, **kw: Any
) -> Any:
    return await lib.push(
        who, scope, kind, name, _body(text.encode()), "file", filename="a.txt", **kw
    )


async def test_an_unscoped_ref_is_looked_up_in_own_space_then_groups_then_common(
    library: LibraryService,
) -> None:
    await _push(library, ADMIN, "common", "data", "d", "common")
    await _push(library, ADMIN, "group:zeta", "data", "d", "zeta")
    await _push(library, BOB, "group:ntnu", "data", "d", "ntnu")

    async def text_for(who: Principal, ref: str) -> str:
        resolved = await library.resolve(who, ref)
        return await library.read_text(resolved, "a.txt")

    assert await text_for(ALICE, "lib:data/d") == "ntnu"  # groups sorted: ntnu before zeta
    assert await text_for(CURATOR, "lib:data/d") == "common"
    await _push(library, ALICE, "me", "data", "d", "mine")
    assert await text_for(ALICE, "lib:data/d") == "mine"
    assert await text_for(BOB, "lib:data/d") == "ntnu"  # alice's own space is hers alone
    assert await text_for(ALICE, "lib:common/data/d") == "common"
    with pytest.raises(InvalidInputError, match="kind"):
        await library.resolve(ALICE, "lib:d")
    assert (await library.resolve(ALICE, "d", kind="data")).asset.scope == "user:alice"
    with pytest.raises(InvalidInputError, match="models"):
        await library.resolve(ALICE, "lib:data/d", kind="models")


async def test_refs_by_tag_digest_prefix_and_path(library: LibraryService) -> None:
    first = await _push(library, ALICE, "me", "models", "m", "one", tags=["1.0", "latest"])
    second = await _push(library, ALICE, "me", "models", "m", "two")
    d1, d2 = first.version.digest, second.version.digest

    assert (await library.resolve(ALICE, "lib:models/m")).version.digest == d2
    assert (await library.resolve(ALICE, "lib:models/m@1.0")).version.digest == d1
    assert (await library.resolve(ALICE, f"lib:models/m@{d1}")).version.digest == d1
    resolved = await library.resolve(ALICE, f"lib:me/models/m@{d1[:19]}#a.txt")
    assert resolved.version.digest == d1 and resolved.path == "a.txt"
    assert resolved.pinned == f"lib:user:alice/models/m@{d1}#a.txt"
    again = await library.resolve(ALICE, resolved.pinned)
    assert again.version.digest == d1 and again.asset.scope == "user:alice"
    path = await library.file_path(resolved)
    assert hashlib.sha256(path.read_bytes()).hexdigest() == resolved.version.files[0].sha256

    with pytest.raises(NotFoundError, match=r"no version 2\.0 \(its tags: 1\.0, latest\)"):
        await library.resolve(ALICE, "lib:models/m@2.0")
    with pytest.raises(NotFoundError, match=r"no file 'b\.txt'.*a\.txt"):
        await library.resolve(ALICE, "lib:models/m#b.txt")
    with pytest.raises(InvalidInputError, match="not a digest"):
        await library.resolve(ALICE, "lib:models/m@sha256:abc")
    with pytest.raises(NotFoundError):
        await library.resolve(ALICE, "lib:models/m@sha256:" + "0" * 12)
    for bad in ("lib:models/M", "lib:a/b/c/d", "lib:toys/x", "lib:models/m@", "lib:models/m#"):
        with pytest.raises(InvalidInputError, match="not a library reference"):
            await library.resolve(ALICE, bad)


async def test_a_private_asset_reads_as_missing_and_common_needs_a_curator(
    library: LibraryService,
) -> None:
    await _push(library, ALICE, "me", "data", "secret", "x")
    with pytest.raises(NotFoundError):
        await library.resolve(BOB, "lib:user:alice/data/secret")
    with pytest.raises(NotFoundError):  # the same answer as for nothing at all
        await library.resolve(BOB, "lib:user:alice/data/nothing")
    with pytest.raises(NotFoundError, match="sign in"):
        await library.resolve(ANONYMOUS, "lib:data/secret")
    with pytest.raises(NotFoundError):
        await library.resolve(ANONYMOUS, "lib:common/data/secret")
    with pytest.raises(NotFoundError):
        await _push(library, BOB, "user:alice", "data", "secret", "y")
    with pytest.raises(ForbiddenError, match="curators"):
        await _push(library, ALICE, "common", "data", "c", "y")
    with pytest.raises(NotFoundError):
        await _push(library, ALICE, "group:other", "data", "c", "y")
    await _push(library, CURATOR, "common", "data", "c", "y")
    await _push(library, BOB, "group:ntnu", "data", "g", "y")  # members write their group
    assert (await library.resolve(ALICE, "lib:group:ntnu/data/g")).asset.created_by == "bob"
    assert (await library.resolve(ADMIN, "lib:user:alice/data/secret")).asset.name == "secret"


async def test_pushing_the_same_content_again_makes_no_version_but_sets_tags(
    library: LibraryService,
) -> None:
    first = await _push(library, ALICE, "me", "data", "d", "same")
    again = await _push(library, ALICE, "me", "data", "d", "same", tags=["1.0"])
    assert first.created and not again.created
    assert again.version.digest == first.version.digest
    assert again.asset.tags == {"1.0": first.version.digest, "latest": first.version.digest}
    assert again.asset.versions == 1
    untagged = await _push(library, ALICE, "me", "data", "d", "other", tags=[])
    assert untagged.created and untagged.asset.tags["latest"] == first.version.digest


async def test_asset_yaml_describes_the_asset_and_meta_wins(
    library: LibraryService, tmp_path: Path
) -> None:
    tree = _tar({
        "asset.yaml": b"description: A beam\nkeywords: [fmu, beam]\nlicence: MIT\nauthor: Ann\n",
        "model/x.bin": b"\0\1",
    })  # fmt: skip
    result = await library.push(
        ALICE, "me", "models", "beam", _body(tree), "tar", meta={"author": "Bo", "note": 1}
    )
    asset = result.asset
    assert (asset.description, asset.keywords, asset.licence, asset.author) == (
        "A beam", ["fmu", "beam"], "MIT", "Bo"
    )  # fmt: skip
    assert result.version.meta == {"note": 1}
    assert [f.path for f in result.version.files] == ["asset.yaml", "model/x.bin"]
    resolved = await library.resolve(ALICE, "lib:models/beam")
    assert resolved.path is None  # several files: the whole tree
    with pytest.raises(InvalidInputError, match="several files"):
        await library.file_path(resolved)
    await library.materialize(resolved, tmp_path / "tree")
    assert (tmp_path / "tree" / "model" / "x.bin").read_bytes() == b"\0\1"

    bad = _tar({"asset.yaml": b"keywords: 3\n"})
    with pytest.raises(InvalidInputError, match="keywords must be a list"):
        await library.push(ALICE, "me", "models", "beam", _body(bad), "tar")


async def test_an_fmu_needs_an_uploader_and_a_good_one(library: LibraryService) -> None:
    pulled: list[bytes] = []

    async def counted() -> AsyncIterator[bytes]:
        for chunk in (b"z", b"ip"):
            pulled.append(chunk)
            yield chunk

    with pytest.raises(ForbiddenError, match="only admins push FMUs"):
        await library.push(ALICE, "me", "models", "x", counted(), "file", filename="x.fmu")
    assert pulled == []  # refused before the upload is read
    with pytest.raises(ForbiddenError, match="only admins push FMUs"):  # inside an archive
        await library.push(ALICE, "me", "models", "x", _body(_tar({"a/x.FMU": b"z"})), "tar")

    def refuse(path: Path) -> dict[str, Any]:
        raise InvalidInputError("not a usable FMU: no modelDescription.xml")

    library.fmu_inspector = refuse
    with pytest.raises(InvalidInputError, match=r"^x\.fmu: not a usable FMU"):
        await library.push(ADMIN, "me", "models", "x", _body(b"zip"), "file", filename="x.fmu")
    library.fmu_inspector = lambda path: {"fmiVersion": "2.0", "size": path.stat().st_size}
    done = await library.push(ADMIN, "me", "models", "x", _body(b"zip"), "file", filename="x.fmu")
    assert done.version.meta == {"fmus": {"x.fmu": {"fmiVersion": "2.0", "size": 3}}}
    # nothing of the refused pushes is left: only the blob the version lists
    assert (
        [p.name for p in library.blobs.root.rglob("*") if p.is_file()]
        == [  # type: ignore[attr-defined]
            done.version.files[0].sha256[2:]
        ]
    )


async def test_holds_refuse_deletes_and_unused_blobs_are_swept(
    library: LibraryService, stores: Stores
) -> None:
    one = await _push(library, ALICE, "me", "data", "d", "one")
    resolved = await library.resolve(ALICE, "lib:data/d")
    await library.hold("processor:1", [resolved])
    held = await stores.metadata.delete_version(one.asset.id, one.version.digest)
    assert held == ["processor:1"]
    await library.release("processor:1")
    assert await stores.metadata.delete_version(one.asset.id, one.version.digest) is None
    sha = one.version.files[0].sha256
    assert await library.blobs.exists(sha)
    assert await library.sweep([sha]) == 1
    assert not await library.blobs.exists(sha)


async def test_bad_input_is_refused_before_anything_is_kept(library: LibraryService) -> None:
    with pytest.raises(InvalidInputError, match="asset kind"):
        await _push(library, ALICE, "me", "toys", "d", "x")
    with pytest.raises(InvalidInputError, match="library scope"):
        await _push(library, ALICE, "everyone", "data", "d", "x")
    with pytest.raises(InvalidInputError, match="asset name"):
        await _push(library, ALICE, "me", "data", "D", "x")
    with pytest.raises(InvalidInputError, match="not a tag"):
        await _push(library, ALICE, "me", "data", "d", "x", tags=["-x"])
    with pytest.raises(InvalidInputError, match="upload format"):
        await library.push(ALICE, "me", "data", "d", _body(b"x"), "rar")
    with pytest.raises(PayloadTooLargeError):
        await library.push(ALICE, "me", "data", "d", _body(b"x" * (2 << 20)), "file",
                           filename="big")  # fmt: skip
    assert await library.store.list_assets(None, kind=None, text=None, limit=5, after=None) == []


async def test_a_push_whose_blob_was_swept_meanwhile_is_refused(library: LibraryService) -> None:
    real_exists = library.blobs.exists

    async def gone(sha256: str) -> bool:
        return False

    library.blobs.exists = gone  # type: ignore[method-assign]
    try:
        with pytest.raises(ConflictError, match="push again"):
            await _push(library, ALICE, "me", "data", "d", "x")
    finally:
        library.blobs.exists = real_exists  # type: ignore[method-assign]
