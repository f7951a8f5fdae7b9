"""FMUs uploaded to a twin: checked with FMPy on upload, kept as files, listed with variables.

An upload is streamed to a temporary file (hashing as it goes, refused once over the size
limit), inspected in a thread (a bad file is refused with FMPy's reasons and leaves nothing
behind), then renamed into place; processors of the twin refer to it by its file name.
"""

from __future__ import annotations

import asyncio
import hashlib
import os
import re
import tempfile
import time
from collections.abc import AsyncIterator
from pathlib import Path
from typing import Any

from twinlink.auth.rights import Principal, has_role
from twinlink.domain.errors import (
    ConflictError,
    ForbiddenError,
    InvalidInputError,
    NotFoundError,
    PayloadTooLargeError,
)
from twinlink.domain.records import FmuRecord, TwinRecord
from twinlink.registry.service import RegistryService
from twinlink.store.base import MetadataStore

FMU_NAME = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.-]{0,99}\.fmu$")


def fmu_view(record: FmuRecord, variables: bool = False) -> dict[str, Any]:
    info = dict(record.info)
    if not variables:
        info.pop("variables", None)
    return {
        "name": record.name,
        "sha256": record.sha256,
        "size": record.size,
        "uploaded_ns": record.uploaded_ns,
        **info,
    }


class FmuService:
    def __init__(
        self,
        store: MetadataStore,
        registry: RegistryService,
        data_dir: Path,
        max_bytes: int,
        uploaders: str = "admins",
    ) -> None:
        self.store = store
        self.registry = registry
        self.root = Path(data_dir) / "fmus"
        self.max_bytes = max_bytes
        self.uploaders = uploaders

    def folder(self, twin_id: int) -> Path:
        return self.root / str(twin_id)

    async def upload(
        self, principal: Principal, slug: str, name: str, body: AsyncIterator[bytes]
    ) -> FmuRecord:
        twin = await self._twin(principal, slug, "editor")
        if not FMU_NAME.match(name):
            raise InvalidInputError(
                f"{name!r} is not an FMU file name: letters, digits, '_', '.', '-', ending .fmu"
            )
        folder = self.folder(twin.id)
        folder.mkdir(parents=True, exist_ok=True)
        fd, temp_name = tempfile.mkstemp(dir=folder, prefix=".upload-", suffix=".fmu")
        temp = Path(temp_name)
        try:
            digest, size = await self._receive(fd, body)
            info = await asyncio.to_thread(inspect_upload, temp)
            os.replace(temp, folder / name)
        finally:
            temp.unlink(missing_ok=True)
        user_id = principal.user.id if principal.user else None
        return await self.store.put_fmu(twin.id, name, digest, size, info, user_id, time.time_ns())

    async def _receive(self, fd: int, body: AsyncIterator[bytes]) -> tuple[str, int]:
        digest = hashlib.sha256()
        size = 0
        with os.fdopen(fd, "wb") as out:
            async for chunk in body:
                size += len(chunk)
                if size > self.max_bytes:
                    raise PayloadTooLargeError(
                        f"the FMU is over the limit of {self.max_bytes // 2**20} MB (fmu_max_mb)"
                    )
                digest.update(chunk)
                await asyncio.to_thread(out.write, chunk)
        if size == 0:
            raise InvalidInputError("the upload is empty: send the .fmu file as the body")
        return digest.hexdigest(), size

    async def list_fmus(self, principal: Principal, slug: str) -> list[FmuRecord]:
        twin = await self._twin(principal, slug, "viewer")
        return await self.store.list_fmus(twin.id)

    async def get(self, principal: Principal, slug: str, name: str) -> FmuRecord:
        for record in await self.list_fmus(principal, slug):
            if record.name == name:
                return record
        raise NotFoundError(f"twin {slug!r} has no FMU {name!r}")

    async def delete(self, principal: Principal, slug: str, name: str, users: list[str]) -> None:
        """Delete an FMU; refused while processors (`users`) are set to use it."""
        twin = await self._twin(principal, slug, "editor")
        if users:
            raise ConflictError(f"{name!r} is used by processor(s) {', '.join(users)}")
        if not await self.store.delete_fmu(twin.id, name):
            raise NotFoundError(f"twin {slug!r} has no FMU {name!r}")
        (self.folder(twin.id) / name).unlink(missing_ok=True)

    async def _twin(self, principal: Principal, slug: str, needed: str) -> TwinRecord:
        twin, role = await self.registry.require_twin(principal, slug)
        if needed == "editor" and not has_role(principal, role, "editor"):
            raise ForbiddenError(f"uploading or deleting FMUs of {slug!r} needs the editor role")
        if needed == "editor" and self.uploaders == "admins" and not principal.is_admin:
            raise ForbiddenError(
                "an FMU is native code that runs on the server, so only admins upload and "
                "delete FMUs here (TWINLINK_FMU_UPLOADERS=editors lets editors of the twin)"
            )
        return twin


def inspect_upload(path: Path) -> dict[str, Any]:
    """Check an uploaded FMU (a twin's, or one pushed to the library) and describe it."""
    # FMPy is imported at the first upload, not when the server starts.
    from twinlink.processors.fmuinfo import FmuError, inspect_fmu

    try:
        return inspect_fmu(path).as_dict()
    except FmuError as err:
        raise InvalidInputError(f"not a usable FMU: {err}") from err
