"""One gateway request: the ASGI types, what the audit log records about it, and the
problem answers (RFC 9457) the gateway gives itself."""

from __future__ import annotations

import time
from collections.abc import Awaitable, Callable, MutableMapping
from typing import Any

import orjson

from twinlink.domain.errors import TwinlinkError, problem_document
from twinlink.domain.records import AuditEntry

Scope = MutableMapping[str, Any]
Message = MutableMapping[str, Any]
Receive = Callable[[], Awaitable[Message]]
Send = Callable[[Message], Awaitable[None]]
ASGIApp = Callable[[Scope, Receive, Send], Awaitable[None]]


class GatewayProblem(TwinlinkError):
    """An answer the gateway gives instead of the service's, with a status of its own.
    `outcome` names it in the audit log; `sent` is set when nothing can be sent any more (the
    client left, or the service's answer had started). The gateway sends it itself (it runs
    in front of the API's routes), as the API would: the same problem document, plus where
    it comes from."""

    def __init__(
        self,
        status: int,
        detail: str,
        outcome: str | None = None,
        headers: list[tuple[bytes, bytes]] | None = None,
        sent: bool = False,
    ) -> None:
        super().__init__(detail)
        self.status = status
        self.detail = detail
        self.outcome = outcome or ("refused" if status < 500 else "failed")
        self.headers = headers or []
        self.sent = sent

    def problem_extensions(self) -> dict[str, Any]:
        # `source`: not the service, the gateway gave this answer itself.
        return {"source": "gateway", "code": self.outcome}

    def problem_headers(self) -> dict[str, str]:
        return {name.decode("latin-1"): value.decode("latin-1") for name, value in self.headers}


def problem_body(problem: GatewayProblem) -> tuple[bytes, list[tuple[bytes, bytes]]]:
    body = orjson.dumps(problem_document(problem))
    headers = [
        (b"content-type", b"application/problem+json"),
        (b"content-length", str(len(body)).encode()),
        *problem.headers,
    ]
    if problem.status == 401:
        headers.append((b"www-authenticate", b'Bearer realm="twinlink"'))
    return body, headers


async def send_problem(send: Send, problem: GatewayProblem) -> None:
    body, headers = problem_body(problem)
    await send({"type": "http.response.start", "status": problem.status, "headers": headers})
    await send({"type": "http.response.body", "body": body})


class Exchange:
    """What the audit log records about one request."""

    __slots__ = (
        "bytes_in",
        "bytes_out",
        "caller",
        "method",
        "outcome",
        "path",
        "service",
        "started",
        "status",
        "twin",
        "upstream_s",
    )

    def __init__(self, method: str, path: str) -> None:
        self.started = time.perf_counter()
        self.caller = "-"
        self.twin = ""
        self.service = ""
        self.method = method
        self.path = path
        self.status = 0
        self.outcome = "refused"
        self.bytes_in = 0
        self.bytes_out = 0
        self.upstream_s: float | None = None

    def entry(self) -> AuditEntry:
        return AuditEntry(
            time_ns=time.time_ns(),
            twin=self.twin,
            service=self.service,
            caller=self.caller,
            method=self.method,
            path=self.path,
            status=self.status,
            outcome=self.outcome,
            bytes_in=self.bytes_in,
            bytes_out=self.bytes_out,
            upstream_ms=None if self.upstream_s is None else self.upstream_s * 1000,
            total_ms=(time.perf_counter() - self.started) * 1000,
        )
