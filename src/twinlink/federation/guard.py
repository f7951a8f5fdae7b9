"""The SSRF guard: which URLs twinlink fetches on a document's say-so (docs/federation.md
"Security").

A relation's dt-id is written by whoever wrote the document, so fetching it must not become
a way to reach what only the server can reach: its loopback, the private network, the cloud
metadata service. Every address a host name resolves to is checked (one bad address refuses
the name: DNS answers rotate), and the fetcher connects to a checked address itself, so a
second lookup cannot answer differently (DNS rebinding).
"""

from __future__ import annotations

import asyncio
import ipaddress
import socket
from collections.abc import Iterable
from dataclasses import dataclass
from urllib.parse import urlsplit

from twinlink.domain.errors import InvalidInputError, TwinlinkError

IPAddress = ipaddress.IPv4Address | ipaddress.IPv6Address
_SCHEMES = {"http": 80, "https": 443}
# Ranges named in refusals; anything else not globally routable is refused as "reserved".
_RANGES: tuple[tuple[str, str], ...] = (
    ("0.0.0.0/8", "unspecified"),
    ("127.0.0.0/8", "loopback"),
    ("10.0.0.0/8", "private"),
    ("172.16.0.0/12", "private"),
    ("192.168.0.0/16", "private"),
    ("100.64.0.0/10", "carrier-grade NAT"),
    ("169.254.0.0/16", "link-local (cloud metadata)"),
    ("224.0.0.0/4", "multicast"),
    ("::/128", "unspecified"),
    ("::1/128", "loopback"),
    ("::ffff:0:0/96", "IPv4-mapped IPv6"),
    ("fc00::/7", "private"),
    ("fe80::/10", "link-local"),
    ("ff00::/8", "multicast"),
)
_NETWORKS = [(ipaddress.ip_network(net), why) for net, why in _RANGES]
# Never fetched, not even with allow_private: no service of anyone's lives there.
_NEVER = {"unspecified", "multicast"}


class FetchRefused(InvalidInputError):
    """A URL the guard will not fetch: its scheme, its host, or an address it resolves to."""


class FetchFailed(TwinlinkError):
    """The other instance could not be read: unreachable, too slow, too large, a redirect
    loop, an error status or not a document. `remote_status` is the status it answered, if
    it answered one (404 and 410 mean the document is gone)."""

    status = 502

    def __init__(self, message: str, remote_status: int | None = None) -> None:
        super().__init__(message)
        self.remote_status = remote_status


@dataclass(frozen=True)
class FetchPolicy:
    hosts: tuple[str, ...] = ("*",)  # allowed host patterns ("*" = any public host, "*.x.org")
    allow_private: bool = False  # loopback, private, link-local, CGNAT, metadata ranges
    max_hops: int = 5  # redirects followed
    max_bytes: int = 1_048_576
    timeout_s: float = 5.0


@dataclass(frozen=True, slots=True)
class Target:
    """A checked URL: where to connect (`addresses`, every one allowed) and what to ask."""

    url: str
    scheme: str
    host: str  # lower case, no trailing dot, IPv6 without brackets
    port: int
    addresses: tuple[str, ...]

    @property
    def origin(self) -> str:
        """scheme://host[:port], the port only when not the scheme's default."""
        host = f"[{self.host}]" if ":" in self.host else self.host
        default = _SCHEMES[self.scheme]
        return f"{self.scheme}://{host}" + ("" if self.port == default else f":{self.port}")


def origin_of(url: str) -> str:
    """The origin of `url` as `Target.origin` writes it (for keying peers' tokens)."""
    scheme, host, port = _split(url)
    return Target(url, scheme, host, port, ()).origin


def _split(url: str) -> tuple[str, str, int]:
    try:
        parts = urlsplit(url.strip())
        port = parts.port
    except ValueError as err:
        raise FetchRefused(f"{url!r} is not a URL: {err}") from err
    scheme = parts.scheme.lower()
    if scheme not in _SCHEMES:
        raise FetchRefused(
            f"{url!r}: only http and https URLs are fetched, not {scheme or 'a relative URL'}"
        )
    host = (parts.hostname or "").rstrip(".").lower()
    if not host:
        raise FetchRefused(f"{url!r} names no host")
    if parts.username is not None or parts.password is not None:
        raise FetchRefused(f"{url!r}: URLs with credentials in them are not fetched")
    return scheme, host, port if port is not None else _SCHEMES[scheme]


def host_allowed(host: str, patterns: Iterable[str]) -> bool:
    """`*` allows any host, `*.x.org` x.org and every name under it, anything else itself."""
    for pattern in patterns:
        p = pattern.strip().rstrip(".").lower()
        if p == "*" or p == host:
            return True
        if p.startswith("*.") and (host == p[2:] or host.endswith(p[1:])):
            return True
    return False


def address_problem(address: str, allow_private: bool) -> str | None:
    """Why `address` may not be connected to (the range's name), or None."""
    try:
        ip: IPAddress = ipaddress.ip_address(address.split("%", 1)[0])
    except ValueError:
        return "not an IP address"
    embedded = _embedded_ipv4(ip)
    if embedded is not None:  # NAT64 and 6to4 reach the IPv4 address inside: check that
        why = address_problem(str(embedded), allow_private)
        return None if why is None else f"{why} (inside {ip})"
    for net, why in _NETWORKS:
        if ip.version == net.version and ip in net:
            return None if allow_private and why not in _NEVER else why
    if not ip.is_global and not allow_private:
        return "reserved"
    return None


_NAT64 = ipaddress.ip_network("64:ff9b::/96")


def _embedded_ipv4(ip: IPAddress) -> ipaddress.IPv4Address | None:
    if not isinstance(ip, ipaddress.IPv6Address):
        return None
    if ip in _NAT64:
        return ipaddress.IPv4Address(int(ip) & 0xFFFFFFFF)
    return ip.sixtofour


def _checked(url: str, policy: FetchPolicy) -> tuple[str, str, int]:
    scheme, host, port = _split(url)
    if not host_allowed(host, policy.hosts):
        raise FetchRefused(
            f"{url!r}: the host {host} is not in TWINLINK_FEDERATION_HOSTS"
            f" ({', '.join(policy.hosts) or 'empty: nothing is fetched'})"
        )
    return scheme, host, port


def _target(
    url: str, policy: FetchPolicy, scheme: str, host: str, port: int, addresses: list[str]
) -> Target:
    if not addresses:
        raise FetchFailed(f"{url!r}: the host {host} has no address")
    for address in addresses:
        why = address_problem(address, policy.allow_private)
        if why is not None:
            raise FetchRefused(
                f"{url!r}: {host} resolves to {address}, a {why} address; such addresses are "
                "fetched only with TWINLINK_FEDERATION_ALLOW_PRIVATE=true"
            )
    return Target(url, scheme, host, port, tuple(dict.fromkeys(addresses)))


def _literal(host: str) -> list[str] | None:
    try:
        return [str(ipaddress.ip_address(host))]
    except ValueError:
        return None


def check_url(url: str, policy: FetchPolicy) -> None:
    """Refuse (FetchRefused) a URL the policy does not allow; resolves the host (blocking).
    The fetcher uses `resolve`, which returns the checked addresses to connect to."""
    scheme, host, port = _checked(url, policy)
    addresses = _literal(host)
    if addresses is None:
        try:
            infos = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)
        except OSError as err:
            raise FetchFailed(f"{url!r}: the host {host} cannot be resolved: {err}") from err
        addresses = [str(info[4][0]) for info in infos]
    _target(url, policy, scheme, host, port, addresses)


async def resolve(url: str, policy: FetchPolicy) -> Target:
    """Check `url` and resolve its host once; connect only to the returned addresses."""
    scheme, host, port = _checked(url, policy)
    addresses = _literal(host)
    if addresses is None:
        try:
            infos = await asyncio.get_running_loop().getaddrinfo(
                host, port, type=socket.SOCK_STREAM
            )
        except OSError as err:
            raise FetchFailed(f"{url!r}: the host {host} cannot be resolved: {err}") from err
        addresses = [str(info[4][0]) for info in infos]
    return _target(url, policy, scheme, host, port, addresses)
