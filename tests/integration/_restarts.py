"""Devices that keep streaming while a test restarts PostgreSQL or Kafka under a node, and
what each of them saw (tests/integration/test_scale_out_restarts.py).

Each device sends many small batches, numbered by `seq`, one at a time, and keeps sending
a batch until it is acknowledged (a device that got an error sends it again, as the SDK
does), so in the end the acknowledged seqs are 1..N with none missing. Every answer is kept
as an `Outcome`: an ack, a duplicate ack (stored by an earlier try), a 503 with Retry-After
(HTTP) or an error with `retry: true` (WebSocket), or anything else (which the tests refuse).
A live client on the node keeps every batch it is shown.
"""

from __future__ import annotations

import asyncio
import contextlib
import threading
import time
from collections import Counter
from dataclasses import dataclass, field
from typing import Any

import asyncpg
import httpx
import orjson
from websockets.exceptions import ConnectionClosed, InvalidStatus, WebSocketException
from websockets.sync.client import ClientConnection, connect

from tests.conftest import Server
from tests.integration._live import ws_url

T0 = 1_700_000_000 * 10**9
SAMPLES = 4  # per batch: many small batches, as a device streaming at a high rate sends
ANSWER_S = 60.0  # an answer later than this is a hang, whatever the machine's load
# The devices here send again sooner than Retry-After says (5 s for the bus, 30 s for the
# store), to keep the test short; that the header is there is checked.
BACKOFF_S = 0.2
PACE_S = 0.02  # between two batches: a device streaming, not one flooding a shared machine
GOOD = ("ack", "duplicate")
UNAVAILABLE = "unavailable"  # 503 + Retry-After + problem+json, or a WebSocket retry error


@dataclass(frozen=True)
class Outcome:
    seq: int
    kind: str  # "ack", "duplicate", UNAVAILABLE, "closed" (WebSocket), or "wrong"
    detail: str = ""


def batch(dev: int, seq: int) -> dict[str, Any]:
    """Batch `seq` of device `dev`, on a stream of its own; each sample says whose it is."""
    t = T0 + seq * 10**6
    rows = [{"time": t + i, "values": {"dev": dev, "seq": seq}} for i in range(SAMPLES)]
    return {"seq": seq, "stream": f"d{dev}", "samples": rows}


@dataclass
class Streaming:
    """One device's stream, run in a thread of its own."""

    server: Server
    token: str
    dev: int
    outcomes: list[Outcome] = field(default_factory=list)
    stopping: threading.Event = field(default_factory=threading.Event)
    thread: threading.Thread | None = None
    next_seq: int = 1

    def start(self) -> None:
        self.thread = threading.Thread(target=self._run, name=f"device-{self.dev}", daemon=True)
        self.thread.start()

    def stop(self) -> None:
        """Ends once the batch being sent is acknowledged (or after ANSWER_S of trying)."""
        self.stopping.set()
        assert self.thread is not None
        self.thread.join(ANSWER_S * 2)
        assert not self.thread.is_alive(), f"device {self.dev} did not stop"

    def acked(self) -> list[int]:
        return [o.seq for o in self.outcomes if o.kind in GOOD]

    def count(self, *kinds: str) -> int:
        return sum(1 for o in self.outcomes if o.kind in kinds)

    def _run(self) -> None:
        deadline: float | None = None
        try:
            while True:
                outcome = self.send(self.next_seq)
                self.outcomes.append(outcome)
                if outcome.kind in GOOD:
                    if self.stopping.is_set():
                        return
                    self.next_seq += 1
                    time.sleep(PACE_S)
                    continue
                if self.stopping.is_set():  # the batch in flight is still sent until acked
                    deadline = deadline or time.monotonic() + ANSWER_S
                    if time.monotonic() > deadline:
                        return
                time.sleep(BACKOFF_S)  # a device's back-off before sending again
        finally:
            self.close()

    def send(self, seq: int) -> Outcome:
        raise NotImplementedError

    def close(self) -> None:
        raise NotImplementedError


class HttpDevice(Streaming):
    client: httpx.Client | None = None

    def send(self, seq: int) -> Outcome:
        if self.client is None:
            self.client = self.server.client(self.token)
            self.client.timeout = httpx.Timeout(ANSWER_S)
        try:
            r = self.client.post("/api/v1/device/samples", json=batch(self.dev, seq))
        except httpx.HTTPError as err:  # a hang (timeout) or a connection the node dropped
            return Outcome(seq, "wrong", repr(err))
        if r.status_code == 200:
            return Outcome(seq, "duplicate" if r.json()["duplicate"] else "ack")
        problem = r.headers.get("content-type", "").startswith("application/problem+json")
        if r.status_code == 503 and problem and r.headers.get("retry-after", "").isdigit():
            return Outcome(seq, UNAVAILABLE, r.json()["detail"])
        return Outcome(seq, "wrong", f"{r.status_code} {dict(r.headers)} {r.text[:300]}")

    def close(self) -> None:
        if self.client is not None:
            self.client.close()


@dataclass
class WebSocketDevice(Streaming):
    ws: ClientConnection | None = None
    held: contextlib.ExitStack = field(default_factory=contextlib.ExitStack)  # the connection

    def send(self, seq: int) -> Outcome:
        try:
            if self.ws is None:
                headers = {"Authorization": f"Bearer {self.token}"}
                url = ws_url(self.server, "/api/v1/device/ws")
                self.ws = self.held.enter_context(
                    connect(url, additional_headers=headers, open_timeout=ANSWER_S)
                )
            self.ws.send(orjson.dumps({"type": "samples", **batch(self.dev, seq)}).decode())
            return self._answer(self.ws, seq)
        except (ConnectionClosed, InvalidStatus, WebSocketException, OSError) as err:
            # the node closed it (1011: the device token could not be checked): reconnect
            self.ws = None
            self.held.close()
            return Outcome(seq, "closed", repr(err))
        except TimeoutError as err:
            return Outcome(seq, "wrong", f"no answer within {ANSWER_S} s: {err!r}")

    def close(self) -> None:
        self.held.close()

    @staticmethod
    def _answer(ws: ClientConnection, seq: int) -> Outcome:
        while True:
            message = orjson.loads(ws.recv(timeout=ANSWER_S))
            if message.get("seq") != seq or message.get("type") not in ("ack", "error"):
                continue  # welcome, desired properties, ...
            if message["type"] == "ack":
                return Outcome(seq, "duplicate" if message["duplicate"] else "ack")
            if message.get("retry") is True:
                return Outcome(seq, UNAVAILABLE, message["message"])
            return Outcome(seq, "wrong", str(message))


@dataclass
class LiveClient:
    """A browser's live connection to the node, subscribed to the streams of the devices."""

    server: Server
    token: str
    slug: str
    devices: int
    seen: Counter[tuple[int, int]] = field(default_factory=Counter)  # (dev, seq) -> times
    errors: list[str] = field(default_factory=list)
    subscribed: threading.Event = field(default_factory=threading.Event)
    stopping: threading.Event = field(default_factory=threading.Event)
    thread: threading.Thread | None = None

    def start(self) -> None:
        self.thread = threading.Thread(target=self._run, name="live", daemon=True)
        self.thread.start()
        assert self.subscribed.wait(ANSWER_S), self.errors

    def stop(self) -> None:
        self.stopping.set()
        assert self.thread is not None
        self.thread.join(10)

    def _run(self) -> None:
        headers = {"Authorization": f"Bearer {self.token}"}
        url = ws_url(self.server, "/api/v1/live")
        with connect(url, additional_headers=headers, open_timeout=ANSWER_S) as ws:
            welcome = orjson.loads(ws.recv(timeout=ANSWER_S))
            for dev in range(self.devices):  # a subscription per stream: one per device
                subscribe = {"op": "subscribe", "id": f"s{dev}", "twin": self.slug}
                ws.send(orjson.dumps({**subscribe, "stream": f"d{dev}"}).decode())
                answer = orjson.loads(ws.recv(timeout=ANSWER_S))
                if welcome["type"] != "welcome" or answer["type"] != "subscribed":
                    self.errors.append(f"{welcome} {answer}")
                    return
            self.subscribed.set()
            while not self.stopping.is_set():
                try:
                    message = orjson.loads(ws.recv(timeout=0.5))
                except TimeoutError:
                    continue
                except ConnectionClosed as err:
                    self.errors.append(repr(err))
                    return
                if message.get("type") != "samples":
                    continue
                batches = {(s["values"]["dev"], s["values"]["seq"]) for s in message["samples"]}
                self.seen.update(batches)


def unpublished(dsn: str) -> int:
    """Device batches stored whose publish no node has confirmed (`ingested.published`)."""

    async def read() -> int:
        conn = await asyncpg.connect(dsn)
        try:
            return int(await conn.fetchval("SELECT count(*) FROM ingested WHERE NOT published"))
        finally:
            await conn.close()

    return asyncio.run(read())


def stored(dsn: str) -> dict[int, Counter[int]]:
    """Per device, how many samples of each seq history holds, read straight from the
    database (not through a node)."""

    async def read() -> list[asyncpg.Record]:
        conn = await asyncpg.connect(dsn)
        try:
            return await conn.fetch(
                "SELECT st.name, s.vi, count(*) FROM samples s "
                "JOIN series se ON se.id = s.series_id JOIN streams st ON st.id = se.stream_id "
                "WHERE se.signal = 'seq' GROUP BY st.name, s.vi"
            )
        finally:
            await conn.close()

    found: dict[int, Counter[int]] = {}
    for stream, seq, n in asyncio.run(read()):
        found.setdefault(int(stream.removeprefix("d")), Counter())[seq] = n
    return found
