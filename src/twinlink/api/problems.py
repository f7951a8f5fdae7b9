"""Every error leaves as problem+json (RFC 9457) with a message a person can act on.

One handler answers every TwinlinkError from what the error carries (its status, problem type,
detail, extension members and headers; domain/errors.py); the others answer what FastAPI and
Starlette raise themselves, and anything unexpected.
"""

from __future__ import annotations

import logging
from typing import Any

import orjson
from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.responses import Response

from twinlink.domain.errors import TwinlinkError, WriteConflictError, problem_document, title_of

log = logging.getLogger("twinlink.api")
PROBLEM = "application/problem+json"


def problem(
    status: int, detail: str, headers: dict[str, str] | None = None, **extra: Any
) -> Response:
    body = {"type": "about:blank", "title": title_of(status), "status": status, "detail": detail}
    return _answer({**body, **extra}, headers)


def error_problem(err: TwinlinkError) -> Response:
    """The answer `err` becomes."""
    return _answer(problem_document(err), err.problem_headers())


def _answer(body: dict[str, Any], headers: dict[str, str] | None) -> Response:
    status: int = body["status"]
    if status == 401:
        headers = {"WWW-Authenticate": 'Bearer realm="twinlink"', **(headers or {})}
    return Response(orjson.dumps(body), status_code=status, media_type=PROBLEM, headers=headers)


def install(app: FastAPI) -> None:
    @app.exception_handler(TwinlinkError)
    async def _twinlink(request: Request, exc: TwinlinkError) -> Response:
        if exc.status == 500:
            # No answer of its own: a bug, answered (and logged) by _unexpected below.
            raise exc
        if isinstance(exc, WriteConflictError):
            # Services check for conflicts first; this is the safety net for a race between
            # them: worth a line in the log.
            extra = {"event": "conflict", "path": request.url.path}
            log.warning("store refused a write", extra=extra)
        return error_problem(exc)

    @app.exception_handler(RequestValidationError)
    async def _invalid(_: Request, exc: RequestValidationError) -> Response:
        errors = [
            {"path": ".".join(str(x) for x in e["loc"]), "message": e["msg"]} for e in exc.errors()
        ]
        summary = "; ".join(f"{e['path']}: {e['message']}" for e in errors[:3])
        return problem(422, f"The request is not valid: {summary}", errors=errors)

    @app.exception_handler(StarletteHTTPException)
    async def _http(_: Request, exc: StarletteHTTPException) -> Response:
        return problem(exc.status_code, str(exc.detail))

    @app.exception_handler(Exception)
    async def _unexpected(request: Request, exc: Exception) -> Response:
        log.exception("unhandled error", extra={"event": "error", "path": request.url.path})
        return problem(500, "An internal error occurred; it has been logged.")
