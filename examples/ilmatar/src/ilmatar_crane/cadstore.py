"""The CAD file server: the crane's exported CAD files over HTTP, as the Data Link paper hosted
them beside a PLM system that had no web API. Files are streamed from one folder with Range and
HEAD support; every `/api/` call needs `Authorization: Bearer <token>`."""

from __future__ import annotations

import hashlib
import re
import secrets
from collections.abc import Awaitable, Callable
from pathlib import Path

from starlette.applications import Starlette
from starlette.requests import Request
from starlette.responses import FileResponse, JSONResponse, Response
from starlette.routing import Route

from ilmatar_crane._http import health, json_error, page_routes

# IANA registers both (RFC 8877 style registrations of 2020/2021); mimetypes knows neither.
MEDIA_TYPES = {
    ".stl": "model/stl",
    ".step": "model/step",
    ".stp": "model/step",
    ".txt": "text/plain; charset=utf-8",
}
# A plain file name: no separators, no leading dot, so nothing can climb out of the folder.
SAFE_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]{0,200}$")
ENDPOINTS = (
    ("GET /api/files", "The files: name, size, media type and sha256."),
    ("GET|HEAD /api/files/{name}", "Download a file; Range requests are supported."),
    ("GET /health", "Liveness (no token needed)."),
)
Handler = Callable[[Request], Awaitable[Response]]


def media_type(path: Path) -> str:
    return MEDIA_TYPES.get(path.suffix.lower(), "application/octet-stream")


class CadStore:
    def __init__(self, folder: Path, token: str) -> None:
        self.folder = folder.resolve()
        self._token = token
        self._hashes: dict[tuple[str, int, int], str] = {}  # (name, size, mtime) -> sha256
        routes = [
            Route("/health", health),
            Route("/api/files", self._guard(self._list)),
            Route("/api/files/{name:path}", self._guard(self._download)),
            *page_routes("Ilmatar CAD store", "CAD files of the crane.", ENDPOINTS),
        ]
        self.app = Starlette(routes=routes)

    def _guard(self, handler: Handler) -> Handler:
        async def guarded(request: Request) -> Response:
            scheme, _, token = request.headers.get("Authorization", "").partition(" ")
            ok = scheme.lower() == "bearer" and secrets.compare_digest(
                token.strip().encode(), self._token.encode()
            )
            if not ok:
                return json_error(
                    401,
                    "unauthorized",
                    "Send Authorization: Bearer <token> with the CAD store's token.",
                    {"WWW-Authenticate": 'Bearer realm="cad-store"'},
                )
            return await handler(request)

        return guarded

    def files(self) -> list[Path]:
        return sorted(p for p in self.folder.iterdir() if p.is_file() and SAFE_NAME.match(p.name))

    def sha256(self, path: Path) -> str:
        stat = path.stat()
        key = (path.name, stat.st_size, stat.st_mtime_ns)
        if key not in self._hashes:
            digest = hashlib.sha256()
            with path.open("rb") as f:
                for chunk in iter(lambda: f.read(1 << 16), b""):
                    digest.update(chunk)
            self._hashes[key] = digest.hexdigest()
        return self._hashes[key]

    async def _list(self, request: Request) -> Response:
        listing = [
            {
                "name": p.name,
                "size": p.stat().st_size,
                "media_type": media_type(p),
                "sha256": self.sha256(p),
            }
            for p in self.files()
        ]
        return JSONResponse({"files": listing})

    async def _download(self, request: Request) -> Response:
        name = request.path_params["name"]
        if not SAFE_NAME.match(name):
            return json_error(400, "invalid_name", "A file name has no path separators or '..'.")
        path = self.folder / name
        if not path.is_file():
            return json_error(404, "not_found", f"No file {name!r}; see GET /api/files.")
        return FileResponse(path, media_type=media_type(path), filename=name)
