"""The asset library: list, push (a folder as a tar stream, or one file), pull (unpacked, or
the archive as it comes), show, versions, tags, delete. Nothing is held whole in memory."""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any

from twinlink.client import _tar
from twinlink.client._http import Transport
from twinlink.client.errors import ApiError
from twinlink.client.refs import AssetRef, parse_ref

ARCHIVE_FORMATS = {".zip": "zip", ".tgz": "tgz", ".gz": "tgz", ".tar": "tar"}


class Library:
    def __init__(self, transport: Transport) -> None:
        self._t = transport

    def ls(
        self, kind: str | None = None, scope: str | None = None, q: str | None = None
    ) -> list[dict[str, Any]]:
        """The assets the caller may read, narrowed by kind, scope and words (all pages)."""
        params = {k: v for k, v in {"kind": kind, "scope": scope, "q": q}.items() if v}
        params["limit"] = "1000"
        found: list[dict[str, Any]] = []
        while True:
            page = self._t.json("GET", "/api/v1/library", params=params)
            found += page["assets"]
            if not page.get("next"):
                return found
            params["after"] = page["next"]

    def locate(self, ref: str | AssetRef, kind: str | None = None) -> AssetRef:
        """`ref` with its scope: as written, else the first space that has the asset, in the
        server's order: the caller's own, their groups (sorted), then `common`."""
        found = ref if isinstance(ref, AssetRef) else parse_ref(ref, kind)
        if found.scope is not None:
            return found
        me = self._t.json("GET", "/api/v1/auth/me")
        scopes = [f"user:{me['username']}", *(f"group:{g}" for g in sorted(me["groups"]))]
        for scope in [*scopes, "common"]:
            try:
                self._t.request("GET", found.at(scope).base)
            except ApiError as err:
                if err.status in (403, 404):
                    continue
                raise
            return found.at(scope)
        raise ApiError(f"no asset {found} in your space, your groups' or common", 404)

    def show(self, ref: str | AssetRef) -> dict[str, Any]:
        """The asset, its tags and its versions."""
        return dict(self._t.json("GET", self.locate(ref).base))

    def versions(self, ref: str | AssetRef) -> list[dict[str, Any]]:
        """The asset's versions, newest first (without their files)."""
        return list(self._t.json("GET", f"{self.locate(ref).base}/versions")["versions"])

    def version(self, ref: str | AssetRef) -> dict[str, Any]:
        """One version with its files (`latest` when the ref names none)."""
        found = self.locate(ref)
        return dict(self._t.json("GET", f"{found.base}/versions/{found.version or 'latest'}"))

    def push(
        self,
        path: str | Path,
        *,
        kind: str,
        name: str,
        scope: str = "me",
        tags: Iterable[str] = (),
        description: str | None = None,
    ) -> dict[str, Any]:
        """Push a folder (its contents, streamed as tar) or one file as a new version of
        scope/kind/name; `{asset, version, created}` (created is false when a version with
        the same content exists: it is tagged, not copied)."""
        source = Path(path)
        if source.is_dir():
            files = _tar.folder_files(source)
            return self.push_files(
                files, kind=kind, name=name, scope=scope, tags=tags, description=description
            )
        if not source.is_file():
            raise FileNotFoundError(f"{source} is neither a file nor a folder")
        query = [("format", "file"), ("filename", source.name), *(("tag", t) for t in tags)]
        return self._push(AssetRef(kind, name, scope), query, _file_chunks(source), description)

    def push_files(
        self,
        files: list[tuple[str, Path]],
        *,
        kind: str,
        name: str,
        scope: str = "me",
        tags: Iterable[str] = (),
        description: str | None = None,
    ) -> dict[str, Any]:
        """Push (path in the version, local file) pairs as one version, streamed as tar."""
        if not files:
            raise ValueError("there are no files to push")
        query = [("format", "tar"), *(("tag", t) for t in tags)]
        return self._push(AssetRef(kind, name, scope), query, _tar.pack(files), description)

    def _push(
        self,
        target: AssetRef,
        query: list[tuple[str, str]],
        body: Iterator[bytes],
        description: str | None,
    ) -> dict[str, Any]:
        answer = dict(self._t.json("POST", f"{target.base}/versions", params=query, content=body))
        if description is not None:
            answer["asset"] = self.update(target, description=description)
        return answer

    def update(self, ref: str | AssetRef, **meta: Any) -> dict[str, Any]:
        """Change the asset's description, keywords, licence or author."""
        return dict(self._t.json("PATCH", self.locate(ref).base, json=meta))

    def pull(
        self, ref: str | AssetRef, dest: str | Path = ".", *, archive: str | Path | None = None
    ) -> Path:
        """The version under `dest` (unpacked; unsafe paths refused), or, with `archive`,
        the archive itself saved there (its format from the name: .tar, .tgz, .zip). A ref
        with `#path` fetches that one file into `dest`. Returns what was written."""
        found = self.locate(ref)
        at = f"{found.base}/versions/{found.version or 'latest'}"
        if archive is not None:
            out = Path(archive)
            fmt = ARCHIVE_FORMATS.get(out.suffix.lower(), "tar")
            with self._t.stream("GET", f"{at}/archive", params={"format": fmt}) as response:
                _save(response.iter_bytes(_tar.CHUNK), out)
            return out
        target = Path(dest)
        if found.path is not None:
            out = target / _tar.safe_member_path(found.path).name
            target.mkdir(parents=True, exist_ok=True)
            with self._t.stream("GET", f"{at}/files/{found.path}") as response:
                _save(response.iter_bytes(_tar.CHUNK), out)
            return out
        with self._t.stream("GET", f"{at}/archive", params={"format": "tar"}) as response:
            _tar.unpack(response.iter_bytes(_tar.CHUNK), target)
        return target

    def tag(self, ref: str | AssetRef, tag: str) -> dict[str, Any]:
        """Point `tag` at the ref's version (`latest` when it names none); moves it if set."""
        found = self.locate(ref)
        body = {"version": found.version or "latest"}
        response = self._t.request("PUT", f"{found.base}/tags/{tag}", json=body)
        return dict(response.json()) if response.content else {}

    def untag(self, ref: str | AssetRef, tag: str) -> None:
        self._t.request("DELETE", f"{self.locate(ref).base}/tags/{tag}")

    def rm(self, ref: str | AssetRef, version: str | None = None) -> None:
        """Delete one version (`version`, or the ref's `@version`), else the whole asset.
        Refused (409, naming them) while a deployment or processor uses it."""
        found = self.locate(ref)
        chosen = version or found.version
        path = f"{found.base}/versions/{chosen}" if chosen else found.base
        self._t.request("DELETE", path)


def _file_chunks(path: Path) -> Iterator[bytes]:
    with path.open("rb") as f:
        while chunk := f.read(_tar.CHUNK):
            yield chunk


def _save(chunks: Iterable[bytes], out: Path) -> None:
    """Written to a temporary file renamed into place: a cut download leaves nothing."""
    partial = out.with_name(out.name + ".partial")
    try:
        with partial.open("wb") as f:
            for chunk in chunks:
                f.write(chunk)
        partial.replace(out)
    finally:
        partial.unlink(missing_ok=True)
