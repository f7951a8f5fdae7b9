"""The one error of the client: the server refused a request, or could not be reached."""

from __future__ import annotations

from typing import Any

import httpx


class ApiError(Exception):
    """A refused or failed API call. `status` is the HTTP status (None when the server was not
    reached), `problem` the server's RFC 9457 problem+json answer when it sent one, and
    `detail` its detail: what to change. str() is the whole explanation, for a person.

    Not a TwinlinkError: the client imports nothing else of twinlink (the layers contract),
    and it is an error of a caller, never an answer of the server's."""

    def __init__(
        self, message: str, status: int | None = None, problem: dict[str, Any] | None = None
    ) -> None:
        super().__init__(message)
        self.status = status
        self.problem = problem or {}

    @property
    def detail(self) -> str:
        return str(self.problem.get("detail") or self)

    @classmethod
    def from_response(cls, response: httpx.Response) -> ApiError:
        """The refusal in `response` (its body read) as an ApiError."""
        problem = _problem(response)
        return cls(
            explain(response.status_code, problem, response.text), response.status_code, problem
        )


def _problem(response: httpx.Response) -> dict[str, Any] | None:
    try:
        body = response.json()
    except ValueError:
        return None
    return body if isinstance(body, dict) else None


def explain(status: int, problem: dict[str, Any] | None, text: str = "") -> str:
    """A refusal as a person reads it: title, detail, and each error the problem lists."""
    if problem is None:
        return f"HTTP {status}: {text[:300]}"
    lines = [f"{problem.get('title', 'Error')} ({status}): {problem.get('detail', '')}"]
    for e in problem.get("errors") or []:
        if isinstance(e, dict):
            path = f"{e['path']}: " if e.get("path") else ""
            lines.append(f"  - {path}{e.get('message', '')}")
    if status == 401:
        lines.append("  Pass a valid token: Client(token=...) or TWINLINK_TOKEN.")
    return "\n".join(lines)
