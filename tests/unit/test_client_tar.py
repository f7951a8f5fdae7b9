"""twinlink.client's tar streams: a folder packed chunk by chunk (read back by tarfile, exec
bits kept), and unpacking that refuses whatever could land outside the destination."""

from __future__ import annotations

import io
import os
import tarfile
from collections.abc import Iterator
from pathlib import Path

import pytest

from twinlink.client import _tar


def _folder(root: Path) -> Path:
    (root / "lifecycle").mkdir(parents=True)
    (root / "README.md").write_text("# rig\n")
    script = root / "lifecycle" / "create"
    script.write_text("#!/bin/sh\necho made\n")
    script.chmod(0o755)
    (root / "data.bin").write_bytes(os.urandom(3 * _tar.BLOCK + 7))
    (root / "empty").mkdir()
    (root / ("long-" + "x" * 120)).write_bytes(b"")  # over ustar's 100 characters: a pax header
    return root


def _chunks(data: bytes, size: int) -> Iterator[bytes]:
    for i in range(0, len(data), size):
        yield data[i : i + size]


def test_a_folder_packs_to_a_tar_that_tarfile_reads(tmp_path: Path) -> None:
    src = _folder(tmp_path / "src")
    files = _tar.folder_files(src)
    assert [name for name, _ in files] == sorted(
        ["README.md", "data.bin", "lifecycle/create", "long-" + "x" * 120]
    )
    data = b"".join(_tar.pack(files))
    with tarfile.open(fileobj=io.BytesIO(data)) as archive:
        members = {m.name: m for m in archive.getmembers()}
        assert set(members) == {name for name, _ in files}
        assert members["lifecycle/create"].mode & 0o100
        assert not members["README.md"].mode & 0o100
        extracted = archive.extractfile("data.bin")
        assert extracted is not None
        assert extracted.read() == (src / "data.bin").read_bytes()


@pytest.mark.parametrize("chunk", [1, 511, 512, 4096, 1 << 20])
def test_unpack_round_trips_whatever_the_chunking(tmp_path: Path, chunk: int) -> None:
    src = _folder(tmp_path / "src")
    data = b"".join(_tar.pack(_tar.folder_files(src)))
    dest = tmp_path / "out"
    written = _tar.unpack(_chunks(data, chunk), dest)
    assert sorted(written) == [name for name, _ in _tar.folder_files(src)]
    assert (dest / "data.bin").read_bytes() == (src / "data.bin").read_bytes()
    assert os.stat(dest / "lifecycle" / "create").st_mode & 0o100
    assert not os.stat(dest / "README.md").st_mode & 0o100


def test_a_link_in_a_folder_is_not_pushed(tmp_path: Path) -> None:
    src = _folder(tmp_path / "src")
    (src / "secret").symlink_to("/etc/passwd")
    with pytest.raises(ValueError, match="is a symbolic link"):
        _tar.folder_files(src)


def _tar_of(*members: tuple[tarfile.TarInfo, bytes]) -> bytes:
    out = io.BytesIO()
    with tarfile.open(fileobj=out, mode="w") as archive:
        for info, content in members:
            info.size = len(content)
            archive.addfile(info, io.BytesIO(content))
    return out.getvalue()


def _link(name: str, target: str, kind: bytes) -> tarfile.TarInfo:
    info = tarfile.TarInfo(name)
    info.type, info.linkname = kind, target
    return info


@pytest.mark.parametrize(
    "bad",
    [
        tarfile.TarInfo("../escape.txt"),
        tarfile.TarInfo("/etc/escape.txt"),
        tarfile.TarInfo("a/../../escape.txt"),
        tarfile.TarInfo("a\\..\\escape.txt"),
        _link("evil", "/etc/passwd", tarfile.SYMTYPE),
        _link("hard", "/etc/passwd", tarfile.LNKTYPE),
    ],
    ids=["dotdot", "absolute", "nested-dotdot", "backslash", "symlink", "hardlink"],
)
def test_unsafe_members_are_refused(tmp_path: Path, bad: tarfile.TarInfo) -> None:
    data = _tar_of((tarfile.TarInfo("ok.txt"), b"fine"), (bad, b""))
    dest = tmp_path / "out" / "inner"
    with pytest.raises(ValueError, match=r"unsafe path|not a file"):
        _tar.unpack(iter([data]), dest)
    assert not (tmp_path / "out" / "escape.txt").exists()
    assert not (dest / "evil").exists() and not (dest / "hard").exists()


def test_a_link_already_in_the_destination_is_replaced_not_written_through(
    tmp_path: Path,
) -> None:
    victim = tmp_path / "victim.txt"
    victim.write_text("keep me")
    dest = tmp_path / "out"
    dest.mkdir()
    (dest / "a.txt").symlink_to(victim)
    _tar.unpack(iter([_tar_of((tarfile.TarInfo("a.txt"), b"new"))]), dest)
    assert victim.read_text() == "keep me"
    assert (dest / "a.txt").read_bytes() == b"new" and not (dest / "a.txt").is_symlink()


def test_packing_is_streamed_a_chunk_at_a_time(tmp_path: Path) -> None:
    big = tmp_path / "big.bin"
    with big.open("wb") as f:
        f.truncate(5 * _tar.CHUNK + 3)  # sparse: no disk used
    chunks = _tar.pack([("big.bin", big)])
    header = next(chunks)
    assert len(header) % _tar.BLOCK == 0 and len(header) < 4 * _tar.BLOCK
    sizes = [len(c) for c in chunks]
    assert max(sizes) == _tar.CHUNK  # never more than a chunk of the file at once
    size = 5 * _tar.CHUNK + 3
    assert sum(sizes) == size + (_tar.BLOCK - size % _tar.BLOCK) + 2 * _tar.BLOCK  # padding, end
