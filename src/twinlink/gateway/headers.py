"""Headers in both directions: hop-by-hop headers removed (RFC 9110 section 7.6.1), the
client's credentials and cookies for the platform never passed on, X-Forwarded-* set by the
gateway alone, and redirects kept inside the service."""

from __future__ import annotations

import re
from urllib.parse import unquote, urlsplit

from twinlink.domain.errors import TwinlinkError

Headers = list[tuple[bytes, bytes]]

HOP_BY_HOP = frozenset(
    {
        b"connection",
        b"keep-alive",
        b"proxy-authenticate",
        b"proxy-authorization",
        b"proxy-connection",
        b"te",
        b"trailer",
        b"transfer-encoding",
        b"upgrade",
    }
)
# Not passed to the service: the client's credentials (for the platform, not the service),
# its cookies (the platform's), forwarding headers it could forge, and what the gateway sets.
_REQUEST_DROP = HOP_BY_HOP | {
    b"authorization",
    b"cookie",
    b"host",
    b"expect",
    b"forwarded",
    b"x-forwarded-for",
    b"x-forwarded-host",
    b"x-forwarded-proto",
    b"x-forwarded-prefix",
    b"x-real-ip",
}
# Not passed back: the service's cookies would be set for the platform's origin.
_RESPONSE_DROP = HOP_BY_HOP | {b"set-cookie", b"date", b"server"}


# RFC 9110 section 5.1 (a token) and 5.5 (visible characters, spaces and tabs; no CR, LF or
# NUL, which would end the header and let a value smuggle headers or a whole request).
_FIELD_NAME = re.compile(r"^[!#$%&'*+\-.^_`|~0-9A-Za-z]+$")
_FIELD_VALUE = re.compile(r"^[\t\x20-\x7e\x80-\xff]*$")


def is_field_name(name: str) -> bool:
    return bool(_FIELD_NAME.match(name))


def is_field_value(value: str) -> bool:
    """Whether `value` can be sent as a header value as it is (latin-1, nothing that ends it)."""
    return bool(_FIELD_VALUE.match(value))


class RedirectRefused(TwinlinkError, ValueError):
    """The service redirected outside its own base URL."""


def _listed_in_connection(headers: Headers) -> frozenset[bytes]:
    named: set[bytes] = set()
    for name, value in headers:
        if name == b"connection":
            named.update(v.strip().lower() for v in value.split(b","))
    return frozenset(named)


def request_headers(
    headers: Headers,
    host: bytes,
    client: str,
    scheme: str,
    client_host: bytes,
    prefix: str,
) -> Headers:
    """The client's headers as sent on to the service (without credentials)."""
    extra_drop = _listed_in_connection(headers)
    out: Headers = [(b"host", host)]
    for name, value in headers:
        if name in _REQUEST_DROP or name in extra_drop:
            continue
        out.append((name, value))
    out.append((b"x-forwarded-for", client.encode("latin-1")))
    out.append((b"x-forwarded-proto", scheme.encode("latin-1")))
    out.append((b"x-forwarded-host", client_host))
    out.append((b"x-forwarded-prefix", prefix.encode("latin-1")))
    return out


def response_headers(headers: Headers, base_url: str, gateway_prefix: str) -> Headers:
    """The service's answer headers as passed back; a Location inside the service is made a
    gateway path, one outside it raises RedirectRefused."""
    extra_drop = _listed_in_connection(headers)
    out: Headers = []
    for name, value in headers:
        lower = name.lower()
        if lower in _RESPONSE_DROP or lower in extra_drop:
            continue
        if lower == b"location":
            value = _location(value.decode("latin-1"), base_url, gateway_prefix).encode("latin-1")
        out.append((lower, value))
    return out


def _location(location: str, base_url: str, gateway_prefix: str) -> str:
    base = urlsplit(base_url)
    loc = urlsplit(location)
    if _dot_segments(loc.path):
        raise RedirectRefused("the service redirected with '.' or '..' in the path")
    if not loc.scheme and not loc.netloc and not location.startswith("/"):
        return location  # relative to the current path, without dot segments: below the service
    same = (loc.scheme or base.scheme, loc.netloc.lower()) == (base.scheme, base.netloc.lower())
    if loc.netloc and not same:
        raise RedirectRefused(f"the service redirected to another host ({loc.netloc})")
    path = loc.path or "/"
    if not path.startswith(base.path):
        raise RedirectRefused("the service redirected outside its base URL")
    rewritten = f"{gateway_prefix}/{path[len(base.path) :]}"
    return rewritten + (f"?{loc.query}" if loc.query else "")


def _dot_segments(path: str) -> bool:
    return any(unquote(p) in (".", "..") for p in path.split("/"))


def content_length(headers: Headers) -> int | None:
    for name, value in headers:
        if name == b"content-length":
            try:
                return int(value)
            except ValueError:
                return None
    return None
