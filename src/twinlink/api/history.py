"""/api/v1/twins/{slug}/streams: a twin's stored telemetry (anyone with a role on the twin).

Times in answers are integers, ns since the epoch. `start` and `end` accept ISO 8601, integer
ns, `now` or a time back from now (`-1h`); see `history.params`.

Every read has a budget (store/sqlite/history/budget.py): an answer over its values is a 422,
a query over its time a 503, each saying what to narrow. An export over its time after it
began streaming is cut: the connection closes before the end of the body, so no client takes
it for complete (JSON lines get a last `{"error": ...}` line first).
"""

from __future__ import annotations

import logging
from collections.abc import AsyncIterator
from typing import Annotated

import orjson
from fastapi import APIRouter, Depends, Query, Request
from starlette.responses import StreamingResponse
from starlette.types import Send

from twinlink.api.deps import Caller
from twinlink.api.models.history import (
    AggregateAnswer,
    DownsampleAnswer,
    Latest,
    SamplesPage,
    StreamList,
)
from twinlink.api.models.problem import problems
from twinlink.api.responses import JSONAnswer
from twinlink.domain.history import (
    FORMATS,
    FUNCTIONS,
    MAX_TIME,
    METHODS,
    MIN_TIME,
    TIME_FORMATS,
    ReadBudgetError,
)
from twinlink.history.params import (
    DURATION_HELP,
    TIME_HELP,
    parse_choice,
    parse_choices,
    parse_cursor,
    parse_duration,
    parse_names,
    parse_time,
)
from twinlink.history.service import HistoryService, Selection

# 403: the twin is seen (a public part) but the caller has no role on it; 503: a read over its
# time budget, or storage that failed.
router = APIRouter(
    prefix="/api/v1/twins/{slug}/streams",
    tags=["history"],
    responses=problems(401, 403, 404, 422, 503),
)
log = logging.getLogger("twinlink.history")


def history_service(request: Request) -> HistoryService:
    return request.app.state.services.history_service  # type: ignore[no-any-return]


History = Annotated[HistoryService, Depends(history_service)]
# An export's answer by `format`: csv, jsonl or json, each a file (history's MEDIA_TYPES).
EXPORT_CONTENT = {
    media: {"schema": {"type": "string"}}
    for media in ("text/csv", "application/jsonl", "application/json")
}
Signals = Annotated[
    str | None, Query(description="Comma-separated signal names; every signal when left out.")
]
Start = Annotated[str | None, Query(description=f"From this time (inclusive): {TIME_HELP}.")]
End = Annotated[str | None, Query(description=f"To this time (inclusive): {TIME_HELP}.")]


class ExportResponse(StreamingResponse):
    """An export, streamed; cut visibly when the read stops half way (over its time, or the
    server stopping): the body's end is never sent, so the client sees an incomplete
    transfer, and JSON lines end with an `{"error": ...}` line. The export's generator is
    closed as soon as streaming ends, for whatever reason, so its read stops with it."""

    def __init__(self, body: AsyncIterator[bytes], fmt: str, media_type: str, filename: str):
        super().__init__(
            body,
            media_type=media_type,
            headers={"Content-Disposition": f'attachment; filename="{filename}"'},
        )
        self.fmt = fmt
        self.source = body

    async def stream_response(self, send: Send) -> None:
        start = {"type": "http.response.start", "status": self.status_code}
        await send({**start, "headers": self.raw_headers})
        try:
            async for chunk in self.source:
                await send({"type": "http.response.body", "body": chunk, "more_body": True})
        except ReadBudgetError as err:
            log.warning("history export cut: %s", err, extra={"event": "history_export_cut"})
            if self.fmt == "jsonl":
                line = orjson.dumps({"error": str(err)}) + b"\n"
                await send({"type": "http.response.body", "body": line, "more_body": True})
            return  # without the end of the body: the connection is closed
        finally:
            # Not left to the garbage collector: a client that went away stops the read now.
            await self.source.aclose()  # type: ignore[attr-defined]
        await send({"type": "http.response.body", "body": b"", "more_body": False})


def _selection(
    history: HistoryService,
    stream: str,
    signals: str | None,
    start: str | None,
    end: str | None,
) -> Selection:
    now = history.clock()
    return Selection(
        stream=stream,
        signals=parse_names(signals),
        start=parse_time(start, "start", now, MIN_TIME),
        end=parse_time(end, "end", now, MAX_TIME),
    )


@router.get(
    "",
    summary="The twin's streams and their signals",
    response_class=JSONAnswer,
    response_model=StreamList,
)
async def list_streams(slug: str, caller: Caller, history: History) -> JSONAnswer:
    return JSONAnswer(await history.streams(caller, slug))


@router.get(
    "/{stream}/latest",
    summary="The newest value of each signal of a stream",
    response_class=JSONAnswer,
    response_model=Latest,
)
async def latest(
    slug: str, stream: str, caller: Caller, history: History, signals: Signals = None
) -> JSONAnswer:
    names = parse_names(signals)
    return JSONAnswer(await history.latest(caller, slug, stream, names))


@router.get(
    "/{stream}/samples",
    summary="Stored samples in a time range, as rows joined on time, a page at a time",
    response_class=JSONAnswer,
    response_model=SamplesPage,
)
async def samples(
    slug: str,
    stream: str,
    caller: Caller,
    history: History,
    signals: Signals = None,
    start: Start = None,
    end: End = None,
    limit: Annotated[int, Query(ge=1, le=100_000, description="Most rows in this page.")] = 1000,
    cursor: Annotated[str | None, Query(description="`next_cursor` of the previous page.")] = None,
) -> JSONAnswer:
    sel = _selection(history, stream, signals, start, end)
    after = parse_cursor(cursor)
    return JSONAnswer(await history.samples(caller, slug, sel, limit, after))


@router.get(
    "/{stream}/aggregate",
    summary="Aggregates (avg, min, max, count, first, last, sum) over fixed time buckets",
    response_class=JSONAnswer,
    response_model=AggregateAnswer,
)
async def aggregate(
    slug: str,
    stream: str,
    caller: Caller,
    history: History,
    bucket: Annotated[
        str, Query(description=f"Bucket width, aligned to the epoch: {DURATION_HELP}.")
    ] = "1m",
    fn: Annotated[
        str | None,
        Query(description=f"Comma-separated functions of {', '.join(FUNCTIONS)}; default avg."),
    ] = None,
    signals: Signals = None,
    start: Start = None,
    end: End = None,
) -> JSONAnswer:
    sel = _selection(history, stream, signals, start, end)
    width = parse_duration(bucket, "bucket")
    fns = parse_choices(fn, "fn", FUNCTIONS, ["avg"])
    return JSONAnswer(await history.aggregate(caller, slug, sel, width, fns))


@router.get(
    "/{stream}/downsample",
    summary="At most `points` samples per signal that keep the peaks (minmax or lttb)",
    response_class=JSONAnswer,
    response_model=DownsampleAnswer,
)
async def downsample(
    slug: str,
    stream: str,
    caller: Caller,
    history: History,
    points: Annotated[int, Query(ge=2, le=100_000, description="Most samples per signal.")] = 1000,
    method: Annotated[
        str | None,
        Query(description="minmax (each bucket's min and max) or lttb (largest triangle)."),
    ] = None,
    signals: Signals = None,
    start: Start = None,
    end: End = None,
) -> JSONAnswer:
    sel = _selection(history, stream, signals, start, end)
    chosen = parse_choice(method, "method", METHODS, "minmax")
    return JSONAnswer(await history.downsample(caller, slug, sel, points, chosen))


@router.get(
    "/{stream}/export",
    summary="The range as a CSV, JSON lines or JSON file, streamed",
    response_class=ExportResponse,
    status_code=200,  # ExportResponse takes no status_code, from which FastAPI would read it
    responses={200: {"description": "The file", "content": EXPORT_CONTENT}},
)
async def export(
    slug: str,
    stream: str,
    caller: Caller,
    history: History,
    format: Annotated[str | None, Query(description="csv (default), jsonl or json.")] = None,
    time: Annotated[
        str | None,
        Query(description="iso (ISO 8601 UTC with ns; default for csv) or ns (default else)."),
    ] = None,
    signals: Signals = None,
    start: Start = None,
    end: End = None,
) -> ExportResponse:
    sel = _selection(history, stream, signals, start, end)
    fmt = parse_choice(format, "format", FORMATS, "csv")
    time_format = parse_choice(time, "time", TIME_FORMATS, "iso" if fmt == "csv" else "ns")
    out = await history.export(caller, slug, sel, fmt, time_format)
    return ExportResponse(out.body, fmt, out.media_type, out.filename)
