"""A twin's document in the exchange formats (docs/formats.md "Endpoints and commands"):
`/twins/{slug}?format=wot-td|dtdl|aas-json`, served by pages.py from the formats registered
here, and `/twins/{slug}/export.aasx`.

What is converted is the document the caller may read at `/twins/{slug}` (Registry.document),
so an export never shows more than the document does, and a twin without a public part needs
a token here as there. The endpoints an export links to come from the settings: the public
URL, the live WebSocket, and the MQTT broker devices publish to.
"""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from typing import Any
from urllib.parse import urlsplit

import orjson
from fastapi import APIRouter, Request
from starlette.responses import Response

from twinlink.api.deps import MaybeCaller, Registry
from twinlink.api.models.problem import problems
from twinlink.api.pages import Format, answer, register_format
from twinlink.config import Settings
from twinlink.formats import FORMATS, Exporter
from twinlink.formats.context import ExportContext

# The AAS specification's media type of an AASX package (Part 2, the API's serialization).
AASX = "application/asset-administration-shell-package+xml"
# For the OpenAPI description of `/twins/{slug}`: each exchange format's media type.
EXPORT_CONTENT: dict[str, Any] = {
    media_type: {"schema": {"type": "object", "additionalProperties": True}}
    for media_type, _ in FORMATS.values()
}

router = APIRouter(
    tags=["documents"], default_response_class=Response, responses=problems(401, 404, 503)
)


def export_context(settings: Settings, mqtt_port: int | None, slug: str) -> ExportContext:
    """The twin's endpoints as a client outside reaches them: the public URL, the live
    WebSocket, and the MQTT broker devices publish to (the embedded listener's address, or
    the external broker's)."""
    base = settings.base_url
    scheme, _, rest = base.partition("://")
    return ExportContext(
        twin_url=f"{base}/twins/{slug}",
        api_url=f"{base}/api/v1",
        slug=slug,
        mqtt_url=_mqtt_url(settings, mqtt_port),
        ws_url=f"{'wss' if scheme == 'https' else 'ws'}://{rest}/api/v1/live",
        mqtt_topic_prefix=settings.mqtt_topic_prefix,
        mqtt_external=settings.mqtt_mode == "external",  # a TD's MQTT forms need a real broker
    )


def _mqtt_url(settings: Settings, port: int | None) -> str | None:
    if settings.mqtt_mode == "external":
        broker = urlsplit(settings.mqtt_broker_url)
        default = 8883 if broker.scheme == "mqtts" else 1883
        return f"{broker.scheme}://{_host(broker.hostname or '')}:{broker.port or default}"
    if settings.mqtt_mode != "embedded" or port is None:
        return None  # off, or the listener is not listening
    host = settings.mqtt_host
    if host in ("0.0.0.0", "::", ""):
        # Listening on every address: the one the public URL names is the one to give out.
        host = urlsplit(settings.base_url).hostname or "127.0.0.1"
    return f"mqtt://{_host(host)}:{port}"


def _host(host: str) -> str:
    return f"[{host}]" if ":" in host else host  # an IPv6 address, bracketed in a URL


def request_context(request: Request, slug: str) -> ExportContext:
    """The export context of this server: its settings, and the port its MQTT listener got
    (with TWINLINK_MQTT_PORT=0 it is known only once listening)."""
    return export_context(request.app.state.settings, request.app.state.services.mqtt.port, slug)


def _render(convert: Exporter) -> Callable[[dict[str, Any], str, Request], bytes]:
    def render(document: dict[str, Any], slug: str, request: Request) -> bytes:
        exported = convert(document, request_context(request, slug))
        return orjson.dumps(exported, option=orjson.OPT_INDENT_2)

    return render


for _name, (_media_type, _convert) in FORMATS.items():
    register_format(_name, Format(_media_type, _render(_convert)))


@router.get(
    "/twins/{slug}/export.aasx",
    summary="The twin as an Asset Administration Shell package (AASX)",
    responses={200: {"content": {AASX: {"schema": {"type": "string", "format": "binary"}}}}},
)
async def twin_aasx(slug: str, request: Request, caller: MaybeCaller, reg: Registry) -> Response:
    # Imported on use, as FORMATS' conversions are: the AAS SDK loads with the first export.
    from twinlink.formats.aas import export_aasx

    twin, _, doc = await reg.document(caller, slug)
    # A zip of the whole environment: made off the event loop.
    package = await asyncio.to_thread(export_aasx, doc, request_context(request, twin.slug))
    # As the document's own answer: never kept by a shared cache once a token showed more.
    public = caller.user is None and twin.visibility == "public"
    headers = {
        "Vary": "Authorization",
        "Cache-Control": "no-cache" if public else "private, no-store",
        "Link": f'<{reg.canonical_url(twin.slug)}>; rel="canonical"',
        "Content-Disposition": f'attachment; filename="{twin.slug}.aasx"',
    }
    return answer(request, package, AASX, headers)
