"""Errors of the domain layer, each carrying what a person needs to fix the input.

`TwinlinkError` is the base of every error the platform raises for a person to read. It
carries the answer it becomes: its HTTP `status` and RFC 9457 `problem_type`, and the
`problem_*` methods for the rest of the answer. So the API answers the whole family with one
handler (api/problems.py), the gateway answers its own refusals the same way (gateway/
exchange.py), and a new error needs no handler of its own. The classes here are the common
ones; a component defines its own beside its code, derived from these or from TwinlinkError.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

# Each status's title in a problem answer: with the type about:blank, the title is the
# status's name (RFC 9457, 4.2.1). 499, 502 and 504 are answered only by the gateway.
TITLES = {
    400: "Bad request",
    401: "Unauthorized",
    403: "Forbidden",
    404: "Not found",
    405: "Method not allowed",
    409: "Conflict",
    413: "Content too large",
    415: "Unsupported media type",
    422: "Unprocessable content",
    499: "Client closed request",
    500: "Internal error",
    502: "Bad gateway",
    503: "Service unavailable",
    504: "Gateway timeout",
    507: "Insufficient storage",
}
# A client told that storage failed tries again after this long (Retry-After): long enough
# for an administrator to notice, short enough that nothing waits needlessly once fixed.
STORAGE_RETRY_AFTER_S = 30
# The same for the bus between nodes (Kafka): a broker restart takes seconds, not minutes.
UNAVAILABLE_RETRY_AFTER_S = 5


def title_of(status: int) -> str:
    return TITLES.get(status, "Error")


class TwinlinkError(Exception):
    """The base of twinlink's errors. `status` is the HTTP status of the answer it becomes
    (the class's, or an instance's own), `problem_type` its RFC 9457 type: about:blank, as
    the status says what went wrong and `detail` what to change.

    An error without an answer of its own (the CLI's, a connector's, one its component turns
    into another) keeps status 500: reaching the API it is a bug, logged with its traceback
    and answered as an internal error, its message kept from the client."""

    status: int = 500
    problem_type: str = "about:blank"

    def problem_detail(self) -> str:
        """The answer's `detail`: what went wrong and what to change, for a person."""
        return str(self)

    def problem_extensions(self) -> dict[str, Any]:
        """Members the answer has after `detail` (RFC 9457 extension members)."""
        return {}

    def problem_headers(self) -> dict[str, str]:
        """Headers the answer comes with (Retry-After, Allow, ...)."""
        return {}


def problem_document(err: TwinlinkError) -> dict[str, Any]:
    """The problem+json body of the answer `err` becomes."""
    return {
        "type": err.problem_type,
        "title": title_of(err.status),
        "status": err.status,
        "detail": err.problem_detail(),
        **err.problem_extensions(),
    }


@dataclass(frozen=True, slots=True)
class Problem:
    """One problem found in a document: where it is and what is wrong."""

    message: str
    path: str = ""
    line: int | None = None
    column: int | None = None
    document: int | None = None  # index in a multi-document YAML stream, from 0

    def as_dict(self) -> dict[str, object]:
        out: dict[str, object] = {"message": self.message, "path": self.path}
        if self.line is not None:
            out["line"] = self.line
            out["column"] = self.column
        if self.document is not None:
            out["document"] = self.document
        return out

    def __str__(self) -> str:
        where = f"line {self.line}, column {self.column}: " if self.line is not None else ""
        path = f"{self.path}: " if self.path else ""
        return f"{where}{path}{self.message}"


class NotFoundError(TwinlinkError, LookupError):
    """The thing asked for does not exist (or the caller may not know that it does)."""

    status = 404

    def problem_detail(self) -> str:
        return str(self.args[0]) if self.args else "not found"


class ForbiddenError(TwinlinkError):
    """A known caller without the right for this action."""

    status = 403


class ConflictError(TwinlinkError):
    """The request contradicts the current state (a cycle, existing children, a taken name)."""

    status = 409


class WriteConflictError(ConflictError):
    """The store refused a write that contradicts what it holds (a name taken by a request
    that ran at the same time): services check for conflicts first, this is the safety net
    for a race between two of them. Sending the request again gets the right answer."""

    ANSWER = "The change conflicts with the current state; retry it."

    def __init__(self, message: str = ANSWER):
        super().__init__(message)

    def problem_detail(self) -> str:
        return self.ANSWER  # the store's words are for the log, not for the client


class InvalidInputError(TwinlinkError, ValueError):
    """A request that cannot be used as sent; the message says what to change. A ValueError
    too: code that checks values catches it as one."""

    status = 422


@dataclass(slots=True)
class DocumentError(TwinlinkError):
    """A document was refused; `problems` lists every problem found, not only the first."""

    title: str
    problems: list[Problem] = field(default_factory=list)
    status = 422

    def __str__(self) -> str:
        lines = [self.title, *(f"  - {p}" for p in self.problems)]
        return "\n".join(lines)

    def problem_detail(self) -> str:
        first = self.problems[0] if self.problems else None
        return self.title if first is None else f"{self.title} First: {first}"

    def problem_extensions(self) -> dict[str, Any]:
        return {"errors": [p.as_dict() for p in self.problems]}


class ContentTooLargeError(TwinlinkError):
    """A request body over a configured size limit: a document, a batch, an upload."""

    status = 413


class DocumentTooLargeError(ContentTooLargeError, DocumentError):
    """A document or batch over its size limit; answered as a refused document (`errors`)."""


class PayloadTooLargeError(ContentTooLargeError, InvalidInputError):
    """An upload over its size limit (an FMU's, say)."""


class StorageError(TwinlinkError):
    """The disk under the store failed a write: nothing of the request was stored, and the
    same request may succeed later (Retry-After)."""

    status = 503

    def problem_headers(self) -> dict[str, str]:
        # Counted and logged (once a minute) where it happened, in the store: the answer
        # only says when to try again.
        return {"Retry-After": str(STORAGE_RETRY_AFTER_S)}


class UnavailableError(TwinlinkError):
    """A service the request needs besides the store (the bus between nodes) cannot be
    reached or did not answer in time: the same request may succeed later (Retry-After)."""

    status = 503

    def problem_headers(self) -> dict[str, str]:
        return {"Retry-After": str(UNAVAILABLE_RETRY_AFTER_S)}


class StorageFullError(StorageError):
    """The disk under the store is full: nothing of the request was stored, and nothing will
    be until space is freed."""

    status = 507


class TooManySignalsError(InvalidInputError):
    """A batch would give its stream more distinct signals than the configured limit; nothing
    of the batch was stored."""
