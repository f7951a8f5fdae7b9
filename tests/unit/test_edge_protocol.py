"""The device SDK's wire helpers: URLs, JSON, sequence numbers, backoff, acks."""

from __future__ import annotations

import json
import random
import time

import numpy as np
import pytest

import twinlink_edge._protocol as protocol
from twinlink_edge import Ack, Backoff, device_ws_url
from twinlink_edge._protocol import SeqCounter, encode


@pytest.mark.parametrize(
    ("url", "expected"),
    [
        ("http://127.0.0.1:8000", "ws://127.0.0.1:8000/api/v1/device/ws"),
        ("https://twins.example.org/", "wss://twins.example.org/api/v1/device/ws"),
        ("https://example.org/twinlink", "wss://example.org/twinlink/api/v1/device/ws"),
        ("wss://example.org/api/v1/device/ws", "wss://example.org/api/v1/device/ws"),
        ("ws://example.org:81", "ws://example.org:81/api/v1/device/ws"),
    ],
)
def test_the_device_url_comes_from_the_server_url(url: str, expected: str) -> None:
    assert device_ws_url(url) == expected


@pytest.mark.parametrize("url", ["ftp://example.org", "example.org", "http://"])
def test_urls_that_are_not_http_or_ws_are_refused(url: str) -> None:
    with pytest.raises(ValueError):
        device_ws_url(url)


@pytest.mark.parametrize("with_orjson", [True, False])
def test_encoding_is_always_json(with_orjson: bool, monkeypatch: pytest.MonkeyPatch) -> None:
    if not with_orjson:
        monkeypatch.setattr(protocol, "_orjson", None)
    value = {"nan": float("nan"), "inf": float("inf"), "np": np.float32(1.5), "i": np.int64(3)}
    value["obj"] = object.__new__(type("Thing", (), {"__str__": lambda self: "thing"}))
    value["raw"] = b"bytes"
    text, size = encode({"values": value, "name": "\u00e6"})
    assert size == len(text.encode())
    assert json.loads(text) == {
        "values": {"nan": None, "inf": None, "np": 1.5, "i": 3, "obj": "thing", "raw": "bytes"},
        "name": "\u00e6",
    }
    assert protocol.loads(text)["values"]["i"] == 3


def test_sequence_numbers_start_at_the_clock_and_always_grow() -> None:
    now_us = time.time_ns() // 1000
    counter = SeqCounter()
    seqs = [counter.next() for _ in range(1000)]
    assert seqs[0] >= now_us and seqs == sorted(set(seqs))
    assert SeqCounter(floor=now_us + 10**9).next() == now_us + 10**9 + 1


def test_backoff_doubles_up_to_its_cap_with_jitter() -> None:
    backoff = Backoff(0.1, 10.0, rng=random.Random(7))
    ceilings = []
    for _ in range(12):
        ceiling = backoff.ceiling()
        delay = backoff.next()
        assert ceiling / 2 <= delay <= ceiling
        ceilings.append(ceiling)
    assert ceilings[:8] == pytest.approx([0.1, 0.2, 0.4, 0.8, 1.6, 3.2, 6.4, 10.0])
    assert ceilings[8:] == [10.0] * 4
    backoff.reset()
    assert backoff.ceiling() == 0.1
    with pytest.raises(ValueError):
        Backoff(0, 1)


def test_acks_are_read_leniently() -> None:
    ack = Ack.from_message(
        {
            "type": "ack",
            "seq": 7,
            "accepted": 99,
            "rejected": [{"index": 3, "reason": "x: bad"}, "junk"],
            "rejected_count": 120,
            "duplicate": True,
            "dropped": 2,
        }
    )
    assert (ack.seq, ack.accepted, ack.rejected, ack.rejected_count) == (
        7,
        99,
        [(3, "x: bad")],
        120,
    )
    assert ack.duplicate and ack.dropped == 2 and ack.refused is None
    empty = Ack.from_message({"type": "ack", "seq": True, "accepted": "many"})
    assert (empty.seq, empty.accepted, empty.rejected_count) == (0, 0, 0)


def test_samples_need_values() -> None:
    with pytest.raises(ValueError):
        protocol.sample({}, None)
    stamped = protocol.sample({"x": 1}, None)
    assert abs(stamped["time"] - time.time_ns()) < 10**10
