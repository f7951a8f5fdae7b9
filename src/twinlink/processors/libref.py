"""Processor params that name an FMU in the library: `fmu: lib:models/tingen-beam@1.0.0`.

At create (and at an update that changes it) the reference is resolved with the rights of the
person making the change, checked against the FMI description the library kept when the
version was pushed (`version.meta["fmus"][path]`), and stored *pinned*
(`lib:common/models/tingen-beam@sha256:...#tingen.fmu`): a tag moved later does not change a
processor that exists. The version is held as `processor:<id>` while the processor uses it,
so it cannot be deleted under it. The worker is given the blob's local file, as it is given
a twin's uploaded FMU: the blueprint sees a folder and a plain file name.
"""

from __future__ import annotations

import logging
from pathlib import Path, PurePosixPath
from typing import Any

from twinlink.auth.rights import Principal
from twinlink.domain.errors import InvalidInputError, NotFoundError, TwinlinkError
from twinlink.domain.library import parse_ref
from twinlink.domain.records import ProcessorRecord
from twinlink.library.service import LibraryService, Resolved
from twinlink.processors.fmuenv import REQUIREMENTS_FILE, parse_requirements
from twinlink.processors.fmurules import check_fmu_params

log = logging.getLogger("twinlink.processors")

SCHEME = "lib:"
PARAM = "fmu"  # the one processor param that may be a library reference


def lib_ref(params: dict[str, Any]) -> str | None:
    """The library reference `params` give as their FMU, if they give one."""
    value = params.get(PARAM)
    return value if isinstance(value, str) and value.startswith(SCHEME) else None


def holder(processor_id: int) -> str:
    return f"processor:{processor_id}"


def checkable(params: dict[str, Any]) -> dict[str, Any]:
    """`params` with a library reference as the plain file name the blueprint will be given,
    so the blueprint's own checks (a plain file name) apply to the rest of them."""
    ref = lib_ref(params)
    if ref is None:
        return params
    try:
        path = parse_ref(ref).path
    except TwinlinkError:
        path = None
    return {**params, PARAM: Path(path).name if path else "library.fmu"}


def check_variables(
    params: dict[str, Any], info: dict[str, Any], where: str, mapped: list[str] | None = None
) -> None:
    """Refuse inputs, outputs and parameters the FMU cannot run with (422 naming them)."""
    check_fmu_params(params, mapped or [], info, where)


class LibraryFmus:
    """The library FMUs of the processors: pinned at create, held while used, and their local
    files found (off the hot path) before a worker starts."""

    def __init__(self, library: LibraryService | None) -> None:
        self.library = library
        self._files: dict[int, Path] = {}  # processor id -> the blob its worker runs
        self._twins: dict[int, int] = {}  # processor id -> its twin, for those using one
        # processor id -> the requirements.txt beside its FMU (a Python FMU's env, fmuenv.py)
        self._requirements: dict[int, list[str]] = {}

    async def open(self, records: list[ProcessorRecord]) -> None:
        self._twins = {r.id: r.twin_id for r in records if lib_ref(_params(r)) is not None}

    async def pin(self, principal: Principal, params: dict[str, Any]) -> Resolved | None:
        """Resolve the params' library FMU for `principal` and check them against it; the
        params then name it pinned (changed in place). None when they name no library FMU."""
        ref = lib_ref(params)
        if ref is None:
            return None
        if self.library is None:
            raise InvalidInputError("params.fmu: this server has no asset library")
        try:
            resolved = await self.library.resolve(principal, ref, kind="models")
        except NotFoundError as err:  # the processor is there to be made: its input is wrong
            raise InvalidInputError(f"params.fmu: {err}") from err
        if resolved.path is None:
            raise InvalidInputError(f"params.fmu: {ref} names no file; add #<path of the .fmu>")
        info = resolved.version.meta.get("fmus", {}).get(resolved.path)
        if not isinstance(info, dict):
            raise InvalidInputError(
                f"params.fmu: {resolved.path} of {resolved.pinned} is not an FMU the library "
                "checked at push (push it as a .fmu file)"
            )
        check_variables(params, info, resolved.pinned)
        await _requirements(self.library, resolved)  # a bad requirements.txt is a 422 now
        params[PARAM] = resolved.pinned
        return resolved

    async def hold(self, record: ProcessorRecord, resolved: Resolved | None) -> None:
        """Hold what the processor now uses, and nothing it used before."""
        await self.release([record.id])
        if resolved is not None and self.library is not None:
            await self.library.hold(holder(record.id), [resolved])
            self._twins[record.id] = record.twin_id

    async def release(self, processor_ids: list[int]) -> None:
        for pid in processor_ids:
            self._files.pop(pid, None)
            if self.library is not None and self._twins.pop(pid, None) is not None:
                await self.library.release(holder(pid))

    def of_twins(self, twin_ids: list[int]) -> list[int]:
        """The processors of these twins that hold library FMUs (deleted with their twins)."""
        return [pid for pid, twin in self._twins.items() if twin in twin_ids]

    async def prepare(self, records: list[ProcessorRecord]) -> None:
        """Find the local files of the processors' pinned library FMUs before their workers
        start. Each was resolved with its creator's rights when it was pinned, and is held
        since: it is looked up here without a person's rights."""
        for record in records:
            ref = lib_ref(_params(record))
            self._files.pop(record.id, None)
            self._requirements.pop(record.id, None)
            if ref is not None and self.library is not None:
                try:
                    self._files[record.id] = await self._local(self.library, ref)
                    self._requirements[record.id] = await self._wanted(self.library, ref)
                except TwinlinkError as err:  # its worker then fails to start, saying so
                    log.warning(
                        "processor %s/%s: its library FMU %s is not available: %s",
                        record.twin_slug, record.name, ref, err,
                    )  # fmt: skip

    async def described(self, ref: str) -> tuple[dict[str, Any], str]:
        """The FMI description the library kept for the pinned `ref` (held by the processor,
        so looked up without a person's rights), and the name to give it in errors."""
        if self.library is None:
            raise InvalidInputError("params.fmu: this server has no asset library")
        parsed = parse_ref(ref)
        if parsed.scope is None or parsed.kind is None or parsed.ref is None:
            raise InvalidInputError(f"params.fmu: {ref} is not pinned")
        asset = await self.library.store.get_asset(parsed.scope, parsed.kind, parsed.name)
        if asset is None:
            raise InvalidInputError(f"params.fmu: the library has no {ref}")
        try:
            version = await self.library.version_of(asset, parsed.ref)
        except NotFoundError as err:
            raise InvalidInputError(f"params.fmu: {err}") from err
        info = version.meta.get("fmus", {}).get(parsed.path)
        if not isinstance(info, dict):
            raise InvalidInputError(f"params.fmu: {ref} is not an FMU the library checked")
        return info, ref

    def requirements(self, processor_id: int) -> list[str]:
        """The requirements.txt beside the processor's library FMU (none: [])."""
        return self._requirements.get(processor_id, [])

    @staticmethod
    async def _wanted(library: LibraryService, ref: str) -> list[str]:
        parsed = parse_ref(ref)
        if parsed.scope is None or parsed.kind is None or parsed.ref is None:
            return []
        asset = await library.store.get_asset(parsed.scope, parsed.kind, parsed.name)
        if asset is None:
            return []
        version = await library.version_of(asset, parsed.ref)
        return await _requirements(library, Resolved(asset, version, parsed.path))

    @staticmethod
    async def _local(library: LibraryService, ref: str) -> Path:
        parsed = parse_ref(ref)
        if parsed.scope is None or parsed.kind is None or parsed.ref is None:
            raise InvalidInputError(f"{ref} is not pinned")
        asset = await library.store.get_asset(parsed.scope, parsed.kind, parsed.name)
        if asset is None:
            raise NotFoundError(f"the library has no {parsed.scope}/{parsed.kind}/{parsed.name}")
        version = await library.version_of(asset, parsed.ref)
        return await library.file_path(Resolved(asset, version, parsed.path))

    def worker_files(
        self, processor_id: int, params: dict[str, Any], files: Path
    ) -> tuple[dict[str, Any], Path]:
        """The params and the files folder the worker is given: for a library FMU, the blob's
        folder and its file name; else as they are."""
        if lib_ref(params) is None:
            return params, files
        local = self._files.get(processor_id)
        if local is None:  # not found (logged when looked for): the worker says it is missing
            return {**params, PARAM: "library-fmu-not-available.fmu"}, files
        return {**params, PARAM: local.name}, local.parent


async def _requirements(library: LibraryService, resolved: Resolved) -> list[str]:
    """The requirements.txt in the FMU's folder of its version, if there is one."""
    if resolved.path is None:
        return []
    wanted = str(PurePosixPath(resolved.path).parent / REQUIREMENTS_FILE).removeprefix("./")
    if not any(f.path == wanted for f in resolved.version.files):
        return []
    text = await library.read_text(resolved, wanted)
    try:
        return parse_requirements(text, f"{wanted} of {resolved.pinned}")
    except ValueError as err:
        raise InvalidInputError(f"params.fmu: {err}") from err


def _params(record: ProcessorRecord) -> dict[str, Any]:
    params = record.spec.get("params")
    return params if isinstance(params, dict) else {}
