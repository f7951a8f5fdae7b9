"""What the crane's HTTP services share: serving a Starlette app with uvicorn inside the running
event loop, JSON errors, and the small page each service shows at `/` and `/docs`."""

from __future__ import annotations

import asyncio
import contextlib
import html
import logging
import socket
import weakref
from collections.abc import Generator, Sequence
from typing import Any

import uvicorn
from starlette.requests import Request
from starlette.responses import HTMLResponse, JSONResponse, Response
from starlette.routing import Route
from starlette.types import ASGIApp

STARTUP_TIMEOUT_S = 10.0


class _QuietLifecycle(logging.Filter):
    """Drops the lines uvicorn logs about a server's own life ("Started server process [n]",
    "Shutting down", ...) from the crane's servers: they share the process and the logger
    (`uvicorn.error`) with the platform's server, whose lines already say it once. Errors
    still pass."""

    def __init__(self) -> None:
        super().__init__()
        self.tasks: weakref.WeakSet[asyncio.Task[None]] = weakref.WeakSet()

    def filter(self, record: logging.LogRecord) -> bool:
        if record.levelno > logging.INFO:
            return True
        try:
            task = asyncio.current_task()
        except RuntimeError:  # no running loop
            return True
        return task not in self.tasks


_QUIET = _QuietLifecycle()


class _InLoopServer(uvicorn.Server):
    # Several servers share one loop and one process; signals belong to whoever runs the loop
    # (the CLI or the platform), so no server may take over SIGINT/SIGTERM.
    @contextlib.contextmanager
    def capture_signals(self) -> Generator[None, None, None]:
        yield


class HttpService:
    """One uvicorn server for `app`, started and stopped inside the caller's event loop."""

    def __init__(self, app: ASGIApp, name: str) -> None:
        self.app = app
        self.name = name
        self.port = 0
        self._server: _InLoopServer | None = None
        self._task: asyncio.Task[None] | None = None

    async def start(self, host: str, port: int) -> None:
        sock = listening_socket(host, port)
        self.port = int(sock.getsockname()[1])
        config = uvicorn.Config(
            self.app,
            lifespan="off",
            log_config=None,
            access_log=False,
            server_header=False,
            ws="none",
            timeout_graceful_shutdown=2,
        )
        server = _InLoopServer(config)
        task = asyncio.create_task(server.serve(sockets=[sock]), name=self.name)
        logging.getLogger("uvicorn.error").addFilter(_QUIET)  # once; adding it again is a no-op
        _QUIET.tasks.add(task)
        self._server, self._task = server, task
        try:
            async with asyncio.timeout(STARTUP_TIMEOUT_S):
                # uvicorn has no "started" event to await; the socket already listens, so
                # clients are queued meanwhile, never refused.
                while not server.started and not task.done():
                    await asyncio.sleep(0.005)
            if not server.started:
                task.result()  # raises what stopped the server
                raise RuntimeError(f"{self.name} stopped while starting")
        except BaseException:
            with contextlib.suppress(Exception):
                await self.stop()
            sock.close()  # uvicorn closes it once started; closing twice is harmless
            raise

    async def stop(self) -> None:
        if self._server is None or self._task is None:
            return
        self._server.should_exit = True
        try:
            await self._task
        finally:
            self._server = None
            self._task = None


def listening_socket(host: str, port: int) -> socket.socket:
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind((host, port))
        sock.listen(128)
    except OSError as err:
        sock.close()
        raise OSError(err.errno, f"cannot listen on {host}:{port}: {err.strerror}") from err
    return sock


def can_listen(host: str, port: int) -> bool:
    """Whether a server could listen on host:port now (no other socket listens there)."""
    if port == 0:
        return True
    try:
        listening_socket(host, port).close()
    except OSError:
        return False
    return True


def url_host(host: str) -> str:
    """The host to put in URLs: a wildcard address is reached through loopback."""
    if host in ("", "0.0.0.0"):
        return "127.0.0.1"
    if host == "::":
        return "[::1]"
    return f"[{host}]" if ":" in host else host


def json_error(
    status: int, error: str, detail: str, headers: dict[str, str] | None = None
) -> JSONResponse:
    """Every service's error shape: `{"error": <code>, "detail": <what to do>}`."""
    return JSONResponse({"error": error, "detail": detail}, status_code=status, headers=headers)


async def json_body(request: Request) -> dict[str, Any] | JSONResponse:
    """The request's JSON object, or the 422 answer to send instead."""
    try:
        body = await request.json()
    except ValueError:
        return json_error(422, "invalid_json", "The body must be a JSON object.")
    if not isinstance(body, dict):
        return json_error(422, "invalid_json", "The body must be a JSON object.")
    return body


async def health(request: Request) -> Response:
    return JSONResponse({"status": "ok"})


def page_routes(title: str, about: str, endpoints: Sequence[tuple[str, str]]) -> list[Route]:
    """`/` and `/docs` (HTML) and `/api/` (JSON): what the service is and its endpoints, all
    readable without credentials so a new user can find their way."""
    rows = "".join(
        f"<tr><td><code>{html.escape(ep)}</code></td><td>{html.escape(what)}</td></tr>"
        for ep, what in endpoints
    )
    body = (
        f"<!doctype html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>"
        f"</head><body><h1>{html.escape(title)}</h1><p>{html.escape(about)}</p>"
        f"<table>{rows}</table><p>Part of the twinlink Ilmatar crane demo; see docs/crane.md."
        f"</p></body></html>"
    )

    index = {"service": title, "about": about, "endpoints": [ep for ep, _ in endpoints]}

    async def page(request: Request) -> Response:
        return HTMLResponse(body)

    async def api_index(request: Request) -> Response:
        return JSONResponse(index)

    return [Route("/", page), Route("/docs", page), Route("/api/", api_index)]
