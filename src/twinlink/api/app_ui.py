"""The web app (the single-page app built from `ui/`) under `/app/`.

The files are served as built (`ui/` -> `npm run build` -> `twinlink/web/app/`, or the
folder named by the `ui_dir` setting). Paths that are not files get `index.html`, so the
app's own routes (`/app/twins/{slug}`, ...) load it too. No token is needed: the app holds
no data, it signs in itself and then calls the API with its token.

The site's icon is served here too, at `/favicon.svg`, for the app and the server's own pages.
"""

from __future__ import annotations

import mimetypes
from pathlib import Path, PurePosixPath

from fastapi import APIRouter, Request
from starlette.responses import FileResponse, HTMLResponse, RedirectResponse, Response

import twinlink.web
from twinlink.web.render import page

router = APIRouter(include_in_schema=False)

PACKAGE_DIR = Path(twinlink.web.__file__).parent / "app"
FAVICON = Path(twinlink.web.__file__).parent / "favicon.svg"

# Vite names the files under assets/ by their content hash: they never change.
IMMUTABLE = "public, max-age=31536000, immutable"
NO_CACHE = "no-cache"

# Not every system's mime.types knows these; the browser refuses a script or a style
# sheet served with the wrong type.
_TYPES = {
    ".html": "text/html; charset=utf-8",
    ".js": "text/javascript; charset=utf-8",
    ".mjs": "text/javascript; charset=utf-8",
    ".css": "text/css; charset=utf-8",
    ".json": "application/json",
    ".map": "application/json",
    ".svg": "image/svg+xml",
    ".png": "image/png",
    ".ico": "image/x-icon",
    ".webp": "image/webp",
    ".woff": "font/woff",
    ".woff2": "font/woff2",
    ".wasm": "application/wasm",
    ".txt": "text/plain; charset=utf-8",
}

NOT_BUILT = page(
    "Web app not built",
    "<section><h1>The web app is not built</h1>"
    "<p>This server has no built web app to serve at <code>/app/</code>. Build it with "
    "<code>make setup</code> in a source checkout, or by hand: "
    "<code>cd ui &amp;&amp; npm ci &amp;&amp; npm run build</code> (Node 20 or newer). "
    "Then reload this page; the server need not be restarted.</p>"
    '<p><a href="/">Twins</a> · <a href="/docs">API documentation</a></p></section>',
)


def ui_dir(request: Request) -> Path:
    configured: Path | None = request.app.state.settings.ui_dir
    return configured if configured is not None else PACKAGE_DIR


def _media_type(path: Path) -> str:
    return (
        _TYPES.get(path.suffix.lower())
        or mimetypes.guess_type(path.name)[0]
        or ("application/octet-stream")
    )


def _file(path: Path, cache: str) -> FileResponse:
    return FileResponse(
        path,
        media_type=_media_type(path),
        headers={"Cache-Control": cache, "X-Content-Type-Options": "nosniff"},
    )


def _not_found() -> Response:
    return Response("Not found\n", status_code=404, media_type="text/plain; charset=utf-8")


@router.api_route("/favicon.svg", methods=["GET", "HEAD"])
async def favicon() -> FileResponse:
    return _file(FAVICON, "public, max-age=86400")


@router.api_route("/favicon.ico", methods=["GET", "HEAD"])
async def favicon_ico() -> RedirectResponse:
    # Browsers ask for /favicon.ico when a page names no icon (every page of ours names the
    # SVG one); tools that only know this name get it too.
    return RedirectResponse("/favicon.svg", status_code=308)


@router.api_route("/app", methods=["GET", "HEAD"])
async def app_root(request: Request) -> RedirectResponse:
    # The app's own links to its root carry state in the query (the catalog's ?view=tree).
    query = request.url.query
    return RedirectResponse(f"/app/?{query}" if query else "/app/", status_code=308)


@router.api_route("/app/{path:path}", methods=["GET", "HEAD"])
async def app_file(path: str, request: Request) -> Response:
    parts = PurePosixPath(path).parts if path else ()
    # A client route never has these; a file of the app never needs them.
    if any(p in ("..", ".") or "\\" in p or "\x00" in p for p in path.split("/")):
        return _not_found()
    root = ui_dir(request)
    index = root / "index.html"
    if not index.is_file():
        return HTMLResponse(NOT_BUILT, status_code=503, headers={"Cache-Control": NO_CACHE})
    if parts:
        target = root.joinpath(*parts)
        try:
            inside = target.resolve().is_relative_to(root.resolve())
        except (OSError, ValueError):
            inside = False
        if not inside:
            return _not_found()
        if target.is_file():
            immutable = parts[0] == "assets"
            return _file(target, IMMUTABLE if immutable else NO_CACHE)
        if parts[0] == "assets":
            # A missing script must not be answered with HTML (an old page after a new build).
            return _not_found()
    return _file(index, NO_CACHE)
