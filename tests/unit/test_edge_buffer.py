"""The device SDK's buffers and batching: bounds and their policies, the disk buffer across a
restart, and sequence numbers that never repeat."""

from __future__ import annotations

import json
import threading
import time
from pathlib import Path

import pytest

import twinlink_edge._batcher
from twinlink_edge import BufferFull, DiskBuffer, MemoryBuffer
from twinlink_edge._batcher import Batcher
from twinlink_edge._buffer import Buffer, StoredBatch


def batcher(buffer: Buffer | None = None, **options: object) -> tuple[Batcher, list[bool]]:
    notes: list[bool] = []
    settings: dict[str, object] = {"batch_size": 10, "max_samples": 30, "on_full": "error"}
    settings.update(options)
    return Batcher(
        MemoryBuffer() if buffer is None else buffer, notify=notes.append, **settings
    ), notes  # type: ignore[arg-type]


def sample(i: int) -> dict[str, object]:
    return {"time": i, "values": {"i": i}}


def sent(b: Batcher) -> list[StoredBatch]:
    out = []
    while (batch := b.next_to_send()) is not None:
        out.append(batch)
    return out


def test_samples_are_sealed_by_count_and_on_demand() -> None:
    b, notes = batcher()
    for i in range(25):
        b.add(sample(i), "telemetry", wait=False)
    assert notes == [False, True, False, True, False]  # first waiting sample; sealed batches
    assert (len(b.buffer), b.pending_samples, b.buffered_samples) == (2, 5, 25)
    last = b.seal_all()
    batches = sent(b)
    assert [x.count for x in batches] == [10, 10, 5] and batches[-1].seq == last
    assert [x.seq for x in batches] == sorted({x.seq for x in batches})
    body = json.loads(batches[0].payload)
    assert body["type"] == "samples" and body["samples"][3] == sample(3)


def test_streams_are_batched_apart_and_checked() -> None:
    b, _ = batcher()
    b.add(sample(1), "a", wait=False)
    b.add(sample(2), "b", wait=False)
    b.seal_all()
    assert sorted(x.stream for x in sent(b)) == ["a", "b"]
    with pytest.raises(ValueError, match="stream names"):
        b.add(sample(3), "Not A Stream", wait=False)


def test_error_policy_raises_when_full() -> None:
    b, _ = batcher(on_full="error")
    for i in range(30):
        b.add(sample(i), "telemetry", wait=False)
    with pytest.raises(BufferFull):
        b.add(sample(30), "telemetry", wait=False)
    first = sent(b)[0].seq
    assert b.remove(first) == 10
    b.add(sample(30), "telemetry", wait=False)
    assert b.buffered_samples == 21


def test_drop_oldest_policy_drops_whole_batches() -> None:
    b, _ = batcher(on_full="drop_oldest")
    for i in range(45):
        b.add(sample(i), "telemetry", wait=False)
    assert b.dropped_samples == 20 and b.buffered_samples == 25
    b.seal_all()
    kept = [json.loads(x.payload)["samples"][0]["values"]["i"] for x in sent(b)]
    assert kept == [20, 30, 40]


def test_block_policy_waits_in_other_threads_and_refuses_without_wait() -> None:
    b, _ = batcher(on_full="block")
    for i in range(30):
        b.add(sample(i), "telemetry", wait=False)
    assert b.add(sample(30), "telemetry", wait=False) is False
    done = threading.Event()

    def add() -> None:
        b.add(sample(30), "telemetry", wait=True)
        done.set()

    adder = threading.Thread(target=add)
    adder.start()
    assert not done.wait(0.05)  # blocked: the buffer is full
    b.remove(sent(b)[0].seq)
    assert done.wait(10)
    adder.join()
    b.close()
    with pytest.raises(RuntimeError, match="closed"):
        b.add(sample(31), "telemetry", wait=True)


def test_a_batch_too_large_for_one_frame_is_split(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(twinlink_edge._batcher, "MAX_FRAME_BYTES", 600)
    b, _ = batcher(batch_size=20, max_samples=40)
    for i in range(20):
        b.add(sample(i), "telemetry", wait=False)
    batches = sent(b)
    assert len(batches) > 1 and all(len(x.payload) <= 600 for x in batches)
    values = [s["values"]["i"] for x in batches for s in json.loads(x.payload)["samples"]]
    assert values == list(range(20)) and sum(x.count for x in batches) == 20


def test_rewind_sends_every_unacked_batch_again_in_order() -> None:
    b, _ = batcher()
    for i in range(30):
        b.add(sample(i), "telemetry", wait=False)
    first = [x.seq for x in sent(b)]
    b.remove(first[1])
    b.rewind()
    assert [x.seq for x in sent(b)] == [first[0], first[2]]
    assert b.requeue(first[2]) and not b.requeue(first[1])
    assert [x.seq for x in sent(b)] == [first[2]]


def test_the_disk_buffer_survives_a_reopen(tmp_path: Path) -> None:
    b, _ = batcher(DiskBuffer(tmp_path))
    for i in range(25):
        b.add(sample(i), "telemetry", wait=False)
    seqs = [x.seq for x in sent(b)]
    b.remove(seqs[0])
    b.close()  # seals the 5 waiting samples into the file too
    again = DiskBuffer(tmp_path)
    try:
        assert len(again) == 2 and again.samples == 15
        assert again.seqs()[0] == seqs[1] and again.last_seq > seqs[1]
        stored = again.get(seqs[1])
        assert stored is not None and json.loads(stored.payload)["samples"][0] == sample(10)
        b2, _ = batcher(again)
        assert b2.buffered_samples == 15 and [x.seq for x in sent(b2)] == again.seqs()
    finally:
        again.close()


def test_the_disk_buffer_keeps_the_last_seq_even_when_the_clock_goes_back(
    tmp_path: Path,
) -> None:
    future = time.time_ns() // 1000 + 10**12  # a clock that was far ahead, then corrected
    buffer = DiskBuffer(tmp_path, synchronous="full")
    buffer.put(StoredBatch(future, "telemetry", 1, "{}"))
    assert buffer.remove(future) == 1
    buffer.close()
    b, _ = batcher(DiskBuffer(tmp_path))
    b.add(sample(1), "telemetry", wait=False)
    assert b.seal_all() == future + 1
    b.close()
    with pytest.raises(ValueError, match="synchronous"):
        DiskBuffer(tmp_path, synchronous="sometimes")


def test_buffers_refuse_batches_out_of_order() -> None:
    buffer = MemoryBuffer()
    buffer.put(StoredBatch(5, "telemetry", 1, "{}"))
    with pytest.raises(ValueError):
        buffer.put(StoredBatch(5, "telemetry", 1, "{}"))
    assert buffer.remove(6) is None and buffer.remove(5) == 1 and buffer.samples == 0


def test_settings_are_checked() -> None:
    with pytest.raises(ValueError, match="on_full"):
        batcher(on_full="sometimes")
    with pytest.raises(ValueError, match="at least batch_size"):
        batcher(batch_size=100, max_samples=10)


def test_durable_samples_are_in_the_file_before_add_returns(tmp_path: Path) -> None:
    b, _ = batcher(DiskBuffer(tmp_path), durable=True, batch_size=10, max_samples=100)
    for i in range(13):
        b.add(sample(i), "telemetry" if i < 10 or i % 2 else "other", wait=False)
    # The process dies here (nothing closed): another opening of the file has every sample,
    # the 10 of the sealed batch in it and the 3 others held, none in both.
    crashed = DiskBuffer(tmp_path)
    try:
        assert crashed.samples == 10 and len(crashed) == 1
        held = crashed.held()
        assert [s["values"]["i"] for _, s in held] == [10, 11, 12]
        assert [stream for stream, _ in held] == ["other", "telemetry", "other"]
        again, _ = batcher(crashed, batch_size=10, max_samples=100)
        assert again.pending_samples == 3 and again.buffered_samples == 13
        again.seal_all()  # they go out as batches now, and are held no more
        assert crashed.held() == [] and crashed.samples == 13
        values = sorted(
            s["values"]["i"] for x in sent(again) for s in json.loads(x.payload)["samples"]
        )
        assert values == list(range(13))
    finally:
        crashed.close()
        b.close()


def test_a_restart_seals_held_samples_in_batches_of_batch_size(tmp_path: Path) -> None:
    buffer = DiskBuffer(tmp_path)
    for i in range(25):  # held by a run with a larger batch_size
        buffer.hold("telemetry", sample(i))
    b, _ = batcher(buffer, batch_size=10, max_samples=100)
    b.seal_all()
    assert [x.count for x in sent(b)] == [10, 10, 5] and buffer.held() == []
    b.close()


def test_durable_needs_a_folder_buffer() -> None:
    with pytest.raises(ValueError, match=r"durable=True .* give `buffer` a folder"):
        batcher(MemoryBuffer(), durable=True)
    with pytest.raises(TypeError, match="MemoryBuffer cannot keep samples"):
        MemoryBuffer().hold("telemetry", sample(1))
