"""Errors of the domain layer, each carrying what a person needs to fix the input."""

from __future__ import annotations

from dataclasses import dataclass, field


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


@dataclass(slots=True)
class DocumentError(Exception):
    """A document was refused; `problems` lists every problem found, not only the first."""

    title: str
    problems: list[Problem] = field(default_factory=list)

    def __str__(self) -> str:
        lines = [self.title, *(f"  - {p}" for p in self.problems)]
        return "\n".join(lines)


class DocumentTooLargeError(DocumentError):
    """The request body is over the configured size limit (HTTP 413)."""


class NotFoundError(LookupError):
    """The thing asked for does not exist (or the caller may not know that it does)."""


class ForbiddenError(Exception):
    """A known caller without the right for this action (HTTP 403)."""


class ConflictError(Exception):
    """The request contradicts the current state (a cycle, existing children, a taken name)."""


class WriteConflictError(ConflictError):
    """The store refused a write that contradicts what it holds (a name taken by a request
    that ran at the same time): services check for conflicts first, this is the safety net
    for a race between two of them. Sending the request again gets the right answer."""

    def __init__(self, message: str = "The change conflicts with the current state; retry it."):
        super().__init__(message)


class InvalidInputError(ValueError):
    """A request that cannot be used as sent (HTTP 422); the message says what to change."""


class PayloadTooLargeError(InvalidInputError):
    """A request body over a configured size limit (HTTP 413)."""


class StorageError(Exception):
    """The disk under the store failed a write (HTTP 503): nothing of the request was stored,
    and the same request may succeed later."""


class StorageFullError(StorageError):
    """The disk under the store is full (HTTP 507): nothing of the request was stored until
    space is freed."""


class TooManySignalsError(InvalidInputError):
    """A batch would give its stream more distinct signals than the configured limit (HTTP
    422); nothing of the batch was stored."""
