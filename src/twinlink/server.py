"""Running the app under uvicorn, and what the first start prints."""

from __future__ import annotations

import contextlib
import logging
import socket
import sys
from collections.abc import Awaitable, Callable, MutableMapping
from typing import Any

import uvicorn
from fastapi import FastAPI

from twinlink.app import Services, create_app, outermost
from twinlink.auth.service import Bootstrap
from twinlink.config import ConfigError, Settings
from twinlink.domain.errors import TwinlinkError
from twinlink.logs import setup_logging


def print_bootstrap(created: Bootstrap) -> None:
    lines = [
        "",
        "  twinlink created the first admin user; this is shown once, keep it safe:",
        f"    username: {created.username}",
    ]
    if created.password:
        lines.append(f"    password: {created.password}")
    if created.token:
        lines.append(f"    API token: {created.token}")
    lines.append("")
    print("\n".join(lines), file=sys.stderr, flush=True)


log = logging.getLogger("twinlink.server")
Cleanup = Callable[[], Awaitable[None]]


class _Server(uvicorn.Server):
    """uvicorn's server, which runs `cleanups` (what `on_ready` started) while it still
    serves: a simulated device of the demo then stops with nothing unacknowledged and a
    connector before its server, instead of each seeing the platform vanish under it."""

    def __init__(self, config: uvicorn.Config, cleanups: list[Cleanup]) -> None:
        super().__init__(config)
        self.cleanups = cleanups

    async def shutdown(self, sockets: list[socket.socket] | None = None) -> None:
        for cleanup in self.cleanups:
            try:
                await cleanup()
            except Exception:
                log.exception("stopping what started with the server failed")
        await super().shutdown(sockets)


def mqtt_port_free(settings: Settings) -> bool:
    """Whether the embedded MQTT listener's port can be bound now."""
    family = socket.AF_INET6 if ":" in settings.mqtt_host else socket.AF_INET
    with socket.socket(family, socket.SOCK_STREAM) as probe:
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            probe.bind((settings.mqtt_host, settings.mqtt_port))
        except OSError:
            return False
    return True


def listen(settings: Settings) -> socket.socket:
    """The server's listening socket, bound and listening before startup, so a client that
    saw "serving at" is queued, never refused; a port that is taken is a ConfigError that
    says what to change (the MQTT listener's too, before anything has started)."""
    family = socket.AF_INET6 if ":" in settings.host else socket.AF_INET
    # Naming IPPROTO_TCP matters: asyncio sets TCP_NODELAY on accepted connections only when
    # the listening socket says it is TCP; without it Nagle's algorithm and delayed ACKs add
    # ~40 ms to every keep-alive request after the first.
    sock = socket.socket(family, socket.SOCK_STREAM, socket.IPPROTO_TCP)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind((settings.host, settings.port))
    except OSError as err:
        sock.close()
        raise ConfigError(
            f"cannot listen on {settings.host}:{settings.port}: {err.strerror}; choose another "
            "port with --port or TWINLINK_PORT (make demo PORT=8080)"
        ) from err
    if settings.mqtt_mode == "embedded" and settings.mqtt_port and not mqtt_port_free(settings):
        sock.close()
        raise ConfigError(
            f"cannot listen for MQTT on {settings.mqtt_host}:{settings.mqtt_port}: the port is "
            "in use (another broker?); set TWINLINK_MQTT_PORT (0 = any free port), or "
            "TWINLINK_MQTT_MODE=external to use that broker, or off"
        )
    sock.listen(2048)
    if settings.port == 0:
        settings.port = sock.getsockname()[1]
    return sock


def announce(settings: Settings) -> None:
    # Scripts and tests wait for this line; keep its wording stable.
    print(f"twinlink serving at {settings.base_url}", file=sys.stderr, flush=True)


def serve(
    settings: Settings,
    on_ready: Callable[[Services], object] | None = None,
    on_bootstrap: Callable[[Bootstrap], None] = print_bootstrap,
    *,
    sock: socket.socket | None = None,
    serving: Callable[[Settings], None] = announce,
) -> None:
    """Run the server until it is stopped. `sock`: a listening socket to serve on instead of
    binding one (a worker's, inherited from `twinlink up --workers`); `serving` is called
    once it serves."""
    setup_logging(settings.log_level, settings.log_format)
    sock = sock or listen(settings)
    cleanups: list[Cleanup] = []

    async def ready(services: Services) -> None:
        if on_ready is not None:
            result = on_ready(services)
            if hasattr(result, "__await__"):
                result = await result
            if callable(result):  # a cleanup coroutine function
                cleanups.append(result)
        serving(settings)

    app = create_app(settings, on_bootstrap=on_bootstrap, on_ready=ready)
    # uvicorn raises the SIGINT it stopped for again once it has stopped cleanly; ending here
    # keeps click from printing "Aborted!" after a clean stop.
    with contextlib.suppress(KeyboardInterrupt):
        # Server.run picks the event loop (uvloop when installed, as with uvicorn[standard]).
        _Server(_uvicorn_config(app, settings), cleanups).run(sockets=[sock])


def _uvicorn_config(app: FastAPI, settings: Settings) -> uvicorn.Config:
    return uvicorn.Config(
        StartErrors(outermost(app)),
        log_level=settings.log_level,
        log_config=None,  # setup_logging has configured uvicorn's loggers
        access_log=settings.access_log,
        lifespan="on",
        server_header=False,
        # A device batch may be up to 16 MiB (docs/protocol.md); larger frames close with 1009.
        ws_max_size=16 * 1024 * 1024 + 4096,
        ws_ping_interval=20.0,
        ws_ping_timeout=20.0,
        proxy_headers=False,
        # At a stop, requests still running after this long are cancelled (a long export
        # would otherwise hold the shutdown until it ends); the stop then takes seconds.
        timeout_graceful_shutdown=5,
    )


Message = MutableMapping[str, Any]
ASGIApp = Callable[
    [Message, Callable[[], Awaitable[Message]], Callable[[Message], Awaitable[None]]],
    Awaitable[None],
]


class StartErrors:
    """A start that fails for a reason a person can act on (PostgreSQL or Kafka unreachable, a
    broker refusing the credentials: a TwinlinkError) is logged as its message, not as the
    traceback uvicorn logs for any other failure. Requests pass straight through."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(
        self,
        scope: Message,
        receive: Callable[[], Awaitable[Message]],
        send: Callable[[Message], Awaitable[None]],
    ) -> None:
        if scope["type"] != "lifespan":
            return await self.app(scope, receive, send)
        held: list[Message] = []

        async def hold_failure(message: Message) -> None:
            if message["type"] == "lifespan.startup.failed":
                held.append(message)  # sent once the error is known, below
            else:
                await send(message)

        try:
            await self.app(scope, receive, hold_failure)
        except TwinlinkError as err:
            if held:
                await send({"type": "lifespan.startup.failed", "message": f"cannot start: {err}"})
            raise
        except BaseException:
            for message in held:
                await send(message)
            raise
        for message in held:
            await send(message)
