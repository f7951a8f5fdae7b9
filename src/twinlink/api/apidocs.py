"""/openapi.json (needs a token unless TWINLINK_PUBLIC_API_DOCS) and /docs.

/docs is a static page (no data) that signs in and then loads Swagger UI 5, which reads the
OpenAPI 3.1 that FastAPI writes (Swagger UI 4 showed "Unable to render this definition").
Swagger UI comes from the npm package swagger-ui-dist, pinned in ui/package.json and built
into the package beside the web app (`apidocs/` of the app's folder, ui/vite.config.ts), so
/docs works offline and never loads code from a CDN.
"""

from __future__ import annotations

from importlib import resources

from fastapi import APIRouter, FastAPI, Request
from starlette.responses import FileResponse, HTMLResponse, Response

from twinlink.api.app_ui import ui_dir
from twinlink.api.contract import describe
from twinlink.api.deps import MaybeCaller
from twinlink.api.responses import JSONAnswer
from twinlink.auth.service import AuthError

router = APIRouter(include_in_schema=False)

# The viewer's files, as the web app's build writes them, and their types.
VIEWER_FILES = {
    "swagger-ui-bundle.js": "text/javascript; charset=utf-8",
    "swagger-ui.css": "text/css; charset=utf-8",
}
NOT_BUILT = (
    "The API viewer is not built. Build the web app (make setup, or cd ui && npm install && "
    "npm run build); it holds the viewer. /openapi.json works without it.\n"
)


def _asset(name: str) -> str:
    return (resources.files("twinlink.web") / name).read_text("utf-8")


@router.get("/openapi.json")
async def openapi(request: Request, caller: MaybeCaller) -> JSONAnswer:
    if caller.user is None and not request.app.state.settings.public_api_docs:
        raise AuthError("a token is required for the API description")
    return JSONAnswer(describe(request.app))


@router.get("/docs")
async def docs() -> HTMLResponse:
    return HTMLResponse(_asset("docs.html"))


@router.get("/docs/apidocs.js")
async def docs_script() -> Response:
    return Response(_asset("apidocs.js"), media_type="text/javascript")


@router.get("/docs/assets/{name}")
async def viewer_file(name: str, request: Request) -> Response:
    media_type = VIEWER_FILES.get(name)
    if media_type is None:
        return Response("Not found\n", status_code=404, media_type="text/plain; charset=utf-8")
    path = ui_dir(request) / "apidocs" / name
    if not path.is_file():
        return Response(NOT_BUILT, status_code=503, media_type="text/plain; charset=utf-8")
    # Not immutable: the name stays when swagger-ui-dist is upgraded.
    return FileResponse(path, media_type=media_type, headers={"Cache-Control": "no-cache"})


def install(app: FastAPI) -> None:
    app.openapi = lambda: describe(app)  # type: ignore[method-assign]
    app.include_router(router)
