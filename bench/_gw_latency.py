"""The Data Link paper's Table 1 on this machine: request execution times of GET and POST,
small and large, directly to the test API and through a proxy.

Each route has its own kept-alive connection (http.client, the same client for every route),
and requests are sequential: the next is sent when the whole answer of the last has been
read. The routes take turns request by request (and which one goes first rotates), so a
moment of other work on the machine falls on all of them alike rather than on one route's
whole row. Each route's own connection is still used for one request at a time.
"""

from __future__ import annotations

import gc
import http.client
import os
import socket
import statistics
import time
from dataclasses import dataclass, field
from typing import Any
from urllib.parse import urlsplit

from _gw_cpu import CpuMeter
from _gw_upstream import SMALL


@dataclass(frozen=True)
class Test:
    name: str  # as in the paper: "GET small"
    method: str
    path: str  # below the route's base URL
    body: bytes | None
    expect: bytes  # the whole answer


@dataclass(frozen=True)
class Route:
    name: str  # direct | nginx | gateway
    base: str  # URL ending in "/" that the test's path is appended to
    pids: list[int] = field(default_factory=list)  # the proxy's processes; none for direct


def tests(large: bytes) -> list[Test]:
    """The paper's four tests. POST answers are always the 2 pairs."""
    return [
        Test("GET small", "GET", "small", None, SMALL),
        Test("POST small", "POST", "small", SMALL, SMALL),
        Test("GET large", "GET", "large", None, large),
        Test("POST large", "POST", "large", large, SMALL),
    ]


class _Connection(http.client.HTTPConnection):
    """http.client with Nagle off, as the servers have it: a request's last small segment
    must not wait for the ACK of the one before."""

    def connect(self) -> None:
        super().connect()
        self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)


class Client:
    """One kept-alive connection to a route."""

    def __init__(self, base: str, headers: dict[str, str]) -> None:
        parts = urlsplit(base)
        self.prefix = parts.path
        self.conn = _Connection(parts.hostname or "127.0.0.1", parts.port or 80, timeout=60)
        self.headers = headers
        self.reconnects = 0

    def call(self, method: str, path: str, body: bytes | None) -> tuple[float, int, bytes]:
        """(milliseconds from sending to having read the whole answer, status, body)."""
        headers = self.headers if body is None else {**self.headers, **_JSON}
        start = time.perf_counter()
        self.conn.request(method, self.prefix + path, body=body, headers=headers)
        answer = self.conn.getresponse()
        data = answer.read()
        elapsed = time.perf_counter() - start
        if answer.will_close:
            self.reconnects += 1
        return elapsed * 1000, answer.status, data

    def close(self) -> None:
        self.conn.close()


_JSON = {"Content-Type": "application/json"}


def stats(ms: list[float]) -> dict[str, Any]:
    """The paper's columns (SD is the sample standard deviation), in ms."""
    if not ms:
        return {"n": 0}
    figures = {
        "min": min(ms),
        "max": max(ms),
        "mean": statistics.fmean(ms),
        "median": statistics.median(ms),
        "sd": statistics.stdev(ms) if len(ms) > 1 else 0.0,
    }
    return {"n": len(ms), **{k: round(v, 4) for k, v in figures.items()}}


def table_1(
    cases: list[Test],
    routes: list[Route],
    requests: int,
    warmup: int,
    headers: dict[str, str],
    api_pids: list[int],
) -> list[dict[str, Any]]:
    """One row per test and route: the timing statistics, errors, and the CPU time each
    request cost the proxy (its processes serve only its own route) and the test API (shared
    by all routes, so per request of any route)."""
    rows = []
    for case in cases:
        rows += _run_test(case, routes, requests, warmup, headers, api_pids)
    return rows


def _run_test(
    case: Test,
    routes: list[Route],
    requests: int,
    warmup: int,
    headers: dict[str, str],
    api_pids: list[int],
) -> list[dict[str, Any]]:
    clients = {r.name: Client(r.base, headers) for r in routes}
    times: dict[str, list[float]] = {r.name: [] for r in routes}
    errors: dict[str, list[str]] = {r.name: [] for r in routes}
    groups = {r.name: r.pids for r in routes if r.pids}
    meter = CpuMeter({**groups, "api": api_pids, "client": [os.getpid()]})
    rounds = warmup + requests
    gc.collect()
    gc.disable()  # a collection in the client would count as latency
    try:
        meter.start()
        start = time.perf_counter()
        for i in range(rounds):
            turn = i % len(routes)
            for route in routes[turn:] + routes[:turn]:
                ms, status, data = clients[route.name].call(case.method, case.path, case.body)
                if status != 200 or data != case.expect:
                    errors[route.name].append(f"HTTP {status}: {data[:200]!r}")
                elif i >= warmup:
                    times[route.name].append(ms)
        wall = time.perf_counter() - start
        used = meter.stop()
    finally:
        gc.enable()
        for client in clients.values():
            client.close()
    return [
        {
            "test": case.name,
            "route": r.name,
            **stats(times[r.name]),
            "errors": len(errors[r.name]),
            "first_error": errors[r.name][0] if errors[r.name] else None,
            "reconnects": clients[r.name].reconnects,
            "proxy_cpu_us": round(used[r.name] / rounds / 1000, 1) if r.name in used else None,
            "api_cpu_us": round(used["api"] / (rounds * len(routes)) / 1000, 1),
            "other_cpu_pct": round(100 * used["other"] / 1e9 / wall, 1),
        }
        for r in routes
    ]
