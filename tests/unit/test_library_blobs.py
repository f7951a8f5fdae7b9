"""The library's blob store on files: a blob is adopted from a temporary file by a rename,
kept once per content under root/ab/cdef..., read-only, read back in chunks."""

from __future__ import annotations

import hashlib
import os
import stat
import time
from pathlib import Path

import pytest

from twinlink.domain.errors import InvalidInputError, NotFoundError
from twinlink.library.blobs import FileBlobStore


def _written(blobs: FileBlobStore, data: bytes) -> tuple[Path, str]:
    fd, temp = blobs.temp_file()
    with os.fdopen(fd, "wb") as out:
        out.write(data)
    return temp, hashlib.sha256(data).hexdigest()


async def test_a_temp_file_is_adopted_as_a_read_only_blob_by_its_digest(tmp_path: Path) -> None:
    blobs = FileBlobStore(tmp_path / "blobs")
    temp, sha = _written(blobs, b"hello")
    assert temp.parent == blobs.temp_dir  # same file system: adopting is a rename

    await blobs.adopt(temp, sha)

    path = await blobs.local_path(sha)
    assert path == tmp_path / "blobs" / sha[:2] / sha[2:]
    assert path.read_bytes() == b"hello"
    assert stat.S_IMODE(path.stat().st_mode) == 0o444
    assert not temp.exists()
    assert await blobs.exists(sha)


async def test_the_same_bytes_again_keep_the_blob_and_leave_no_temp(tmp_path: Path) -> None:
    blobs = FileBlobStore(tmp_path)
    first, sha = _written(blobs, b"same")
    await blobs.adopt(first, sha)
    inode = (await blobs.local_path(sha)).stat().st_ino

    second, _ = _written(blobs, b"same")
    await blobs.adopt(second, sha)

    assert (await blobs.local_path(sha)).stat().st_ino == inode
    assert list(blobs.temp_dir.iterdir()) == []


async def test_a_blob_is_read_in_chunks(tmp_path: Path) -> None:
    blobs = FileBlobStore(tmp_path)
    data = os.urandom(10_000)
    temp, sha = _written(blobs, data)
    await blobs.adopt(temp, sha)

    chunks = [chunk async for chunk in blobs.read(sha, chunk=4096)]

    assert [len(c) for c in chunks] == [4096, 4096, 1808]
    assert b"".join(chunks) == data


async def test_a_deleted_blob_is_gone_and_asking_for_it_is_not_found(tmp_path: Path) -> None:
    blobs = FileBlobStore(tmp_path)
    temp, sha = _written(blobs, b"short-lived")
    await blobs.adopt(temp, sha)

    await blobs.delete(sha)
    await blobs.delete(sha)  # deleting what is gone is no error

    assert not await blobs.exists(sha)
    with pytest.raises(NotFoundError, match=sha):
        await blobs.local_path(sha)
    with pytest.raises(NotFoundError):
        [chunk async for chunk in blobs.read(sha)]


@pytest.mark.parametrize("bad", ["", "../../etc/passwd", "AB" * 32, "a" * 63, "a" * 64 + "/x"])
async def test_a_digest_that_is_not_sha256_hex_never_becomes_a_path(
    tmp_path: Path, bad: str
) -> None:
    blobs = FileBlobStore(tmp_path)
    with pytest.raises(InvalidInputError, match="not a SHA-256"):
        await blobs.exists(bad)


def test_stale_temps_are_removed_and_fresh_ones_kept(tmp_path: Path) -> None:
    blobs = FileBlobStore(tmp_path)
    assert blobs.remove_stale_temps() == 0  # no temp folder yet
    stale, _ = _written(blobs, b"left by a crash")
    fresh, _ = _written(blobs, b"an upload running now")
    old = time.time() - 2 * 24 * 3600
    os.utime(stale, (old, old))

    assert blobs.remove_stale_temps() == 1

    assert not stale.exists()
    assert fresh.exists()
