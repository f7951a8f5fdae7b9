"""HistoryService on every storage backend (`_storage.BACKENDS`), through `HistoryReadStore`:
who may read, ranges narrowed to the data, pages joined by cursors, text signals in
aggregates and plots, exact sums beyond 64 bits, and exports named for their twin."""

from __future__ import annotations

import json

import orjson
import pytest

from tests.unit._services import SLUG, Setting, T, setting
from tests.unit._storage import Stores
from tests.unit._storage import stores as stores  # fixture
from twinlink.domain.errors import ForbiddenError, NotFoundError
from twinlink.domain.records import SearchRow, TwinWrite
from twinlink.domain.samples import SampleBatch, Value
from twinlink.history.params import QueryError, format_cursor, parse_cursor
from twinlink.history.service import HistoryService, Selection

S = 10**9


@pytest.fixture
async def world(stores: Stores) -> Setting:
    return await setting(stores)


@pytest.fixture
def history(world: Setting) -> HistoryService:
    return HistoryService(world.registry, world.stores.history)


async def write(world: Setting, rows: list[tuple[int, dict[str, Value]]]) -> None:
    times, values = [t for t, _ in rows], [v for _, v in rows]
    batch = SampleBatch(world.twin.id, SLUG, "telemetry", times, values, received_ns=T)
    assert await world.stores.history.append(batch)


async def test_reading_needs_a_role(history: HistoryService, world: Setting) -> None:
    await write(world, [(T, {"x": 1.0})])
    assert (await history.streams(world.viewer, SLUG))["streams"][0]["name"] == "telemetry"
    with pytest.raises(NotFoundError):  # a private twin: without a role it is not there
        await history.latest(world.stranger, SLUG, "telemetry", None)


async def test_seeing_a_public_twin_is_not_enough(history: HistoryService, world: Setting) -> None:
    public = TwinWrite(
        slug="open", dt_id="urn:open", name="open", created_ns=T, modified_ns=T,
        parts={"public": {"name": "open"}}, edges=[],
        search_rows=[SearchRow("public", None, "open", "", [], "")],
        owner_user_id=world.owner.user.id,  # type: ignore[union-attr]
    )  # fmt: skip
    await world.stores.metadata.save_twins([public])
    with pytest.raises(ForbiddenError, match="needs a role on it"):
        await history.streams(world.stranger, "open")
    assert (await history.streams(world.owner, "open"))["streams"] == []


async def test_pages_follow_their_cursors_to_the_end(
    history: HistoryService, world: Setting
) -> None:
    await write(world, [(T + i * S, {"x": i, "y": -i}) for i in range(7)])
    await write(world, [(T + 3 * S, {"x": 30})])  # a second row at 3 s
    rows, cursor = [], None
    while True:
        page = await history.samples(
            world.viewer, SLUG, Selection("telemetry", ["x"]), 3, parse_cursor(cursor)
        )
        rows.extend(page["rows"])
        cursor = page["next_cursor"]
        if cursor is None:
            break
        assert cursor == format_cursor(parse_cursor(cursor))  # type: ignore[arg-type]
    assert [r["values"]["x"] for r in rows] == [0, 1, 2, 3, 30, 4, 5, 6]
    assert page["start"] is None and page["end"] is None  # open bounds are shown as such


async def test_a_range_backwards_is_refused(history: HistoryService, world: Setting) -> None:
    with pytest.raises(QueryError, match="is after `end`"):
        await history.samples(world.viewer, SLUG, Selection("telemetry", None, T + S, T), 10, None)


async def test_aggregates_narrow_the_range_to_the_data_before_counting_buckets(
    history: HistoryService, world: Setting
) -> None:
    await write(world, [(T + i * S, {"x": float(i), "mode": "run"}) for i in range(10)])
    everything = Selection("telemetry")  # open bounds: 584 years of 1 s buckets, but ...
    answer = await history.aggregate(world.viewer, SLUG, everything, S, ["min", "max"])
    assert len(answer["rows"]) == 10  # ... the data spans 10 s
    assert answer["skipped"] == ["mode"]  # text, left out when every signal was asked for
    assert (answer["bucket"], answer["bucket_ns"]) == ("1s", S)
    wide = Selection("telemetry", None, T - 10**6 * S, T + 10**6 * S)
    await write(world, [(T - 10**6 * S, {"x": 0.0}), (T + 10**6 * S, {"x": 0.0})])
    with pytest.raises(QueryError, match="at most 100000 are allowed"):
        await history.aggregate(world.viewer, SLUG, wide, S, ["avg"])
    with pytest.raises(QueryError, match="holds text, not numbers"):
        await history.aggregate(world.viewer, SLUG, Selection("telemetry", ["mode"]), S, ["avg"])


async def test_empty_ranges_answer_no_rows(history: HistoryService, world: Setting) -> None:
    await write(world, [(T, {"x": 1.0})])
    later = Selection("telemetry", None, T + S, T + 2 * S)
    assert (await history.aggregate(world.viewer, SLUG, later, S, ["avg"]))["rows"] == []
    assert (await history.downsample(world.viewer, SLUG, later, 10, "minmax"))["signals"] == {}


async def test_sums_beyond_64_bits_go_out_as_exact_digits(
    history: HistoryService, world: Setting
) -> None:
    big = 2**63 - 1
    await write(world, [(T + i, {"n": big}) for i in range(4)])
    answer = await history.aggregate(world.viewer, SLUG, Selection("telemetry"), S, ["sum"])
    assert json.loads(orjson.dumps(answer["rows"])) == [  # stdlib json: any int exactly
        {"time": T, "values": {"n": {"sum": 4 * big}}}
    ]


async def test_plots_leave_text_signals_out(history: HistoryService, world: Setting) -> None:
    await write(world, [(T + i * S, {"x": float(i % 3), "mode": "run"}) for i in range(100)])
    answer = await history.downsample(world.viewer, SLUG, Selection("telemetry"), 10, "minmax")
    assert answer["skipped"] == ["mode"] and list(answer["signals"]) == ["x"]
    plot = answer["signals"]["x"]
    assert 0 < len(plot["time"]) <= 10 and set(plot["value"]) == {0.0, 2.0}
    with pytest.raises(QueryError, match="cannot downsample 'mode'"):
        await history.downsample(world.viewer, SLUG, Selection("telemetry", ["mode"]), 10, "lttb")


async def test_an_export_is_named_for_its_twin_and_stream(
    history: HistoryService, world: Setting
) -> None:
    await write(world, [(T, {"x": 1.5, "mode": "run"}), (T + S, {"x": 2.5})])
    export = await history.export(world.viewer, SLUG, Selection("telemetry"), "jsonl", "ns")
    assert (export.filename, export.media_type) == ("rig-telemetry.jsonl", "application/jsonl")
    assert export.signals == ["mode", "x"]
    lines = b"".join([piece async for piece in export.body]).splitlines()
    assert [orjson.loads(line) for line in lines] == [
        {"time": T, "values": {"mode": "run", "x": 1.5}},
        {"time": T + S, "values": {"x": 2.5}},
    ]
