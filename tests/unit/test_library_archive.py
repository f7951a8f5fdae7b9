"""Library versions in and out: archives received into blobs (hostile ones refused, naming the
entry, leaving nothing behind), sent back as the same files, materialized as a tree; the
version digest as the design defines it."""

from __future__ import annotations

import gzip
import hashlib
import io
import os
import stat
import tarfile
import tracemalloc
import warnings
import zipfile
from collections.abc import AsyncIterator
from pathlib import Path

import pytest

from twinlink.domain.errors import InvalidInputError, PayloadTooLargeError
from twinlink.library.archive import (
    FileEntry,
    Format,
    Limits,
    materialize,
    receive,
    send,
    version_digest,
)
from twinlink.library.blobs import FileBlobStore
from twinlink.library.pack import SendFormat

LIMITS = Limits(max_bytes=1 << 20, max_files=20)
TREE = {"run.sh": (b"#!/bin/sh\necho hi\n", True), "model/beam.fmu": (b"PK fmu", False)}


async def _body(data: bytes, chunk: int = 7000) -> AsyncIterator[bytes]:
    for at in range(0, len(data), chunk):
        yield data[at : at + chunk]


async def _join(chunks: AsyncIterator[bytes]) -> bytes:
    return b"".join([chunk async for chunk in chunks])


def _tar(members: list[tuple[tarfile.TarInfo, bytes]], gz: bool = False) -> bytes:
    out = io.BytesIO()
    with tarfile.open(fileobj=out, mode="w:gz" if gz else "w") as tar:
        for info, data in members:
            info.size = len(data) if info.isreg() else 0
            tar.addfile(info, io.BytesIO(data) if info.isreg() else None)
    return out.getvalue()


def _file(name: str, data: bytes = b"x", mode: int = 0o644) -> tuple[tarfile.TarInfo, bytes]:
    info = tarfile.TarInfo(name)
    info.mode = mode
    return info, data


def _special(name: str, kind: bytes, link: str = "") -> tuple[tarfile.TarInfo, bytes]:
    info = tarfile.TarInfo(name)
    info.type = kind
    info.linkname = link
    return info, b""


def _zip(entries: list[tuple[str, bytes, int]]) -> bytes:
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, data, mode in entries:
            info = zipfile.ZipInfo(name)
            info.create_system = 3
            info.external_attr = mode << 16
            info.compress_type = zipfile.ZIP_DEFLATED
            archive.writestr(info, data)
    return out.getvalue()


def _kept(root: Path) -> list[Path]:
    """Every file under the blob store: blobs and temporary files alike."""
    return [p for p in root.rglob("*") if p.is_file()]


def _tree_tar(prefix: str = "") -> bytes:
    return _tar(
        [_file(prefix + path, data, 0o755 if x else 0o644) for path, (data, x) in TREE.items()]
    )


# -- the digest --------------------------------------------------------------------------------


def test_the_version_digest_is_sha256_of_the_canonical_manifest() -> None:
    a = FileEntry("b.txt", "1" * 64, 3, executable=True)
    b = FileEntry("a.txt", "2" * 64, 10)
    canonical = f"a.txt\0{'2' * 64}\x0010\x000\nb.txt\0{'1' * 64}\x003\x001\n".encode()

    assert version_digest([a, b]) == "sha256:" + hashlib.sha256(canonical).hexdigest()
    assert version_digest([b, a]) == version_digest([a, b])  # the order given does not count
    assert version_digest([a, FileEntry("a.txt", "2" * 64, 10, executable=True)]) != (
        version_digest([a, b])
    )


# -- received ----------------------------------------------------------------------------------


async def test_a_plain_file_is_one_entry_named_by_filename(tmp_path: Path) -> None:
    blobs = FileBlobStore(tmp_path)
    data = os.urandom(50_000)

    files = await receive(_body(data), "file", blobs, LIMITS, filename="data.csv")

    sha = hashlib.sha256(data).hexdigest()
    assert files == [FileEntry("data.csv", sha, len(data))]
    assert (await blobs.local_path(sha)).read_bytes() == data
    assert list(blobs.temp_dir.iterdir()) == []


async def test_a_plain_file_needs_a_usable_name(tmp_path: Path) -> None:
    blobs = FileBlobStore(tmp_path)
    with pytest.raises(InvalidInputError, match=r"filename="):
        await receive(_body(b"x"), "file", blobs, LIMITS)
    with pytest.raises(InvalidInputError, match=r"goes up"):
        await receive(_body(b"x"), "file", blobs, LIMITS, filename="../x")
    assert _kept(tmp_path) == []


@pytest.mark.parametrize("prefix", ["", "./"])
async def test_a_tar_becomes_its_files_with_exec_bits(tmp_path: Path, prefix: str) -> None:
    blobs = FileBlobStore(tmp_path)
    folders = [_special(prefix or ".", tarfile.DIRTYPE), _special(prefix + "model/", b"5")]
    files_ = [_file(prefix + p, d, 0o755 if x else 0o644) for p, (d, x) in TREE.items()]
    body = _tar([*folders, *files_])

    files = await receive(_body(body), "tar", blobs, LIMITS)

    assert [(f.path, f.size, f.executable) for f in files] == [
        ("model/beam.fmu", 6, False),
        ("run.sh", len(TREE["run.sh"][0]), True),
    ]
    for f in files:
        assert (await blobs.local_path(f.sha256)).read_bytes() == TREE[f.path][0]
    assert list(blobs.temp_dir.iterdir()) == []  # the spooled upload is gone too


async def test_a_single_top_level_folder_is_kept(tmp_path: Path) -> None:
    files = await receive(_body(_tree_tar("rig/")), "tar", FileBlobStore(tmp_path), LIMITS)
    assert [f.path for f in files] == ["rig/model/beam.fmu", "rig/run.sh"]


async def test_a_zip_becomes_its_files_with_exec_bits(tmp_path: Path) -> None:
    blobs = FileBlobStore(tmp_path)
    body = _zip(
        [
            ("model/", b"", stat.S_IFDIR | 0o755),
            ("model/beam.fmu", b"PK fmu", stat.S_IFREG | 0o644),
            ("run.sh", TREE["run.sh"][0], stat.S_IFREG | 0o755),
        ]
    )

    files = await receive(_body(body), "zip", blobs, LIMITS)

    assert [(f.path, f.executable) for f in files] == [("model/beam.fmu", False), ("run.sh", True)]
    assert (await blobs.local_path(files[1].sha256)).read_bytes() == TREE["run.sh"][0]


# -- refused -----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("name", "says"),
    [
        ("../x", "goes up"),
        ("/etc/x", "absolute"),
        ("a/../../x", "goes up"),
        ("a\\..\\x", "backslash"),
        ("C:/x", "absolute"),
        ("a//b", "empty"),
        ("a/line\nbreak", "control character"),
    ],
)
@pytest.mark.parametrize("fmt", ["tar", "tgz", "zip"])
async def test_a_path_leaving_the_root_is_refused_naming_it(
    tmp_path: Path, fmt: Format, name: str, says: str
) -> None:
    good = [("ok.txt", b"fine", stat.S_IFREG | 0o644)]
    if fmt == "zip":
        body = _zip([*good, (name, b"evil", stat.S_IFREG | 0o644)])
    else:
        body = _tar([_file("ok.txt", b"fine"), _file(name, b"evil")], gz=fmt == "tgz")

    with pytest.raises(InvalidInputError, match=says) as err:
        await receive(_body(body), fmt, FileBlobStore(tmp_path), LIMITS)

    assert repr(name) in str(err.value)
    assert _kept(tmp_path) == []  # not even the good file's blob


@pytest.mark.parametrize(
    ("member", "says"),
    [
        (_special("link", tarfile.SYMTYPE, "/etc/passwd"), "symbolic link"),
        (_special("hard", tarfile.LNKTYPE, "ok.txt"), "hard link"),
        (_special("dev", tarfile.CHRTYPE), "not a regular file"),
        (_special("disk", tarfile.BLKTYPE), "not a regular file"),
        (_special("pipe", tarfile.FIFOTYPE), "not a regular file"),
    ],
)
async def test_a_tar_entry_that_is_not_a_regular_file_is_refused(
    tmp_path: Path, member: tuple[tarfile.TarInfo, bytes], says: str
) -> None:
    body = _tar([_file("ok.txt"), member])
    with pytest.raises(InvalidInputError, match=says) as err:
        await receive(_body(body), "tar", FileBlobStore(tmp_path), LIMITS)
    assert repr(member[0].name) in str(err.value)
    assert _kept(tmp_path) == []


@pytest.mark.parametrize(
    ("mode", "says"),
    [(stat.S_IFLNK | 0o777, "symbolic link"), (stat.S_IFIFO | 0o644, "not a regular file")],
)
async def test_a_zip_entry_that_is_not_a_regular_file_is_refused(
    tmp_path: Path, mode: int, says: str
) -> None:
    body = _zip([("ok.txt", b"x", stat.S_IFREG | 0o644), ("link", b"/etc/passwd", mode)])
    with pytest.raises(InvalidInputError, match=says) as err:
        await receive(_body(body), "zip", FileBlobStore(tmp_path), LIMITS)
    assert "'link'" in str(err.value)
    assert _kept(tmp_path) == []


@pytest.mark.parametrize(
    ("names", "says"),
    [
        (["a.txt", "a.txt"], "twice"),
        (["a.txt", "./a.txt"], "twice"),
        (["a", "a/b"], "is a file in the archive"),
    ],
)
@pytest.mark.parametrize("fmt", ["tar", "zip"])
async def test_paths_that_cannot_both_be_written_are_refused(
    tmp_path: Path, fmt: Format, names: list[str], says: str
) -> None:
    if fmt == "zip":
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # zipfile warns of a duplicate name, and writes it
            body = _zip([(n, b"x", stat.S_IFREG | 0o644) for n in names])
    else:
        body = _tar([_file(n) for n in names])
    with pytest.raises(InvalidInputError, match=says):
        await receive(_body(body), fmt, FileBlobStore(tmp_path), LIMITS)
    assert _kept(tmp_path) == []


async def test_a_body_over_the_limit_is_refused_without_reading_the_rest(
    tmp_path: Path,
) -> None:
    pulled = 0

    async def endless() -> AsyncIterator[bytes]:
        nonlocal pulled
        while True:
            pulled += 1
            yield b"\0" * 65536

    with pytest.raises(PayloadTooLargeError, match=r"1 MB \(library_max_mb\)"):
        await receive(endless(), "tar", FileBlobStore(tmp_path), LIMITS)

    assert pulled == LIMITS.max_bytes // 65536 + 1  # the first chunk past the limit, no more
    assert _kept(tmp_path) == []


async def test_a_zip_bomb_is_refused_on_the_bytes_it_unpacks(tmp_path: Path) -> None:
    limits = Limits(max_bytes=1 << 20)
    body = _zip([("ok.txt", b"fine", stat.S_IFREG | 0o644), ("zeros", bytes(8 << 20), 0)])
    assert len(body) < 20_000  # 8 MB of zeros in a few kB

    with pytest.raises(PayloadTooLargeError, match=r"'zeros'.*more than the library's limit"):
        await receive(_body(body), "zip", FileBlobStore(tmp_path), limits)
    assert _kept(tmp_path) == []


async def test_a_zip_whose_headers_understate_the_size_is_refused_on_real_bytes(
    tmp_path: Path,
) -> None:
    # The central directory says 10 bytes; the entry inflates to 4 MB: zipfile stops at the
    # stated size (a CRC mismatch), the library never trusts it either way.
    body = bytearray(_zip([("zeros", bytes(4 << 20), stat.S_IFREG | 0o644)]))
    at = body.rfind(b"PK\x01\x02")
    body[at + 24 : at + 28] = (10).to_bytes(4, "little")  # the uncompressed size

    with pytest.raises(InvalidInputError):
        await receive(_body(bytes(body)), "zip", FileBlobStore(tmp_path), Limits(1 << 20))
    assert _kept(tmp_path) == []


async def test_a_gzip_bomb_is_refused_on_the_bytes_it_unpacks(tmp_path: Path) -> None:
    body = _tar([_file("zeros", bytes(8 << 20))], gz=True)
    assert len(body) < 100_000

    with pytest.raises(PayloadTooLargeError, match="'zeros'"):
        await receive(_body(body), "tgz", FileBlobStore(tmp_path), Limits(1 << 20))
    assert _kept(tmp_path) == []


async def test_a_tar_header_too_big_to_read_is_refused(tmp_path: Path) -> None:
    info, _ = _file("big-header")
    info.pax_headers = {"comment": "x" * (2 << 20)}  # tarfile would read it whole
    body = _tar([(info, b"x")], gz=True)

    with pytest.raises(PayloadTooLargeError, match="tar header is over 1 MB"):
        await receive(_body(body), "tgz", FileBlobStore(tmp_path), Limits(8 << 20))
    assert _kept(tmp_path) == []


@pytest.mark.parametrize("fmt", ["tar", "zip"])
async def test_too_many_files_are_refused(tmp_path: Path, fmt: Format) -> None:
    names = [f"f{n}" for n in range(LIMITS.max_files + 1)]
    if fmt == "zip":
        body = _zip([(n, b"x", stat.S_IFREG | 0o644) for n in names])
    else:
        body = _tar([_file(n) for n in names])
    with pytest.raises(InvalidInputError, match="more than 20 entries"):
        await receive(_body(body), fmt, FileBlobStore(tmp_path), LIMITS)
    assert _kept(tmp_path) == []


@pytest.mark.parametrize(
    ("fmt", "body", "says"),
    [
        ("tar", b"not an archive" * 100, "not a readable tar archive"),
        ("tar", gzip.compress(b"x" * 1000), "format=tgz"),
        ("tgz", b"not gzip" * 100, "not a readable tgz archive"),
        ("zip", b"not a zip" * 100, "not a readable zip archive"),
        ("tar", b"", "empty"),
        ("rar", b"x", "unknown format"),
    ],
)
async def test_a_body_that_is_not_what_it_says_is_refused(
    tmp_path: Path, fmt: Format, body: bytes, says: str
) -> None:
    with pytest.raises(InvalidInputError, match=says):
        await receive(_body(body), fmt, FileBlobStore(tmp_path), LIMITS)
    assert _kept(tmp_path) == []


async def test_an_archive_without_files_is_refused(tmp_path: Path) -> None:
    body = _tar([_special("empty/", tarfile.DIRTYPE)])
    with pytest.raises(InvalidInputError, match="holds no files"):
        await receive(_body(body), "tar", FileBlobStore(tmp_path), LIMITS)
    assert _kept(tmp_path) == []


# -- sent and materialized ---------------------------------------------------------------------


def _unpacked(fmt: str, data: bytes) -> dict[str, tuple[bytes, bool]]:
    """What a standard reader finds in an archive: path -> (bytes, executable)."""
    if fmt == "zip":
        with zipfile.ZipFile(io.BytesIO(data)) as archive:
            return {
                i.filename: (archive.read(i), bool(i.external_attr >> 16 & 0o100))
                for i in archive.infolist()
            }
    with tarfile.open(fileobj=io.BytesIO(data), mode="r:*") as tar:
        found = {}
        for member in tar:
            source = tar.extractfile(member)
            assert source is not None
            found[member.name] = (source.read(), bool(member.mode & 0o100))
        return found


@pytest.mark.parametrize("into", ["tar", "tgz", "zip"])
@pytest.mark.parametrize("out", ["tar", "tgz", "zip"])
async def test_an_archive_round_trips_to_the_same_files_and_digest(
    tmp_path: Path, into: Format, out: SendFormat
) -> None:
    blobs = FileBlobStore(tmp_path)
    tree = {**TREE, "data/big.bin": (os.urandom(3 << 20), False), "empty.txt": (b"", False)}
    if into == "zip":
        modes = {p: stat.S_IFREG | (0o755 if x else 0o644) for p, (_, x) in tree.items()}
        body = _zip([(p, d, modes[p]) for p, (d, _) in tree.items()])
    else:
        body = _tar(
            [_file(p, d, 0o755 if x else 0o644) for p, (d, x) in tree.items()], gz=into == "tgz"
        )
    files = await receive(_body(body), into, blobs, Limits(8 << 20))

    sent = await _join(send(files, blobs, out))

    assert _unpacked(out, sent) == tree
    again = await receive(_body(sent, chunk=1 << 16), out, blobs, Limits(8 << 20))
    assert again == files
    assert version_digest(again) == version_digest(files)
    assert await _join(send(again, blobs, out)) == sent  # the same version, the same bytes


async def test_sending_an_unknown_format_is_refused_before_streaming(tmp_path: Path) -> None:
    with pytest.raises(InvalidInputError, match="tar, tgz or zip"):
        send([], FileBlobStore(tmp_path), "rar")  # type: ignore[arg-type]


async def test_a_client_that_stops_reading_stops_the_writer(tmp_path: Path) -> None:
    blobs = FileBlobStore(tmp_path)
    files = await receive(_body(os.urandom(12 << 20)), "file", blobs, Limits(16 << 20), "x")
    stream = send(files, blobs, "zip")

    first = await anext(stream)
    await stream.aclose()

    assert len(first) >= 1 << 20  # the writer's thread is gone: the hygiene check says so


async def test_a_version_is_materialized_as_its_tree(tmp_path: Path) -> None:
    blobs = FileBlobStore(tmp_path / "blobs")
    files = await receive(_body(_tree_tar()), "tar", blobs, LIMITS)
    dest = tmp_path / "work" / "assets" / "rig"

    await materialize(files, blobs, dest)

    found = sorted(str(p.relative_to(dest)) for p in dest.rglob("*") if p.is_file())
    assert found == ["model/beam.fmu", "run.sh"]
    fmu, script = dest / "model/beam.fmu", dest / "run.sh"
    assert fmu.read_bytes() == TREE["model/beam.fmu"][0]
    # a hard link to the read-only blob; the executable a copy of its own, 0o755
    assert fmu.stat().st_ino == (await blobs.local_path(files[0].sha256)).stat().st_ino
    assert stat.S_IMODE(fmu.stat().st_mode) == 0o444
    assert stat.S_IMODE(script.stat().st_mode) == 0o755
    assert script.stat().st_ino != (await blobs.local_path(files[1].sha256)).stat().st_ino


async def test_a_version_is_materialized_as_copies_when_asked(tmp_path: Path) -> None:
    blobs = FileBlobStore(tmp_path / "blobs")
    files = await receive(_body(_tree_tar()), "tar", blobs, LIMITS)

    await materialize(files, blobs, tmp_path / "copy", link=False)

    fmu = tmp_path / "copy/model/beam.fmu"
    assert fmu.stat().st_ino != (await blobs.local_path(files[0].sha256)).stat().st_ino
    assert stat.S_IMODE(fmu.stat().st_mode) == 0o644
    fmu.write_bytes(b"changed")  # a copy: the blob stays as it was
    assert (await blobs.local_path(files[0].sha256)).read_bytes() == b"PK fmu"


async def test_100_mb_in_and_out_keeps_memory_constant(tmp_path: Path) -> None:
    blobs = FileBlobStore(tmp_path)
    size = 100 << 20
    part = os.urandom(1 << 20)  # 100 MB of incompressible bytes, never held whole

    async def big() -> AsyncIterator[bytes]:
        for n in range(size // len(part)):
            yield part[n:] + part[:n]

    tracemalloc.start()
    try:
        files = await receive(big(), "file", blobs, Limits(size), filename="big.bin")
        archive = send(files, blobs, "tar")
        again = await receive(archive, "tar", blobs, Limits(size + (1 << 20)))
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()

    assert again == files and files[0].size == size
    assert peak < 16 << 20  # a few chunks in flight, not the 100 MB
