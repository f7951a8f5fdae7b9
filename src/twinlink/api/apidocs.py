"""/openapi.json (needs a token unless TWINLINK_PUBLIC_API_DOCS) and /docs.

/docs is a static page (no data) that signs in and then loads Swagger UI from assets shipped
in the swagger-ui-bundle package, so it works offline and never loads code from a CDN.
"""

from __future__ import annotations

from importlib import resources
from typing import Any

from fastapi import APIRouter, FastAPI, Request
from starlette.responses import HTMLResponse, Response
from starlette.staticfiles import StaticFiles

from twinlink.api.contract import describe
from twinlink.api.deps import MaybeCaller
from twinlink.auth.service import AuthError

router = APIRouter(include_in_schema=False)


def _asset(name: str) -> str:
    return (resources.files("twinlink.web") / name).read_text("utf-8")


@router.get("/openapi.json")
async def openapi(request: Request, caller: MaybeCaller) -> Any:
    if caller.user is None and not request.app.state.settings.public_api_docs:
        raise AuthError("a token is required for the API description")
    return describe(request.app)


@router.get("/docs")
async def docs() -> HTMLResponse:
    return HTMLResponse(_asset("docs.html"))


@router.get("/docs/apidocs.js")
async def docs_script() -> Response:
    return Response(_asset("apidocs.js"), media_type="text/javascript")


def install(app: FastAPI) -> None:
    import swagger_ui_bundle  # type: ignore[import-untyped]

    app.openapi = lambda: describe(app)  # type: ignore[method-assign]
    app.include_router(router)
    app.mount(
        "/docs/assets", StaticFiles(directory=swagger_ui_bundle.swagger_ui_path), name="docs-assets"
    )
