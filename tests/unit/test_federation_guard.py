"""The SSRF guard (federation/guard.py, docs/federation.md "Security"): schemes, hosts
allowed, and every address a name resolves to checked against the ranges only the server
can reach, unless TWINLINK_FEDERATION_ALLOW_PRIVATE."""

from __future__ import annotations

import asyncio
import re
import socket
from typing import Any

import pytest

from twinlink.federation import guard
from twinlink.federation.guard import (
    FetchPolicy,
    FetchRefused,
    address_problem,
    check_url,
    host_allowed,
    origin_of,
    resolve,
)

OPEN = FetchPolicy(hosts=("*",), allow_private=False)
PRIVATE_OK = FetchPolicy(hosts=("*",), allow_private=True)

REFUSED = [
    ("127.0.0.1", "loopback"),
    ("127.8.9.10", "loopback"),
    ("::1", "loopback"),
    ("10.1.2.3", "private"),
    ("172.16.0.1", "private"),
    ("172.31.255.255", "private"),
    ("192.168.1.1", "private"),
    ("fd12:3456::1", "private"),
    ("169.254.169.254", "link-local (cloud metadata)"),
    ("fe80::1", "link-local"),
    ("100.64.0.1", "carrier-grade NAT"),
    ("100.127.255.254", "carrier-grade NAT"),
    ("0.0.0.0", "unspecified"),
    ("::", "unspecified"),
    ("224.0.0.1", "multicast"),
    ("ff02::1", "multicast"),
    ("::ffff:127.0.0.1", "IPv4-mapped IPv6"),
    ("::ffff:8.8.8.8", "IPv4-mapped IPv6"),
    ("64:ff9b::a9fe:a9fe", "link-local (cloud metadata) (inside 64:ff9b::a9fe:a9fe)"),  # NAT64
    ("2002:7f00:1::1", "loopback (inside 2002:7f00:1::1)"),  # 6to4 of 127.0.0.1
    ("192.0.2.1", "reserved"),  # TEST-NET-1: documentation only
    ("240.0.0.1", "reserved"),
]


@pytest.mark.parametrize(("address", "why"), REFUSED)
def test_addresses_only_the_server_can_reach_are_refused(address: str, why: str) -> None:
    assert address_problem(address, allow_private=False) == why


@pytest.mark.parametrize(
    "address", ["8.8.8.8", "1.1.1.1", "2606:4700:4700::1111", "172.32.0.1", "64:ff9b::808:808"]
)
def test_public_addresses_pass(address: str) -> None:
    assert address_problem(address, allow_private=False) is None


def test_allow_private_opens_the_private_ranges_but_never_unspecified_or_multicast() -> None:
    for address in ("127.0.0.1", "::1", "10.0.0.1", "169.254.169.254", "100.64.0.1", "fd00::1"):
        assert address_problem(address, allow_private=True) is None
    for address in ("0.0.0.0", "::", "224.0.0.1", "ff02::1"):
        assert address_problem(address, allow_private=True) in ("unspecified", "multicast")


@pytest.mark.parametrize(
    "url",
    ["file:///etc/passwd", "ftp://x.org/a", "gopher://x.org/", "/twins/a", "javascript:alert(1)"],
)
def test_only_http_and_https_are_fetched(url: str) -> None:
    with pytest.raises(FetchRefused, match="only http and https"):
        check_url(url, OPEN)


def test_a_url_with_credentials_or_without_a_host_is_refused() -> None:
    with pytest.raises(FetchRefused, match="credentials"):
        check_url("https://user:pw@8.8.8.8/", OPEN)
    with pytest.raises(FetchRefused, match="no host"):
        check_url("https:///twins/a", OPEN)
    with pytest.raises(FetchRefused, match="not a URL"):
        check_url("http://[::1/", OPEN)


def test_literal_addresses_are_checked_without_a_lookup() -> None:
    with pytest.raises(FetchRefused, match=re.escape("169.254.169.254, a link-local")):
        check_url("http://169.254.169.254/latest/meta-data/", OPEN)
    with pytest.raises(FetchRefused, match="IPv4-mapped"):
        check_url("http://[::ffff:169.254.169.254]/", OPEN)
    check_url("http://127.0.0.1:8000/twins/a", PRIVATE_OK)
    check_url("https://8.8.8.8/", OPEN)


def test_hosts_allowed_by_pattern() -> None:
    assert host_allowed("twins.example.org", ["*"])
    assert host_allowed("twins.example.org", ["*.example.org"])
    assert host_allowed("example.org", ["*.example.org"])
    assert not host_allowed("badexample.org", ["*.example.org"])
    assert not host_allowed("example.org.evil.net", ["*.example.org"])
    assert host_allowed("example.org", [" Example.ORG. "])
    assert not host_allowed("a.example.org", ["example.org"])
    assert not host_allowed("example.org", [])


def test_a_host_outside_the_list_is_refused_before_any_lookup(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    def no_lookup(*args: Any, **kwargs: Any) -> Any:
        raise AssertionError("looked up")

    monkeypatch.setattr(socket, "getaddrinfo", no_lookup)
    policy = FetchPolicy(hosts=("*.example.org",), allow_private=False)
    with pytest.raises(FetchRefused, match="not in TWINLINK_FEDERATION_HOSTS"):
        check_url("https://evil.net/x", policy)
    with pytest.raises(FetchRefused, match="empty: nothing is fetched"):
        check_url("https://example.org/x", FetchPolicy(hosts=(), allow_private=False))


def _resolving_to(*addresses: str) -> Any:
    def fake(host: str, port: Any, *args: Any, **kwargs: Any) -> list[Any]:
        return [
            (socket.AF_INET6 if ":" in a else socket.AF_INET, socket.SOCK_STREAM, 6, "", (a, port))
            for a in addresses
        ]

    return fake


def test_every_address_a_name_resolves_to_is_checked(monkeypatch: pytest.MonkeyPatch) -> None:
    # One public and one private answer (a DNS name pointed at both): refused, as the
    # connection could go to either.
    monkeypatch.setattr(socket, "getaddrinfo", _resolving_to("93.184.216.34", "10.0.0.5"))
    with pytest.raises(
        FetchRefused, match=re.escape("twins.example.org resolves to 10.0.0.5, a private")
    ):
        check_url("https://twins.example.org/twins/a", OPEN)


async def test_resolve_returns_the_checked_addresses_to_connect_to(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    calls: list[str] = []

    async def fake(host: str, port: Any, **kwargs: Any) -> list[Any]:
        calls.append(host)
        return _resolving_to("93.184.216.34", "2606:2800:220:1::1", "93.184.216.34")(host, port)

    monkeypatch.setattr(asyncio.get_running_loop(), "getaddrinfo", fake)
    target = await resolve("HTTPS://Twins.Example.ORG./twins/a?x=1", OPEN)
    assert target.addresses == ("93.184.216.34", "2606:2800:220:1::1")
    assert (target.scheme, target.host, target.port) == ("https", "twins.example.org", 443)
    assert target.origin == "https://twins.example.org"
    assert calls == ["twins.example.org"]  # looked up once: the fetcher connects to these


async def test_a_name_that_resolves_to_loopback_is_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    # What DNS rebinding would try: a public name whose answer is 127.0.0.1.
    async def fake(host: str, port: Any, **kwargs: Any) -> list[Any]:
        return _resolving_to("127.0.0.1")(host, port)

    monkeypatch.setattr(asyncio.get_running_loop(), "getaddrinfo", fake)
    with pytest.raises(FetchRefused, match=re.escape("127.0.0.1, a loopback address")):
        await resolve("http://rebind.example.net/", OPEN)


def test_origins_are_written_one_way() -> None:
    assert origin_of("HTTPS://Example.org:443/a/b") == "https://example.org"
    assert origin_of("http://example.org:80") == "http://example.org"
    assert origin_of("http://127.0.0.1:8001/twins/x") == "http://127.0.0.1:8001"
    assert origin_of("https://[::1]:8443/") == "https://[::1]:8443"
    assert guard.FetchPolicy().hosts == ("*",) and not guard.FetchPolicy().allow_private
