"""An uploaded co-simulation file or folder, received into a folder of its own.

The body is spooled to a file (refused as soon as it is over the limit), then kept as it is
(a Maestro multi-model, a YAML system, an SSP archive) or unpacked (a zip or tar of a folder)
with the library's hardened unpacker (library/unpack.py: paths, links, entry counts and sizes
checked before a byte is written). `received` says which document describes the system.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import os
import shutil
import zipfile
from collections.abc import AsyncIterator
from dataclasses import dataclass
from pathlib import Path

from twinlink.domain.errors import InvalidInputError, PayloadTooLargeError
from twinlink.library.blobs import CHUNK, FileBlobStore
from twinlink.library.manifest import Limits
from twinlink.library.unpack import size_text, unpack

from .ssp import SSD_NAME, extract

# What a body may be, by its Content-Type (parameters such as charset ignored).
MEDIA = {
    "application/json": "json",
    "application/yaml": "yaml",
    "application/x-yaml": "yaml",
    "text/yaml": "yaml",
    "application/zip": "zip",
    "application/x-zip-compressed": "zip",
    "application/x-tar": "tar",
    "application/gzip": "tgz",
    "application/x-gzip": "tgz",
}
DOCUMENT_SUFFIXES = (".json", ".yaml", ".yml")
MAX_FILES = 2000  # entries of an uploaded folder
FILES = "files"  # the uploaded files' folder, in the co-simulation's folder
SSP_FILE = "system.ssp"  # an SSP archive, kept whole beside its unpacked files


@dataclass(frozen=True, slots=True)
class Received:
    """The upload as kept: the system's `document` and a Maestro settings file beside it, if
    any (both relative to the co-simulation's folder), and its `format` (maestro, ssp, yaml)."""

    document: str
    format: str
    settings: str | None = None


def kind_of(content_type: str) -> str:
    media = content_type.split(";", 1)[0].strip().lower()
    kind = MEDIA.get(media)
    if kind is None:
        accepted = ", ".join(sorted(MEDIA))
        raise InvalidInputError(
            f"Content-Type {media or '(none)'!r} is not a co-simulation file; send a Maestro "
            f"multi-model (application/json), a YAML system (application/yaml), an SSP or a "
            f"folder as a zip, tar or tgz (one of: {accepted})"
        )
    return kind


async def receive(
    body: AsyncIterator[bytes], content_type: str, folder: Path, max_bytes: int
) -> Received:
    """Keep the upload in `folder` (its files under `files/`); InvalidInputError naming what
    is wrong, PayloadTooLargeError over `max_bytes` (the caller removes the folder then)."""
    kind = kind_of(content_type)
    files = folder / FILES
    files.mkdir(parents=True)
    spool = folder / "upload.part"
    try:
        await _spool(body, spool, max_bytes)
        if kind == "json":
            spool.rename(files / "multimodel.json")
            return Received(f"{FILES}/multimodel.json", "maestro")
        if kind == "yaml":
            spool.rename(files / "system.yaml")
            return Received(f"{FILES}/system.yaml", "yaml")
        if kind == "zip" and await asyncio.to_thread(_is_ssp, spool):
            spool.rename(folder / SSP_FILE)
            await asyncio.to_thread(extract, folder / SSP_FILE, files)
            return Received(SSP_FILE, "ssp")
        await asyncio.to_thread(_unpack, spool, kind, files, max_bytes)
        return await asyncio.to_thread(_find_document, folder)
    finally:
        spool.unlink(missing_ok=True)


async def _spool(body: AsyncIterator[bytes], spool: Path, max_bytes: int) -> None:
    size = 0
    with spool.open("wb") as out:
        pending: list[bytes] = []
        pending_size = 0
        async for chunk in body:
            size += len(chunk)
            if size > max_bytes:
                raise PayloadTooLargeError(
                    f"the upload is over the co-simulation limit of {size_text(max_bytes)} "
                    "(cosim_max_mb)"
                )
            pending.append(chunk)
            pending_size += len(chunk)
            if pending_size >= CHUNK:
                await asyncio.to_thread(out.writelines, pending)
                pending, pending_size = [], 0
        await asyncio.to_thread(out.writelines, pending)
    if size == 0:
        raise InvalidInputError("the upload is empty: send the co-simulation file as the body")


def _is_ssp(spool: Path) -> bool:
    """A zip holding SystemStructure.ssd at its root is an SSP archive."""
    try:
        with zipfile.ZipFile(spool) as archive:
            return SSD_NAME in archive.namelist()
    except (OSError, zipfile.BadZipFile) as err:
        raise InvalidInputError(f"the body is not a readable zip archive: {err}") from err


def _unpack(spool: Path, kind: str, files: Path, max_bytes: int) -> None:
    """The archive's files under `files`, each where its path says (checked by unpack)."""
    blobs = FileBlobStore(files.parent / "unpacking")
    try:
        unpacked = unpack(spool, kind, blobs, Limits(max_bytes, MAX_FILES))
    except PayloadTooLargeError as err:  # its own words name the library's setting
        raise PayloadTooLargeError(
            f"the archive unpacks to more than the co-simulation limit of "
            f"{size_text(max_bytes)} (cosim_max_mb)"
        ) from err
    try:
        for entry, temp in zip(unpacked.entries, unpacked.temps, strict=True):
            target = files / entry.path
            target.parent.mkdir(parents=True, exist_ok=True)
            os.replace(temp, target)
            target.chmod(0o644)
    finally:
        unpacked.discard()
        shutil.rmtree(blobs.root, ignore_errors=True)


def _find_document(folder: Path) -> Received:
    """The one document at the folder's top level (or in its only folder, as `tar -cf x.tar
    msd/` packs it); with two JSON files, the multi-model (it has `fmus`) and its settings."""
    top = folder / FILES
    entries = list(top.iterdir())
    if len(entries) == 1 and entries[0].is_dir():
        top = entries[0]
    found = sorted(p for p in top.iterdir() if p.is_file() and p.suffix in DOCUMENT_SUFFIXES)
    rel = [p.relative_to(folder).as_posix() for p in found]
    if not found:
        raise InvalidInputError(
            "the folder holds no .json, .yaml or .yml document at its top level (nor a "
            "SystemStructure.ssd): put the multi-model or the YAML system there"
        )
    yaml_docs = [r for r in rel if not r.endswith(".json")]
    json_docs = [r for r in rel if r.endswith(".json")]
    if len(found) == 1:
        return Received(rel[0], "yaml" if yaml_docs else "maestro")
    if not yaml_docs and len(json_docs) == 2:
        models = [r for r in json_docs if _has_fmus(folder / r)]
        if len(models) == 1:
            settings = next(r for r in json_docs if r != models[0])
            return Received(models[0], "maestro", settings)
    names = ", ".join(r.removeprefix(f"{FILES}/") for r in rel)
    raise InvalidInputError(
        f"the folder holds several documents at its top level ({names}): keep one "
        "(or a multi-model and its settings file, such as coe.json)"
    )


def _has_fmus(path: Path) -> bool:
    with contextlib.suppress(OSError, ValueError):
        data = json.loads(path.read_text(encoding="utf-8"))
        return isinstance(data, dict) and "fmus" in data
    return False
