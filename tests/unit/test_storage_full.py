"""A disk that fills up (or fails) under the stores: SQLITE_FULL and SQLITE_IOERR injected
at every statement of a group commit and of a metadata write, on real SQLite files.

What must hold: a caller is answered only once its data is committed, or gets a
StorageError; what failed, resent, is stored once; no acknowledged sample ever lands under
another signal's name (a series id cached from a rolled-back transaction once was).
"""

from __future__ import annotations

import asyncio
import logging
import sqlite3
from collections.abc import AsyncIterator, Callable
from pathlib import Path
from typing import Any

import pytest

from tests.unit._faulty import FaultyConnection, disk_error, wrap_writer_connections
from twinlink.commands.write_behind import WriteBehind
from twinlink.domain.commands import CommandRecord
from twinlink.domain.errors import StorageError, StorageFullError, TooManySignalsError
from twinlink.domain.samples import SampleBatch
from twinlink.ingest.service import IngestService
from twinlink.store.sqlite import SqliteStore
from twinlink.store.sqlite import db as db_module
from twinlink.store.sqlite.faults import StorageFaults, translate
from twinlink.store.sqlite.history import staging
from twinlink.store.sqlite.history.codec import decode_values
from twinlink.store.sqlite.history.writer import HistoryWriter


@pytest.fixture(autouse=True)
def blocks_at_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """These tests count blocks or statements of batches written as blocks: no batch is
    staged (test_history_staging.py covers staged batches)."""
    monkeypatch.setattr(staging, "STAGE_BELOW", 0)


T = 1_704_067_200 * 10**9
DEVICE = 5
CODES = [sqlite3.SQLITE_FULL, sqlite3.SQLITE_IOERR_WRITE]


def batch(signal: str, values: list[float], seq: int, twin_id: int = 1) -> SampleBatch:
    times = [T + seq * 1000 + i for i in range(len(values))]
    rows: list[dict[str, Any]] = [{signal: v} for v in values]
    return SampleBatch(twin_id, f"twin{twin_id}", "telemetry", times, rows, T, seq=seq)


def stored(path: Path) -> dict[str, list[float]]:
    """Every signal's values, read back from the file."""
    conn = sqlite3.connect(path)
    try:
        found: dict[str, list[float]] = {}
        for signal, kind, vals in conn.execute(
            "SELECT s.signal, b.kind, b.vals FROM blocks b JOIN series s ON s.id = b.series_id "
            "ORDER BY s.signal, b.t0"
        ):
            found.setdefault(signal, []).extend(decode_values(kind, vals).tolist())
        return found
    finally:
        conn.close()


@pytest.fixture
def faulty(monkeypatch: pytest.MonkeyPatch) -> list[FaultyConnection]:
    """The writer's connections, each wrapped in a FaultyConnection (disarmed)."""
    return wrap_writer_connections(monkeypatch)


def mark(conn: sqlite3.Connection) -> str:
    """A write of the kind commands and properties make through the writer."""
    conn.execute("INSERT INTO ingested (device_id, seq, at_ns) VALUES (99, 1, 0)")
    return "marked"


async def one_round_failing_at(
    path: Path, faulty: list[FaultyConnection], at: int, whole: bool, code: int
) -> bool:
    """A round of two new signals and a write, failing at statement `at`; then everything
    that failed is sent again. True when the fault fired (`at` was within the round)."""
    writer = HistoryWriter(path, "normal")
    await writer.open()
    conn = faulty[-1]
    try:
        assert await writer.append(batch("w", [1.0], seq=1), DEVICE) is True
        conn.arm(at, whole, code)
        sends: list[Callable[[], Any]] = [
            lambda: writer.append(batch("A", [10.0, 11.0, 12.0], seq=2), DEVICE),
            lambda: writer.append(batch("B", [20.0], seq=3), DEVICE),
            lambda: writer.write(mark),
        ]
        results = await asyncio.gather(*(send() for send in sends), return_exceptions=True)
        fired = conn.fired
        conn.disarm()
        for send, result in zip(sends, results, strict=True):
            if isinstance(result, BaseException):
                assert isinstance(result, StorageError), repr(result)
                assert isinstance(result, StorageFullError) == (code == sqlite3.SQLITE_FULL)
                assert (await send()) in (True, "marked")  # resent: stored now
            else:
                assert result in (True, "marked")
        # A signal new after the failure gets an id of its own, not one rolled back.
        assert await writer.append(batch("C", [30.0], seq=4), DEVICE) is True
        assert await writer.append(batch("A", [10.0, 11.0, 12.0], seq=2), DEVICE) is False
        ids = {r[0] for r in conn.conn.execute("SELECT id FROM series")}
        assert writer.take_small_blocks() <= ids  # no id of a series that never was
    finally:
        await writer.close()
    assert stored(path) == {"w": [1.0], "A": [10.0, 11.0, 12.0], "B": [20.0], "C": [30.0]}
    check = sqlite3.connect(path)
    try:
        assert check.execute("SELECT count(*) FROM ingested WHERE device_id = 99").fetchone() == (
            1,
        )
        assert check.execute("SELECT count(*) FROM series").fetchone() == (4,)
    finally:
        check.close()
    return fired


@pytest.mark.parametrize("code", CODES, ids=["full", "ioerr"])
@pytest.mark.parametrize("whole", [False, True], ids=["statement", "transaction"])
async def test_a_fault_at_any_statement_of_a_round_loses_or_mixes_up_nothing(
    tmp_path: Path, faulty: list[FaultyConnection], whole: bool, code: int
) -> None:
    at = 0
    while True:
        at += 1
        if not await one_round_failing_at(tmp_path / str(at) / "h.db", faulty, at, whole, code):
            break
    # BEGIN, 3 x (SAVEPOINT, its statements, RELEASE), the latest values, COMMIT
    assert at > 14, f"the round had only {at - 1} statements: {faulty[-1].statements}"


async def test_the_issue_13_sequence_stores_each_signal_under_its_own_name(
    tmp_path: Path, faulty: list[FaultyConnection]
) -> None:
    """The report: seq 2 (new signal A) fails at COMMIT on a full disk, seq 3 (new signal B)
    is stored, seq 2 is resent. B's rows once held A's values, under A's rolled-back id."""
    path = tmp_path / "history.db"
    writer = HistoryWriter(path, "normal")
    await writer.open()
    conn = faulty[-1]
    try:
        assert await writer.append(batch("w", [1.0], seq=1), DEVICE)
        # BEGIN, SAVEPOINT, INSERT ingested, INSERT series, blocks, RELEASE, latest, COMMIT
        conn.arm(at=8)
        with pytest.raises(StorageFullError, match="storage is full"):
            await writer.append(batch("A", [float(i) for i in range(2000)], seq=2), DEVICE)
        assert conn.statements[-1] == "COMMIT"
        conn.disarm()
        assert await writer.append(batch("B", [7.0, 8.0, 9.0], seq=3), DEVICE)
        assert await writer.append(batch("A", [float(i) for i in range(2000)], seq=2), DEVICE)
    finally:
        await writer.close()
    assert stored(path) == {"w": [1.0], "A": [float(i) for i in range(2000)], "B": [7.0, 8.0, 9.0]}
    assert writer.faults.counts == {"full": 1, "io": 0}


async def test_a_twin_forgotten_in_a_failed_round_is_still_known(
    tmp_path: Path, faulty: list[FaultyConnection]
) -> None:
    path = tmp_path / "history.db"
    writer = HistoryWriter(path, "normal")
    await writer.open()
    conn = faulty[-1]
    try:
        assert await writer.append(batch("x", [1.0], seq=1, twin_id=3))

        def drop_twin(c: sqlite3.Connection) -> None:
            c.execute("DELETE FROM series WHERE twin_id = 3")
            writer.forget_series(3)

        conn.arm(at=5)  # BEGIN, SAVEPOINT, DELETE, RELEASE, latest: then COMMIT fails
        with pytest.raises(StorageFullError):
            await writer.write(drop_twin)
        conn.disarm()
        # The series is still there, and still known: its next batch goes to it.
        assert await writer.append(batch("x", [2.0], seq=2, twin_id=3))
    finally:
        await writer.close()
    assert stored(path) == {"x": [1.0, 2.0]}


async def test_close_on_a_full_disk_is_clean(
    tmp_path: Path, faulty: list[FaultyConnection], caplog: pytest.LogCaptureFixture
) -> None:
    writer = HistoryWriter(tmp_path / "history.db", "normal")
    await writer.open()
    assert await writer.append(batch("x", [1.0], seq=1))
    faulty[-1].arm(at=1)  # PRAGMA optimize, at close
    await writer.close()
    assert "skipped PRAGMA optimize" in caplog.text


# -- the metadata store ----------------------------------------------------------------------


@pytest.fixture
async def store(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> AsyncIterator[tuple[SqliteStore, list[FaultyConnection]]]:
    made: list[FaultyConnection] = []
    real = db_module.connect

    def connect(path: Path) -> Any:
        made.append(FaultyConnection(real(path)))
        return made[-1]

    monkeypatch.setattr(db_module, "connect", connect)
    s = SqliteStore(tmp_path)
    await s.open()
    try:
        yield s, made
    finally:
        await s.close()


@pytest.mark.parametrize("at", [1, 2, 3, 4])  # BEGIN, INSERT, SELECT, COMMIT
@pytest.mark.parametrize("whole", [False, True], ids=["statement", "transaction"])
async def test_a_metadata_write_on_a_full_disk_raises_storage_full_and_stores_nothing(
    store: tuple[SqliteStore, list[FaultyConnection]], at: int, whole: bool
) -> None:
    s, (conn,) = store
    conn.arm(at, whole)
    with pytest.raises(StorageFullError):  # not "cannot rollback - no transaction is active"
        await s.create_user("bob", None, False, [], 1)
    conn.disarm()
    assert await s.list_users() == []
    assert s.db.faults.counts["full"] == 1
    created = await s.create_user("bob", None, False, [], 1)  # works again
    assert [u.id for u in await s.list_users()] == [created.id]


async def test_last_used_times_are_written_in_one_statement_each_and_never_go_back(
    store: tuple[SqliteStore, list[FaultyConnection]],
) -> None:
    s, (conn,) = store
    user = await s.create_user("bob", None, False, [], 1)
    tokens = [await s.create_token(user.id, f"t{i}", bytes([i]), "tl_", "api", 1, None)
              for i in range(3)]  # fmt: skip
    conn.arm(at=10**6)  # count only
    await s.touch_tokens({t.id: 100 + t.id for t in tokens})
    assert conn.statements == ["BEGIN IMMEDIATE", "UPDATE api_tokens SET last_used_ns = ? "
                               "WHERE id = ? AND", "COMMIT"]  # fmt: skip
    conn.disarm()
    await s.touch_tokens({tokens[0].id: 1})  # older: ignored
    assert [t.last_used_ns for t in await s.list_tokens(None)] == [100 + t.id for t in tokens]


# -- errors, counts and log lines ------------------------------------------------------------


def test_translate_names_full_and_io_errors_and_keeps_others() -> None:
    full = translate(disk_error(sqlite3.SQLITE_FULL))
    assert isinstance(full, StorageFullError) and isinstance(full.__cause__, sqlite3.Error)
    io = translate(disk_error(sqlite3.SQLITE_IOERR_WRITE))  # an extended code
    assert type(io) is StorageError
    locked = sqlite3.OperationalError("database is locked")
    locked.sqlite_errorcode = sqlite3.SQLITE_BUSY
    assert translate(locked) is locked
    other = ValueError("x")
    assert translate(other) is other


def test_storage_faults_log_once_a_minute_with_a_count(caplog: pytest.LogCaptureFixture) -> None:
    now = [0.0]
    faults = StorageFaults(every_s=60, clock=lambda: now[0])
    err = translate(disk_error())
    assert isinstance(err, StorageError)
    with caplog.at_level(logging.INFO, logger="twinlink.store"):
        for _ in range(500):  # a burst: one line
            faults.failed(err, "history.db", "history commit")
        now[0] = 61.0
        faults.failed(err, "history.db", "history commit")  # a minute later: one more
        faults.ok("history.db")
        faults.ok("history.db")  # nothing to say twice
    lines = [r.getMessage() for r in caplog.records]
    assert len(lines) == 3, lines
    assert lines[0].startswith("storage full: database or disk is full (history.db); 1 ")
    assert "; 500 write(s) failed since the last report" in lines[1]
    assert lines[2] == "storage writable again (history.db) after 501 failed write(s)"
    assert all(r.exc_info is None for r in caplog.records)  # no tracebacks
    assert faults.counts == {"full": 501, "io": 0}


# -- the command log, written behind -----------------------------------------------------------


def command(command_id: str, state: str = "pending") -> CommandRecord:
    return CommandRecord(
        id=command_id, twin_id=1, device_id=1, device="rig", name="pause", args={},
        state=state, queued=False, sent_by=None, created_ns=1, expires_ns=2,
    )  # fmt: skip


async def test_command_changes_a_full_disk_refused_are_written_with_the_next_write() -> None:
    written: list[list[str]] = []
    fail = [True]

    async def save(records: list[CommandRecord]) -> None:
        if fail[0]:
            raise StorageFullError("full")
        written.append([r.id for r in records])

    log = WriteBehind(save)
    log.save(command("a"))
    with pytest.raises(StorageFullError):
        await log.sync()
    log.save(command("b"))  # tried again with the next change: fails again, keeps both
    with pytest.raises(StorageFullError):
        await log.sync()
    fail[0] = False
    await log.sync()
    assert written == [["a", "b"]]
    fail[0] = True
    log.save(command("c"))
    await log.close()  # best effort at shutdown: no error
    assert log.closed


# -- processor outputs the store refuses -------------------------------------------------------


class RefusingHistory:
    def __init__(self, error: Exception) -> None:
        self.error = error

    async def append(self, batch: SampleBatch, device_id: int | None = None) -> bool:
        raise self.error


class Bus:
    def __init__(self) -> None:
        self.published = 0

    async def publish(self, subject: str, batch: SampleBatch) -> None:
        self.published += 1


class Registry:
    generation = 0


async def test_refused_processor_output_is_logged_once_a_minute_per_stream(
    caplog: pytest.LogCaptureFixture,
) -> None:
    refusal = TooManySignalsError("this batch would give stream 'fmu' 1001 signals")
    bus = Bus()
    ingest = IngestService(Registry(), RefusingHistory(refusal), bus)  # type: ignore[arg-type]
    out = SampleBatch(1, "rig", "fmu", [T], [{"x": 1.0}], T, source="processor:sim")
    with caplog.at_level(logging.INFO, logger="twinlink.ingest"):
        for _ in range(50):  # a processor sends its next output a moment later
            await ingest.publish_first(out)
        await asyncio.gather(*list(ingest._storing), return_exceptions=True)
        await asyncio.sleep(0)  # the done callbacks
    assert bus.published == 50  # live views still get them; the log does not fill up
    assert ingest.outputs_not_stored == 50
    assert [r.getMessage() for r in caplog.records] == [
        "output of processor:sim not stored (stream 'fmu' of twin 'rig'): this batch would "
        "give stream 'fmu' 1001 signals"
    ]


async def test_processor_output_refused_by_a_full_disk_is_left_to_the_store_to_log(
    caplog: pytest.LogCaptureFixture,
) -> None:
    ingest = IngestService(
        Registry(),  # type: ignore[arg-type]
        RefusingHistory(StorageFullError("full")),  # type: ignore[arg-type]
        Bus(),  # type: ignore[arg-type]
    )
    out = SampleBatch(1, "rig", "fmu", [T], [{"x": 1.0}], T, source="processor:sim")
    with caplog.at_level(logging.INFO, logger="twinlink.ingest"):
        await ingest.publish_first(out)
        await asyncio.gather(*list(ingest._storing), return_exceptions=True)
        await asyncio.sleep(0)
    assert ingest.outputs_not_stored == 1 and caplog.records == []
