"""Every error leaves as problem+json (RFC 9457) with a message a person can act on."""

from __future__ import annotations

import logging
from typing import Any

import orjson
from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.responses import Response

from twinlink.auth.service import AuthError, LoginError
from twinlink.commands.targets import DeviceChoiceError
from twinlink.domain.errors import (
    ConflictError,
    DocumentError,
    DocumentTooLargeError,
    ForbiddenError,
    InvalidInputError,
    NotFoundError,
    PayloadTooLargeError,
    StorageError,
    StorageFullError,
    WriteConflictError,
)

log = logging.getLogger("twinlink.api")
PROBLEM = "application/problem+json"
TITLES = {
    400: "Bad request",
    401: "Unauthorized",
    403: "Forbidden",
    404: "Not found",
    405: "Method not allowed",
    409: "Conflict",
    413: "Content too large",
    415: "Unsupported media type",
    422: "Unprocessable content",
    500: "Internal error",
    503: "Service unavailable",
    507: "Insufficient storage",
}
# A client told that storage failed tries again after this long (Retry-After): long enough
# for an administrator to notice, short enough that nothing waits needlessly once fixed.
STORAGE_RETRY_AFTER_S = 30


def problem(
    status: int, detail: str, headers: dict[str, str] | None = None, **extra: Any
) -> Response:
    body = {
        "type": "about:blank",
        "title": TITLES.get(status, "Error"),
        "status": status,
        "detail": detail,
        **extra,
    }
    if status == 401:
        headers = {"WWW-Authenticate": 'Bearer realm="twinlink"', **(headers or {})}
    return Response(orjson.dumps(body), status_code=status, media_type=PROBLEM, headers=headers)


def install(app: FastAPI) -> None:
    @app.exception_handler(AuthError)
    async def _auth(_: Request, exc: AuthError) -> Response:
        if isinstance(exc, LoginError):
            return problem(401, f"{exc}.")
        return problem(401, f"{exc}. Send a valid token as 'Authorization: Bearer <token>'.")

    @app.exception_handler(ForbiddenError)
    async def _forbidden(_: Request, exc: ForbiddenError) -> Response:
        return problem(403, str(exc))

    @app.exception_handler(NotFoundError)
    async def _not_found(_: Request, exc: NotFoundError) -> Response:
        return problem(404, str(exc.args[0]) if exc.args else "not found")

    @app.exception_handler(ConflictError)
    async def _conflict(_: Request, exc: ConflictError) -> Response:
        return problem(409, str(exc))

    @app.exception_handler(DocumentError)
    async def _document(_: Request, exc: DocumentError) -> Response:
        status = 413 if isinstance(exc, DocumentTooLargeError) else 422
        first = exc.problems[0] if exc.problems else None
        detail = exc.title if first is None else f"{exc.title} First: {first}"
        return problem(status, detail, errors=[p.as_dict() for p in exc.problems])

    @app.exception_handler(InvalidInputError)
    async def _invalid_input(_: Request, exc: InvalidInputError) -> Response:
        return problem(413 if isinstance(exc, PayloadTooLargeError) else 422, str(exc))

    @app.exception_handler(DeviceChoiceError)
    async def _device_choice(_: Request, exc: DeviceChoiceError) -> Response:
        # Why, and the devices to choose from, so a client can say it in its own terms (the
        # CLI names its --device option).
        return problem(422, str(exc), reason=exc.reason, devices=exc.devices)

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

    @app.exception_handler(StorageError)
    async def _storage(_: Request, exc: StorageError) -> Response:
        # Counted and logged (once a minute) where it happened, in the store: not here.
        # 507 when the disk is full (it stays so until someone frees space), 503 for an I/O
        # error; both say when to try again, and that nothing was stored.
        status = 507 if isinstance(exc, StorageFullError) else 503
        retry = {"Retry-After": str(STORAGE_RETRY_AFTER_S)}
        return problem(status, str(exc), headers=retry)

    @app.exception_handler(WriteConflictError)
    async def _integrity(request: Request, exc: WriteConflictError) -> Response:
        # Services check for conflicts first; this is the safety net for a race between them.
        log.warning("store refused a write", extra={"event": "conflict", "path": request.url.path})
        return problem(409, "The change conflicts with the current state; retry it.")

    @app.exception_handler(Exception)
    async def _unexpected(request: Request, exc: Exception) -> Response:
        log.exception("unhandled error", extra={"event": "error", "path": request.url.path})
        return problem(500, "An internal error occurred; it has been logged.")
