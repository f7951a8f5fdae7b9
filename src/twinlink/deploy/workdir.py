"""A deployment's working folder (docs/runs.md): one folder kept across all its lifecycle runs,
as DTaaS keeps a digital twin's folder, so that what `create` installed and `execute` wrote is
there for `analyze`, until `clean` has run and the deployment is terminated.

The folder is `<root>/<deployment id>/work`. It is filled once with copies of the package's
files (and its assets under `assets/<alias>/`), never hard links to the library's blobs (a
script could then write into the content-addressed store). A record beside it,
`<root>/<id>/package.json`, names the package version the folder holds and the files the
platform put there, so that a reconfigure to another version replaces exactly those: the new
version's files are written over them, the old version's files the new one lacks are removed,
and what the scripts made is kept.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import os
import shutil
from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import Any

from twinlink.deploy.runner import own_files

RECORD = "package.json"  # beside the folder, not in it: the scripts never see or change it
Materialize = Callable[[Path], Awaitable[None]]


def folder(root: Path, deployment_id: int) -> Path:
    return root / str(deployment_id) / "work"


def _read_record(path: Path) -> dict[str, Any] | None:
    try:
        record = json.loads(path.read_text("utf-8"))
    except (OSError, ValueError):
        return None  # none yet, or cut off while written: the folder is filled again
    return record if isinstance(record, dict) else None


def _files_under(top: Path) -> list[str]:
    return sorted(
        (Path(dirpath) / name).relative_to(top).as_posix()
        for dirpath, _, names in os.walk(top)
        for name in names
    )


def _remove(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    else:
        with contextlib.suppress(FileNotFoundError):
            path.unlink()


def _swap(stage: Path, work: Path, old: list[str]) -> list[str]:
    """Move the staged version's files into `work` over the old version's, remove the old
    version's files the new one lacks (and folders that leaves empty); the new files."""
    new = _files_under(stage)
    for path in set(old) - set(new):
        target = work / path
        _remove(target)
        for parent in target.parents:  # folders the old version brought, now empty
            if parent == work or not parent.is_relative_to(work):
                break
            try:
                parent.rmdir()
            except OSError:  # not empty (a script's files), or gone
                break
    for path in new:
        target = work / path
        for parent in reversed(target.relative_to(work).parents[:-1]):
            if (work / parent).is_file():  # a script's file where the package has a folder
                _remove(work / parent)
        target.parent.mkdir(parents=True, exist_ok=True)
        if target.is_dir() and not target.is_symlink():
            shutil.rmtree(target)
        os.replace(stage / path, target)
    return new


def _fill(work: Path, stage: Path, key: str) -> None:
    record_path = work.parent / RECORD
    record = _read_record(record_path)
    old = [str(p) for p in record.get("files", [])] if record else []
    own_files(stage)  # copies, never the library's blobs
    work.mkdir(parents=True, exist_ok=True)
    files = _swap(stage, work, old)
    temp = record_path.with_suffix(".tmp")
    temp.write_text(json.dumps({"key": key, "files": files}), "utf-8")
    os.replace(temp, record_path)


async def prepare(work: Path, key: str, materialize: Materialize) -> bool:
    """Bring the deployment's folder `work` to the package version `key` names (its pinned
    refs): nothing when it holds it already, else that version's files copied in (replacing
    the platform's files of the version before). Whether anything was written. The caller
    keeps two prepares of one folder from overlapping."""
    record = await asyncio.to_thread(_read_record, work.parent / RECORD)
    if record is not None and record.get("key") == key and work.is_dir():
        return False
    stage = work.parent / "stage"
    await asyncio.to_thread(shutil.rmtree, stage, True)
    await asyncio.to_thread(stage.mkdir, parents=True)
    try:
        await materialize(stage)
        await asyncio.to_thread(_fill, work, stage, key)
    finally:
        await asyncio.to_thread(shutil.rmtree, stage, True)
    return True


def remove(root: Path, deployment_id: int) -> None:
    """The deployment's folder and its record, gone (after `clean`, at terminate)."""
    shutil.rmtree(root / str(deployment_id), ignore_errors=True)
