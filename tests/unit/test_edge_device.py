"""The device SDK (twinlink_edge) against FakeServer: an in-process fake of the device
WebSocket of docs/protocol.md, run on its own thread and event loop. Tests against the real
server are in tests/integration/test_edge_*.py."""

from __future__ import annotations

import asyncio
import json
import logging
import threading
import time
from collections.abc import Callable, Iterator
from http import HTTPStatus
from pathlib import Path
from typing import Any

import pytest
from websockets.asyncio.server import Request, Response, Server, ServerConnection, serve
from websockets.exceptions import ConnectionClosed

import twinlink_edge._connection
from twinlink_edge import AsyncDevice, BufferFull, Device, DiskBuffer

Msg = dict[str, Any]
TIMEOUT = 10.0


class FakeServer:
    """A fake twinlink device endpoint: it sends `welcome` (plus `welcome_extra`, then the
    `queued` messages), records every message, answers pings, stores batches (once per seq)
    and, with `auto_ack`, acks them (duplicates flagged). `on_samples` may answer a batch
    instead. Thread-safe; `wait`/`until` block or await until a predicate on the fake holds."""

    def __init__(self, token: str = "tld_fake", *, auto_ack: bool = True) -> None:
        self.token = token
        self.auto_ack = auto_ack
        self.welcome_extra: Msg = {}
        self.queued: list[Msg] = []  # sent after each welcome, as the server does queued commands
        self.on_samples: Callable[[Msg], Msg | None] | None = None
        self.received: list[Msg] = []
        self.stored: dict[int, int] = {}  # seq -> samples
        self.refused = 0  # handshakes refused for a wrong token
        self.connections = 0
        self.reported_version = 0
        self.reported_extra: Msg = {}
        self.answer_reports = True
        self.answer_pings = True
        self.close_at_once: tuple[int, str] | None = None  # as the server does a bad token
        self.port = 0
        self._cond = threading.Condition()
        self._loop = asyncio.new_event_loop()
        self._thread = threading.Thread(target=self._loop.run_forever, daemon=True)
        self._server: Server | None = None
        self._conns: set[ServerConnection] = set()

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    def start(self, port: int = 0) -> FakeServer:
        self._thread.start()

        async def listen() -> Server:
            return await serve(self._handle, "127.0.0.1", port, process_request=self._auth)

        self._server = self._call(listen())
        self.port = next(iter(self._server.sockets)).getsockname()[1]
        return self

    def stop(self) -> None:
        async def shutdown() -> None:
            assert self._server is not None
            self._server.close()
            await self._server.wait_closed()

        self._call(shutdown())
        self._loop.call_soon_threadsafe(self._loop.stop)
        self._thread.join()
        self._loop.close()

    def __enter__(self) -> FakeServer:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()

    def _call(self, coro: Any) -> Any:
        return asyncio.run_coroutine_threadsafe(coro, self._loop).result(TIMEOUT)

    # ---- what the tests use ---------------------------------------------------------------

    def wait(self, predicate: Callable[[FakeServer], bool], timeout: float = TIMEOUT) -> None:
        with self._cond:
            assert self._cond.wait_for(lambda: predicate(self), timeout), "timed out"

    async def until(
        self, predicate: Callable[[FakeServer], bool], timeout: float = TIMEOUT
    ) -> None:
        await asyncio.to_thread(self.wait, predicate, timeout)

    def of_type(self, kind: str) -> list[Msg]:
        with self._cond:
            return [m for m in self.received if m.get("type") == kind]

    def batches(self) -> list[Msg]:
        return self.of_type("samples")

    def push(self, message: Msg | str) -> None:
        """Send `message` to every connected device."""
        text = message if isinstance(message, str) else json.dumps(message)

        async def send() -> None:
            for ws in list(self._conns):
                await ws.send(text)

        self._call(send())

    def drop(self) -> None:
        """End every connection abruptly, as a lost network does."""

        async def abort() -> None:
            for ws in list(self._conns):
                ws.transport.abort()

        self._call(abort())

    def ack(self, *seqs: int) -> None:
        for seq in seqs:
            batch = next(b for b in self.batches() if b["seq"] == seq)
            self.push(self.ack_for(batch, duplicate=False))

    @staticmethod
    def ack_for(batch: Msg, *, duplicate: bool) -> Msg:
        bad = [i for i, s in enumerate(batch["samples"]) if "reject_me" in s["values"]]
        return {
            "type": "ack",
            "seq": batch["seq"],
            "accepted": 0 if duplicate else len(batch["samples"]) - len(bad),
            "rejected": [{"index": i, "reason": "reject_me: refused"} for i in bad],
            "rejected_count": len(bad),
            "server_timed": 0,
            "dropped": 0,
            "duplicate": duplicate,
        }

    # ---- the server side ------------------------------------------------------------------

    def _auth(self, connection: ServerConnection, request: Request) -> Response | None:
        if request.headers.get("Authorization") == f"Bearer {self.token}":
            return None
        with self._cond:
            self.refused += 1
            self._cond.notify_all()
        return connection.respond(HTTPStatus.UNAUTHORIZED, "bad token\n")

    async def _handle(self, ws: ServerConnection) -> None:
        self._conns.add(ws)
        with self._cond:
            self.connections += 1
            self._cond.notify_all()
        if self.close_at_once is not None:
            await ws.close(*self.close_at_once)
            return
        welcome = {"type": "welcome", "device": "fake-device", "twin": "fake-twin"}
        await ws.send(json.dumps({**welcome, "server_time": time.time_ns(), **self.welcome_extra}))
        for message in list(self.queued):
            await ws.send(json.dumps(message))
        try:
            async for raw in ws:
                reply = self._receive(json.loads(raw))
                if reply is not None:
                    await ws.send(json.dumps(reply))
        except ConnectionClosed:
            pass
        finally:
            self._conns.discard(ws)

    def _receive(self, msg: Msg) -> Msg | None:
        with self._cond:
            self.received.append(msg)
            self._cond.notify_all()
            if msg["type"] == "ping":
                return (
                    {"type": "pong", "server_time": time.time_ns()} if self.answer_pings else None
                )
            if msg["type"] == "reported" and self.answer_reports:
                self.reported_version += 1
                return {
                    "type": "reported_ack",
                    "version": self.reported_version,
                    **self.reported_extra,
                }
            if msg["type"] != "samples":
                return None
            if self.on_samples is not None:
                answer = self.on_samples(msg)
                if answer is not None:
                    return answer
            duplicate = msg["seq"] in self.stored
            self.stored.setdefault(msg["seq"], len(msg["samples"]))
            return self.ack_for(msg, duplicate=duplicate) if self.auto_ack else None


@pytest.fixture
def fake() -> Iterator[FakeServer]:
    with FakeServer() as server:
        yield server


def device(fake: FakeServer, **options: Any) -> AsyncDevice:
    options = {"flush_interval": 0.005, "backoff_initial": 0.01, "backoff_max": 0.05, **options}
    return AsyncDevice(fake.url, fake.token, **options)


async def test_samples_go_out_in_batches_and_are_acked(fake: FakeServer) -> None:
    before_us = time.time_ns() // 1000
    async with device(fake, batch_size=1000) as dev:
        for i in range(2500):
            dev.add({"i": i}, time_ns=1_000 + i)
        await dev.flush(timeout=TIMEOUT)
        assert (dev.acked_samples, dev.accepted_samples, dev.buffered_samples) == (2500, 2500, 0)
        assert dev.connected and (dev.device_name, dev.twin) == ("fake-device", "fake-twin")
    batches = fake.batches()
    assert [len(b["samples"]) for b in batches] == [1000, 1000, 500]
    seqs = [b["seq"] for b in batches]
    assert seqs == sorted(set(seqs)) and seqs[0] >= before_us
    assert [s["values"]["i"] for b in batches for s in b["samples"]] == list(range(2500))
    first = batches[0]
    assert (first["stream"], first["time_unit"]) == ("telemetry", "ns")
    assert first["samples"][0] == {"time": 1000, "values": {"i": 0}}


async def test_a_partial_batch_goes_out_after_the_flush_interval(fake: FakeServer) -> None:
    async with device(fake, flush_interval=0.01) as dev:
        dev.add({"x": 1.5}, stream="other")
        await fake.until(lambda f: len(f.batches()) == 1)
        assert fake.batches()[0]["stream"] == "other"


async def test_at_most_a_window_of_batches_is_in_flight(fake: FakeServer) -> None:
    fake.auto_ack = False
    async with device(fake, batch_size=10, window=4) as dev:
        for i in range(100):
            dev.add({"i": i})
        await fake.until(lambda f: len(f.batches()) == 4)
        await dev.report({"marker": 1})  # sent after the batches the window allowed
        assert len(fake.batches()) == 4
        fake.ack(fake.batches()[0]["seq"])
        await fake.until(lambda f: len(f.batches()) == 5)
        fake.auto_ack = True
        fake.ack(*[b["seq"] for b in fake.batches()[1:]])
        await dev.flush(TIMEOUT)
        assert dev.acked_samples == 100


async def test_unacked_batches_are_resent_in_order_after_a_reconnect(fake: FakeServer) -> None:
    fake.auto_ack = False
    async with device(fake, batch_size=10) as dev:
        for i in range(30):
            dev.add({"i": i})
        await fake.until(lambda f: len(f.batches()) == 3)
        first = [b["seq"] for b in fake.batches()]
        fake.auto_ack = True
        fake.drop()
        await fake.until(lambda f: len(f.batches()) == 6)
        await dev.flush(TIMEOUT)
        assert [b["seq"] for b in fake.batches()[3:]] == first
        assert dev.connections == 2 and dev.connected
        # The server had stored them: the acks say duplicate, and nothing is counted twice.
        assert (dev.acked_samples, dev.accepted_samples, dev.duplicate_batches) == (30, 30, 3)
    assert sum(fake.stored.values()) == 30


async def test_rejections_are_counted_and_logged(
    fake: FakeServer, caplog: pytest.LogCaptureFixture
) -> None:
    acks = []
    async with device(fake, on_ack=acks.append) as dev:
        dev.add({"x": 1})
        dev.add({"reject_me": 1})
        await dev.flush(TIMEOUT)
        assert (dev.acked_samples, dev.accepted_samples, dev.rejected) == (2, 1, 1)
    assert acks[0].rejected == [(1, "reject_me: refused")]
    assert "1 samples rejected (#1: reject_me: refused)" in caplog.text


async def test_a_refused_batch_is_dropped_and_a_retryable_one_resent(
    fake: FakeServer, monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    monkeypatch.setattr(twinlink_edge._connection, "RETRY_DELAY", 0.01)
    answers = iter(
        [
            {"type": "error", "message": "unreadable", "fatal": False},
            {"type": "error", "message": "not stored; send it again", "retry": True},
        ]
    )

    def answer(msg: Msg) -> Msg | None:
        special = next(answers, None)
        return None if special is None else {**special, "seq": msg["seq"]}

    fake.on_samples = answer
    async with device(fake) as dev:
        dev.add({"x": 1})
        await dev.flush(TIMEOUT)
        assert (dev.refused_batches, dev.rejected, dev.acked_samples) == (1, 1, 1)
        dev.add({"x": 2})
        await dev.flush(TIMEOUT)
        assert (dev.refused_batches, dev.accepted_samples) == (1, 1)
    seqs = [b["seq"] for b in fake.batches()]
    assert seqs[1] == seqs[2] and len(seqs) == 3  # the retryable batch went out twice
    assert "refused by the server: unreadable" in caplog.text


async def test_server_noise_never_breaks_the_device(
    fake: FakeServer, caplog: pytest.LogCaptureFixture
) -> None:
    caplog.set_level(logging.DEBUG, "twinlink_edge")
    async with device(fake) as dev:
        assert await dev.wait_connected(TIMEOUT)
        for noise in ["not json", "[1, 2]", {"type": "mystery"}, {"type": "ack"}]:
            fake.push(noise)
        fake.push({"type": "ack", "seq": "x", "rejected": "y"})
        fake.push({"type": "desired", "properties": "nope"})
        fake.push({"type": "error", "message": "something odd"})
        dev.add({"x": 1})
        await dev.flush(TIMEOUT)
        assert dev.acked_samples == 1 and dev.connections == 1
        assert dev.last_error == "something odd"
    assert "not JSON" in caplog.text and "the server says: something odd" in caplog.text


async def test_a_refused_token_is_retried_with_backoff(fake: FakeServer) -> None:
    async with AsyncDevice(fake.url, "tld_wrong", backoff_initial=0.01, backoff_max=0.02) as dev:
        await fake.until(lambda f: f.refused >= 3)
        assert not dev.connected
        assert dev.last_error is not None and "refused the device token (401)" in dev.last_error
    # The real server accepts the WebSocket, then closes it with 4401 and the reason.
    fake.close_at_once = (4401, "unknown device token")
    async with device(fake) as dev:
        await fake.until(lambda f: f.connections >= 3)
        assert not dev.connected and dev.connections == 0
        expected = "the server refused the device token (4401 unknown device token)"
        assert dev.last_error == expected  # set before the third attempt


async def test_a_full_buffer_refuses_add_on_the_loop_and_send_waits(fake: FakeServer) -> None:
    fake.auto_ack = False
    async with device(fake, batch_size=10, max_buffered_samples=20) as dev:
        for i in range(20):
            dev.add({"i": i})
        with pytest.raises(BufferFull):
            dev.add({"i": 20})
        waiting = asyncio.ensure_future(dev.send({"i": 20}))
        await fake.until(lambda f: len(f.batches()) == 2)
        assert not waiting.done()
        fake.auto_ack = True
        fake.ack(*[b["seq"] for b in fake.batches()])
        await asyncio.wait_for(waiting, TIMEOUT)
        await dev.flush(TIMEOUT)
        assert dev.acked_samples == 21


async def test_the_disk_buffer_resends_after_a_restart_of_the_device(tmp_path: Path) -> None:
    with FakeServer(auto_ack=False) as fake:
        async with device(fake, buffer=tmp_path, batch_size=5, close_timeout=0.05) as dev:
            for i in range(12):
                dev.add({"i": i})
            await fake.until(lambda f: len(f.batches()) == 3)
        first = [b["seq"] for b in fake.batches()]
    with FakeServer() as fake:
        dev = device(fake, buffer=str(tmp_path), batch_size=5)
        assert dev.buffered_samples == 12
        async with dev:
            dev.add({"i": 12})
            await dev.flush(TIMEOUT)
            assert dev.acked_samples == 13
    seqs = [b["seq"] for b in fake.batches()]
    assert seqs[:3] == first and seqs[3] > first[-1]
    assert [s["values"]["i"] for b in fake.batches() for s in b["samples"]] == list(range(13))


async def test_a_device_never_started_refuses_samples(fake: FakeServer, tmp_path: Path) -> None:
    dev = device(fake, buffer=tmp_path)
    with pytest.raises(RuntimeError, match=r"not running: call start\(\) first"):
        dev.add({"x": 1})
    with pytest.raises(RuntimeError, match=r"not running: call start\(\) first"):
        await dev.flush()
    dev._close_unstarted()
    plain = Device(fake.url, fake.token)
    with pytest.raises(RuntimeError, match=r"not running: call start\(\) first"):
        plain.add({"x": 1})
    plain.close()
    buffer = DiskBuffer(tmp_path)
    assert (buffer.samples, buffer.held()) == (0, [])  # nothing kept for a start never made
    buffer.close()
    with pytest.raises(ValueError, match=r"durable=True .* give `buffer`"):
        device(fake, durable=True)


async def test_a_durable_device_sends_what_it_held(fake: FakeServer, tmp_path: Path) -> None:
    async with device(fake, buffer=tmp_path, durable=True, flush_interval=3600) as dev:
        for i in range(3):
            dev.add({"i": i})
        on_disk = DiskBuffer(tmp_path)  # a second reader of the file, as after a crash
        assert len(on_disk.held()) == 3  # though no batch was sealed yet
        on_disk.close()
        await dev.flush(TIMEOUT)
        assert dev.acked_samples == 3
    assert [s["values"]["i"] for b in fake.batches() for s in b["samples"]] == [0, 1, 2]
