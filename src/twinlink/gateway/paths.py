"""Which requests are for the gateway, and the upstream target they may reach.

Only paths below a service's base URL are ever asked for: the part of the path after the
service name is checked segment by segment in its raw (percent-encoded) form and refused if
any segment is, or decodes to, `.` or `..` (also with `;parameters`), holds an encoded slash,
backslash or NUL, or is encoded twice; absolute URLs and empty leading segments (`//host`) are
refused too.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from urllib.parse import unquote_to_bytes

from twinlink.domain.errors import TwinlinkError

_TWIN_SERVICE = re.compile(rb"^/twins/([a-z0-9][a-z0-9-]*)/services/([a-z0-9][a-z0-9-]*)(/.*)?$")
_DEFAULT = re.compile(rb"^/services/([a-z0-9][a-z0-9-]*)(/.*)?$")
_ALLOWED = re.compile(rb"^[A-Za-z0-9\-._~!$&'()*+,;=:@%]*$")
_PLAIN = re.compile(rb"^[A-Za-z0-9\-._~!$&'()*+,;=:@][A-Za-z0-9\-._~!$&'()*+,;=:@/]*$")
_DOUBLE = re.compile(rb"%(?:25|2e|2f|5c|00)", re.IGNORECASE)


class PathRefused(TwinlinkError, ValueError):
    """A path that could leave the service's base URL."""


@dataclass(frozen=True, slots=True)
class Route:
    twin: str | None  # None: the configured default twin
    service: str
    rest: bytes  # raw path below the service, without the leading slash
    prefix: str  # the gateway path of the service, for X-Forwarded-Prefix and Location


def match(raw_path: bytes) -> Route | None:
    """The gateway route of a request path, or None when it is not a gateway path."""
    found = _TWIN_SERVICE.match(raw_path)
    if found is not None:
        twin, service, rest = found.group(1), found.group(2), found.group(3) or b""
        prefix = f"/twins/{twin.decode()}/services/{service.decode()}"
        return Route(twin.decode(), service.decode(), rest[1:], prefix)
    found = _DEFAULT.match(raw_path)
    if found is not None:
        service, rest = found.group(1), found.group(2) or b""
        return Route(None, service.decode(), rest[1:], f"/services/{service.decode()}")
    return None


def check_rest(rest: bytes) -> bytes:
    """`rest` if it stays below the base URL; PathRefused (with the reason) otherwise."""
    if not rest or (
        _PLAIN.match(rest) and b"/." not in rest and rest[:1] != b"." and b"://" not in rest
    ):
        return rest  # the usual path: nothing encoded, no dot segments
    if rest.startswith(b"/"):
        raise PathRefused("the path below the service may not start with '/'")
    for segment in rest.split(b"/"):
        if not _ALLOWED.match(segment):
            raise PathRefused("the path holds characters that must be percent-encoded")
        decoded = unquote_to_bytes(segment)
        # `..;x` is `..` to servers that strip path parameters (Tomcat, Jetty, Spring).
        if decoded.split(b";", 1)[0] in (b".", b".."):
            raise PathRefused("'.' and '..' segments are not allowed in a service path")
        if b"/" in decoded or b"\\" in decoded or b"\x00" in decoded:
            raise PathRefused("encoded '/', '\\' and NUL are not allowed in a service path")
        if _DOUBLE.search(decoded):
            raise PathRefused("the path is percent-encoded twice")
    if b"://" in unquote_to_bytes(rest):
        raise PathRefused("a service path may not hold an absolute URL")
    return rest


def target(base_path: str, rest: bytes, query: bytes, extra_query: list[str]) -> str:
    """The request target sent to the service: its base path, `rest` and the query."""
    path = base_path + rest.decode("ascii")
    parts = [query.decode("latin-1")] if query else []
    parts.extend(extra_query)
    return f"{path}?{'&'.join(parts)}" if parts else path


def strip_query_param(query: bytes, name: bytes) -> tuple[bytes, str | None]:
    """The query without `name=...`, and that parameter's value (the WebSocket token)."""
    if name not in query:
        return query, None
    kept, value = [], None
    for pair in query.split(b"&"):
        key, _, val = pair.partition(b"=")
        if key == name:
            value = unquote_to_bytes(val).decode("utf-8", "replace")
        else:
            kept.append(pair)
    return b"&".join(kept), value
