"""One exception base: every error of the platform is a TwinlinkError carrying the answer it
becomes (HTTP status, RFC 9457 type), and the API answers the whole family with one handler
(api/problems.py): problem+json with the error's status, detail, members and headers. An
error without an answer of its own (status 500), and any other exception, is a bug: logged
with its traceback, answered as an internal error that shows nothing of it."""

from __future__ import annotations

import importlib
import inspect
import logging
import pkgutil
from dataclasses import dataclass, field
from typing import Any

import httpx
import pytest
from fastapi import FastAPI

import twinlink
from twinlink.api.problems import install
from twinlink.auth.service import AuthError, LoginError, ScopeError
from twinlink.bus.kafka.bus import KafkaBusError
from twinlink.bus.kafka.codec import UnencodableMessageError
from twinlink.commands.targets import DeviceChoiceError
from twinlink.cosim.model import CosimFormatError
from twinlink.cosim.slaves import CosimRunError
from twinlink.domain.errors import (
    ConflictError,
    ContentTooLargeError,
    DocumentError,
    DocumentTooLargeError,
    ForbiddenError,
    InvalidInputError,
    NotFoundError,
    PayloadTooLargeError,
    Problem,
    StorageError,
    StorageFullError,
    TooManySignalsError,
    TwinlinkError,
    UnavailableError,
    WriteConflictError,
)
from twinlink.domain.history import (
    QueryTimeoutError,
    QueryTooLargeError,
    ReadBudgetError,
    ReadCancelledError,
)
from twinlink.domain.jsontext import JsonTextError
from twinlink.domain.samples import BatchError
from twinlink.federation.guard import FetchFailed, FetchRefused
from twinlink.gateway.exchange import GatewayProblem, problem_body
from twinlink.history.params import QueryError
from twinlink.live.protocol import LiveMessageError

PROBLEM = "application/problem+json"
# The exceptions that stay outside the family, each for a reason given where it is defined:
# control flow inside one component, never shown to a person as an error of its own.
PLAIN = {
    "twinlink.api.live._Gone",
    "twinlink.client.errors.ApiError",
    "twinlink.cli.cosimapi.FileError",  # click's own error: one line and exit 2, never HTTP
    "twinlink.cosim.slaves.FmuTerminated",
    "twinlink.cosim.ssp._Refused",
    "twinlink.bus.kafka.codec.UndecodableRecordError",
    "twinlink.domain.yamlsource._IntTooLong",
    "twinlink.domain.yamlsource._TooLarge",
    "twinlink.ingest.mqtt._wire.MalformedPacket",
    "twinlink.ingest.mqtt.packets.ProtocolViolation",
    "twinlink.processors.blueprints._fmu_fmi.Terminated",
    "twinlink.processors.fmuenv.EnvBuildError",
    "twinlink.processors.wire.ChannelClosed",
    "twinlink.store.postgres.history.group._Stale",
}


def _exception_classes() -> dict[str, type[BaseException]]:
    """Every exception class twinlink defines, by its full name (each module imported)."""
    found: dict[str, type[BaseException]] = {}
    for module in pkgutil.walk_packages(twinlink.__path__, "twinlink."):
        if module.name.endswith("__main__"):
            continue  # runs the CLI
        loaded = importlib.import_module(module.name)
        for value in vars(loaded).values():
            if (
                inspect.isclass(value)
                and issubclass(value, BaseException)
                and value.__module__ == loaded.__name__
            ):
                found[f"{value.__module__}.{value.__qualname__}"] = value
    return found


CLASSES = _exception_classes()
ERRORS = [cls for cls in CLASSES.values() if issubclass(cls, TwinlinkError)]


def test_every_exception_of_twinlink_is_a_twinlink_error_or_says_why_not() -> None:
    plain = {name for name, cls in CLASSES.items() if not issubclass(cls, TwinlinkError)}
    assert plain == PLAIN
    assert len(ERRORS) > 40  # the walk found the modules


@pytest.mark.parametrize("cls", ERRORS, ids=lambda cls: cls.__qualname__)
def test_every_twinlink_error_has_a_status_and_a_problem_type(cls: type[TwinlinkError]) -> None:
    assert isinstance(cls.status, int) and 400 <= cls.status <= 599
    assert cls.problem_type == "about:blank"


def test_the_standard_bases_stay_where_code_catches_them() -> None:
    """`except ValueError` and `except LookupError` sites keep catching what they caught."""
    assert issubclass(InvalidInputError, ValueError) and issubclass(NotFoundError, LookupError)
    assert issubclass(PayloadTooLargeError, InvalidInputError)
    assert issubclass(DocumentTooLargeError, DocumentError)
    for cls in (QueryError, LiveMessageError, ContentTooLargeError):
        assert issubclass(cls, TwinlinkError)
    assert issubclass(LiveMessageError, ValueError) and issubclass(QueryError, ValueError)


def test_the_two_too_large_errors_are_one_family() -> None:
    for cls in (DocumentTooLargeError, PayloadTooLargeError):
        assert issubclass(cls, ContentTooLargeError) and cls.status == 413


# -- the one handler ---------------------------------------------------------------------------


@dataclass
class Case:
    error: Exception
    status: int
    detail: str
    members: dict[str, Any] = field(default_factory=dict)
    headers: dict[str, str] = field(default_factory=dict)


TITLES = {
    401: "Unauthorized",
    403: "Forbidden",
    404: "Not found",
    405: "Method not allowed",
    409: "Conflict",
    413: "Content too large",
    422: "Unprocessable content",
    502: "Bad gateway",
    503: "Service unavailable",
    507: "Insufficient storage",
}
BEARER = {"www-authenticate": 'Bearer realm="twinlink"'}
RETRY = {"retry-after": "30"}
BUS_RETRY = {"retry-after": "5"}  # a broker restart takes seconds
CASES = [
    Case(NotFoundError("no twin 'crane'"), 404, "no twin 'crane'"),
    Case(NotFoundError(), 404, "not found"),
    Case(ForbiddenError("needs the editor role"), 403, "needs the editor role"),
    Case(ConflictError("the name is taken"), 409, "the name is taken"),
    Case(
        WriteConflictError("UNIQUE constraint failed: twins.slug"),
        409,
        "The change conflicts with the current state; retry it.",
    ),
    Case(InvalidInputError("`limit` must be positive"), 422, "`limit` must be positive"),
    Case(BatchError("the body is not JSON"), 422, "the body is not JSON"),
    Case(
        JsonTextError("unexpected character", 2, 5), 422, "unexpected character (line 2, column 5)"
    ),
    Case(TooManySignalsError("over 1000 signals"), 422, "over 1000 signals"),
    Case(
        DeviceChoiceError("the twin has several devices (a, b)", ["a", "b"]),
        422,
        "the twin has several devices (a, b); name one with `device`",
        {"reason": "the twin has several devices (a, b)", "devices": ["a", "b"]},
    ),
    Case(
        DocumentError("The DT document has problems.", [Problem("not a number", "a.b", 3, 4)]),
        422,
        "The DT document has problems. First: line 3, column 4: a.b: not a number",
        {"errors": [{"message": "not a number", "path": "a.b", "line": 3, "column": 4}]},
    ),
    Case(DocumentError("The document is empty."), 422, "The document is empty.", {"errors": []}),
    Case(ContentTooLargeError("over the limit"), 413, "over the limit"),
    Case(
        DocumentTooLargeError("A batch is at most 8 bytes."),
        413,
        "A batch is at most 8 bytes.",
        {"errors": []},
    ),
    Case(PayloadTooLargeError("the FMU is over 1 MB"), 413, "the FMU is over 1 MB"),
    Case(StorageError("the disk failed; retry"), 503, "the disk failed; retry", headers=RETRY),
    Case(StorageFullError("the disk is full"), 507, "the disk is full", headers=RETRY),
    Case(
        AuthError("the token has expired"),
        401,
        "the token has expired. Send a valid token as 'Authorization: Bearer <token>'.",
        headers=BEARER,
    ),
    Case(
        LoginError("wrong username or password"), 401, "wrong username or password.", headers=BEARER
    ),
    Case(
        ScopeError("this token is scoped to twin 'rig'"), 403, "this token is scoped to twin 'rig'."
    ),
    Case(QueryError("`start` is not a time"), 422, "`start` is not a time"),
    Case(ReadBudgetError("the read stopped"), 503, "the read stopped"),
    Case(QueryTooLargeError("narrow the query"), 422, "narrow the query"),
    Case(QueryTimeoutError("over 10 s"), 503, "over 10 s"),
    Case(ReadCancelledError("the server is shutting down"), 503, "the server is shutting down"),
    Case(LiveMessageError("a message needs an op"), 422, "a message needs an op"),
    Case(
        UnavailableError("the bus is away; retry"), 503, "the bus is away; retry", headers=BUS_RETRY
    ),
    Case(
        KafkaBusError("Kafka cannot be reached; retry"),
        503,
        "Kafka cannot be reached; retry",
        headers=BUS_RETRY,
    ),
    Case(UnencodableMessageError("no form for a set"), 422, "no form for a set"),
    Case(
        FetchRefused("'http://10.0.0.1/': a private address"),
        422,
        "'http://10.0.0.1/': a private address",
    ),
    Case(FetchFailed("'https://x.org/t' answered 500", 500), 502, "'https://x.org/t' answered 500"),
    Case(CosimFormatError("mm.json: fmus is not a map"), 422, "mm.json: fmus is not a map"),
    Case(CosimRunError("msd1.m1 (mass.fmu) failed"), 422, "msd1.m1 (mass.fmu) failed"),
    Case(
        GatewayProblem(405, "the service 'x' allows GET", headers=[(b"allow", b"GET")]),
        405,
        "the service 'x' allows GET",
        {"source": "gateway", "code": "refused"},
        {"allow": "GET"},
    ),
]


def test_every_error_with_an_answer_of_its_own_is_checked_here() -> None:
    answered = {cls for cls in ERRORS if cls.status != 500}
    assert answered <= {type(case.error) for case in CASES}


def app_raising(error: BaseException) -> FastAPI:
    app = FastAPI()
    install(app)

    @app.get("/fail")
    async def fail() -> None:
        raise error

    return app


async def answer_to(error: BaseException) -> httpx.Response:
    # The app's exceptions are answered, not raised here, as a server would.
    transport = httpx.ASGITransport(app_raising(error), raise_app_exceptions=False)
    async with httpx.AsyncClient(transport=transport, base_url="http://twinlink") as client:
        return await client.get("/fail")


def test_the_api_has_one_handler_for_the_family() -> None:
    app = FastAPI()
    install(app)
    handled = [k for k in app.exception_handlers if isinstance(k, type)]
    assert [k for k in handled if issubclass(k, TwinlinkError)] == [TwinlinkError]


@pytest.mark.parametrize("case", CASES, ids=lambda case: type(case.error).__name__)
async def test_the_handler_answers_each_error_as_a_problem(case: Case) -> None:
    r = await answer_to(case.error)
    assert r.status_code == case.status
    assert r.headers["content-type"] == PROBLEM
    assert r.json() == {
        "type": "about:blank",
        "title": TITLES[case.status],
        "status": case.status,
        "detail": case.detail,
        **case.members,
    }
    for name, value in case.headers.items():
        assert r.headers[name] == value
    if case.status != 401:
        assert "www-authenticate" not in r.headers
    if case.status not in (503, 507):
        assert "retry-after" not in r.headers


async def test_a_write_conflict_is_logged_once_answered(caplog: pytest.LogCaptureFixture) -> None:
    with caplog.at_level(logging.WARNING, "twinlink.api"):
        r = await answer_to(WriteConflictError("UNIQUE constraint failed: twins.slug"))
    assert r.status_code == 409 and "UNIQUE" not in r.text
    [record] = [r for r in caplog.records if r.name == "twinlink.api"]
    assert record.getMessage() == "store refused a write" and record.path == "/fail"  # type: ignore[attr-defined]


INTERNAL = sorted((cls for cls in ERRORS if cls.status == 500), key=lambda cls: cls.__name__)


@pytest.mark.parametrize(
    "error",
    [
        RuntimeError("secret detail of a bug"),
        *(c.__new__(c, "secret detail of a bug") for c in INTERNAL),
    ],
    ids=lambda error: type(error).__name__,
)
async def test_anything_else_is_an_internal_error_that_shows_nothing_of_it(
    error: BaseException, caplog: pytest.LogCaptureFixture
) -> None:
    """A plain exception, or a TwinlinkError without an answer of its own that reached the
    API: a 500 problem without the message or a traceback, the traceback in the log."""
    with caplog.at_level(logging.ERROR, "twinlink.api"):
        r = await answer_to(error)
    assert r.status_code == 500 and r.headers["content-type"] == PROBLEM
    assert r.json() == {
        "type": "about:blank",
        "title": "Internal error",
        "status": 500,
        "detail": "An internal error occurred; it has been logged.",
    }
    assert "secret" not in r.text and "Traceback" not in r.text
    [record] = [r for r in caplog.records if r.name == "twinlink.api"]
    assert record.getMessage() == "unhandled error" and record.exc_info is not None
    assert record.exc_info[1] is error


def test_the_gateway_answers_its_own_problems_as_the_api_does() -> None:
    body, headers = problem_body(GatewayProblem(401, "a token is required"))
    assert httpx.Response(200, content=body).json() == {
        "type": "about:blank",
        "title": "Unauthorized",
        "status": 401,
        "detail": "a token is required",
        "source": "gateway",
        "code": "refused",
    }
    assert (b"content-type", PROBLEM.encode()) in headers
    assert (b"www-authenticate", b'Bearer realm="twinlink"') in headers
    gone, _ = problem_body(GatewayProblem(502, "the service broke off", outcome="upstream_send"))
    assert b'"title":"Bad gateway"' in gone and b'"code":"upstream_send"' in gone
