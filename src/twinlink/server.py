"""Running the app under uvicorn, and what the first start prints."""

from __future__ import annotations

import socket
import sys
from collections.abc import Callable

import uvicorn

from twinlink.app import Services, create_app, outermost
from twinlink.auth.service import Bootstrap
from twinlink.config import ConfigError, Settings
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


def serve(
    settings: Settings,
    on_ready: Callable[[Services], object] | None = None,
    on_bootstrap: Callable[[Bootstrap], None] = print_bootstrap,
) -> None:
    setup_logging(settings.log_level, settings.log_format)
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
            f"cannot listen on {settings.host}:{settings.port}: {err.strerror}"
        ) from None
    if settings.mqtt_mode == "embedded" and settings.mqtt_port and not mqtt_port_free(settings):
        sock.close()
        raise ConfigError(
            f"cannot listen for MQTT on {settings.mqtt_host}:{settings.mqtt_port}: the port is "
            "in use (another broker?); set TWINLINK_MQTT_PORT (0 = any free port), or "
            "TWINLINK_MQTT_MODE=external to use that broker, or off"
        )
    # Listen before startup so a client that saw "serving at" is queued, never refused.
    sock.listen(2048)
    if settings.port == 0:
        settings.port = sock.getsockname()[1]

    async def ready(services: Services) -> object:
        result = None
        if on_ready is not None:
            result = on_ready(services)
            if hasattr(result, "__await__"):
                result = await result
        # Scripts and tests wait for this line; keep its wording stable.
        print(f"twinlink serving at {settings.base_url}", file=sys.stderr, flush=True)
        return result  # a cleanup coroutine function, if on_ready gave one

    app = create_app(settings, on_bootstrap=on_bootstrap, on_ready=ready)
    config = uvicorn.Config(
        outermost(app),
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
    )
    # Server.run picks the event loop (uvloop when installed, as with uvicorn[standard]).
    uvicorn.Server(config).run(sockets=[sock])
