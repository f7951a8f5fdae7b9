"""What a push reads from a version's files: `asset.yaml` (the asset's describing fields) and
the FMUs (checked, their FMI variables kept in the version's meta).

FMUs are checked by an inspector the composition root hands in (the processors' FMPy check):
the library sits below the processors and does not import them.
"""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from pathlib import Path
from typing import Any

from twinlink.domain.errors import DocumentError, InvalidInputError, TwinlinkError
from twinlink.domain.library import FileEntry
from twinlink.domain.yamlsource import parse_yaml_stream
from twinlink.library.blobs import BlobStore
from twinlink.store.library import AssetFields

# Checks the FMU at a path and describes it (FMI version, variables...); raises a
# TwinlinkError (InvalidInputError) saying what is wrong with it.
FmuInspector = Callable[[Path], dict[str, Any]]

ASSET_YAML = "asset.yaml"
ASSET_YAML_MAX = 64 * 1024
_TEXT_FIELDS = ("description", "licence", "author")


def fmu_paths(files: list[FileEntry]) -> list[str]:
    return [f.path for f in files if f.path.lower().endswith(".fmu")]


async def inspect_fmus(
    files: list[FileEntry], blobs: BlobStore, inspector: FmuInspector | None
) -> dict[str, dict[str, Any]]:
    """The FMI description of each FMU of the version by path; a bad one is refused (422)
    naming the file."""
    found: dict[str, dict[str, Any]] = {}
    by_path = {f.path: f for f in files}
    for path in fmu_paths(files):
        if inspector is None:
            break
        local = await blobs.local_path(by_path[path].sha256)
        try:
            found[path] = await asyncio.to_thread(inspector, local)
        except TwinlinkError as err:
            raise InvalidInputError(f"{path}: {err}") from err
    return found


async def read_asset_yaml(files: list[FileEntry], blobs: BlobStore) -> AssetFields:
    """The describing fields `asset.yaml` at the root of the version gives (none if absent)."""
    entry = next((f for f in files if f.path == ASSET_YAML), None)
    if entry is None:
        return AssetFields()
    if entry.size > ASSET_YAML_MAX:
        raise InvalidInputError(f"{ASSET_YAML} is over {ASSET_YAML_MAX // 1024} KiB")
    data = b"".join([chunk async for chunk in blobs.read(entry.sha256)])
    try:
        docs = parse_yaml_stream(data.decode("utf-8"))
    except UnicodeDecodeError as err:
        raise InvalidInputError(f"{ASSET_YAML} is not UTF-8 text") from err
    except DocumentError as err:
        raise InvalidInputError(f"{ASSET_YAML}: {err.problem_detail()}") from err
    return fields_of(docs[0].data if docs else None, ASSET_YAML)


def fields_of(data: Any, where: str) -> AssetFields:
    """The describing fields of a mapping (asset.yaml, a PATCH, a push's meta), checked."""
    if data is None:
        return AssetFields()
    if not isinstance(data, dict):
        raise InvalidInputError(f"{where} must be a mapping of description, keywords, ...")
    for key in _TEXT_FIELDS:
        if key in data and not isinstance(data[key], str):
            raise InvalidInputError(f"{where}: {key} must be text")
    keywords = data.get("keywords")
    if keywords is not None and (
        not isinstance(keywords, list) or not all(isinstance(k, str) for k in keywords)
    ):
        raise InvalidInputError(f"{where}: keywords must be a list of words")
    return AssetFields(
        description=data.get("description"),
        keywords=keywords,
        licence=data.get("licence"),
        author=data.get("author"),
    )


def merged(base: AssetFields, over: AssetFields) -> AssetFields:
    """`over`'s fields where it has them, else `base`'s."""
    return AssetFields(**{**base.as_dict(), **over.as_dict()})
