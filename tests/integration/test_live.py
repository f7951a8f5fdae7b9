"""Live streams for clients (`GET /api/v1/live`, docs/protocol.md): auth, subscribe with a
signal filter and max_rate, unsubscribe, errors that leave the connection open, and a slow
client that loses data (and is told) while a client reading beside it loses none.

Samples come from a device over HTTP ingest; its answer (the ack) comes after the batch was
published, so by then the batch is in each subscriber's queue. Every wait is a receive with a
timeout, never a sleep."""

from __future__ import annotations

import socket
import threading
import time
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from pathlib import Path
from typing import Any

import orjson
import pytest
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import ClientConnection, connect

from tests.conftest import Server, start_server, stop_server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._live import TIMEOUT_S, device_twin, ws_url
from tests.integration._util import apply, make_user, twin_doc, unique

pytestmark = pytest.mark.integration

QUEUE = 8  # the server's live_queue_messages, small so a slow client overflows soon
T0 = 1_732_200_000_000_000_000
MS = 1_000_000


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    srv = start_server(
        tmp_path_factory.mktemp("data"), {"TWINLINK_LIVE_QUEUE_MESSAGES": str(QUEUE)}
    )
    try:
        yield srv
    finally:
        stop_server(srv)


@contextmanager
def live(server: Server, token: str | None, **options: Any) -> Iterator[ClientConnection]:
    headers = {"Authorization": f"Bearer {token}"} if token else {}
    with connect(
        ws_url(server, "/api/v1/live"),
        additional_headers=headers,
        open_timeout=TIMEOUT_S,
        **options,
    ) as ws:
        yield ws


def recv(ws: ClientConnection) -> dict[str, Any]:
    return orjson.loads(ws.recv(timeout=TIMEOUT_S))  # type: ignore[no-any-return]


def send(ws: ClientConnection, **message: Any) -> None:
    ws.send(orjson.dumps(message).decode())


@contextmanager
def watch(server: Server, token: str, **options: Any) -> Iterator[ClientConnection]:
    """A header-authenticated live connection, past its welcome."""
    with live(server, token, **options) as ws:
        welcome = recv(ws)
        assert welcome["type"] == "welcome", welcome
        yield ws


def subscribe(ws: ClientConnection, sub: str, twin: str, **options: Any) -> dict[str, Any]:
    send(ws, op="subscribe", id=sub, twin=twin, **options)
    answer = recv(ws)
    assert answer["type"] == "subscribed" and answer["id"] == sub, answer
    return answer


def post(server: Server, device: str, seq: int, samples: list[dict[str, Any]]) -> None:
    with server.client(device) as c:
        r = c.post("/api/v1/device/samples", json={"seq": seq, "samples": samples})
    assert r.status_code == 200 and r.json()["accepted"] == len(samples), r.text


def closed_with(ws: ClientConnection) -> tuple[int, str]:
    with pytest.raises(ConnectionClosed) as info:
        while True:
            ws.recv(timeout=TIMEOUT_S)
    assert info.value.rcvd is not None, "the server closed without a close frame"
    return info.value.rcvd.code, info.value.rcvd.reason


@pytest.fixture
def rig(server: Server) -> tuple[str, str]:
    """A public twin and its device token."""
    slug, [device] = device_twin(server)
    return slug, device


def test_samples_arrive_with_the_receive_and_send_times(server: Server, rig: Any) -> None:
    slug, device = rig
    with live(server, server.admin_token) as ws:
        welcome = recv(ws)
        assert welcome["type"] == "welcome" and welcome["user"] == "admin"
        assert welcome["limits"]["queue_messages"] == QUEUE
        answer = subscribe(ws, "a", slug)
        assert answer["stream"] == "telemetry" and answer["signals"] is None
        assert answer["latest"] == {}  # no history yet
        before = time.time_ns()
        post(server, device, 1, [{"time": T0, "values": {"x": 1.5}}, {"values": {"x": 2.5}}])
        after = time.time_ns()
        message = recv(ws)
    assert message["type"] == "samples" and (message["sub"], message["twin"]) == ("a", slug)
    assert message["stream"] == "telemetry"
    assert message["samples"][0] == {"time": T0, "values": {"x": 1.5}}
    assert before <= message["samples"][1]["time"] == message["received"] <= after
    assert message["received"] <= message["sent"] <= time.time_ns()
    assert message["sent"] - message["received"] < 10 * 10**9


def test_signal_filter(server: Server, rig: Any) -> None:
    slug, device = rig
    with live(server, server.admin_token) as ws:
        recv(ws)
        assert subscribe(ws, "f", slug, signals=["x", "z"])["signals"] == ["x", "z"]
        post(server, device, 1, [{"time": T0, "values": {"y": 1}}])  # nothing for "f"
        post(server, device, 2, [{"time": T0 + MS, "values": {"x": 1, "y": 2, "z": 3}}])
        message = recv(ws)
    assert message["samples"] == [{"time": T0 + MS, "values": {"x": 1, "z": 3}}]


def test_subscribed_carries_the_latest_stored_values(server: Server, rig: Any) -> None:
    slug, device = rig
    post(server, device, 1, [{"time": T0, "values": {"x": 1, "y": 2}}])
    post(server, device, 2, [{"time": T0 + MS, "values": {"x": 3}}])
    with live(server, server.admin_token) as ws:
        recv(ws)
        everything = subscribe(ws, "all", slug)["latest"]
        some = subscribe(ws, "some", slug, signals=["x", "never-sent"])["latest"]
        other = subscribe(ws, "other", slug, stream="events")["latest"]
    assert everything == {"x": {"time": T0 + MS, "value": 3}, "y": {"time": T0, "value": 2}}
    assert some == {"x": {"time": T0 + MS, "value": 3}}
    assert other == {}


def test_max_rate_decimates_by_sample_time(server: Server, rig: Any) -> None:
    slug, device = rig
    with live(server, server.admin_token) as ws:
        recv(ws)
        assert subscribe(ws, "slow", slug, max_rate=10)["max_rate"] == 10
        subscribe(ws, "all", slug)
        # 1 kHz for 0.25 s, in two batches: at 10 per second, one sample per 100 ms is kept.
        post(server, device, 1, [{"time": T0 + i * MS, "values": {"x": i}} for i in range(150)])
        post(
            server, device, 2, [{"time": T0 + i * MS, "values": {"x": i}} for i in range(150, 250)]
        )
        got: dict[str, list[int]] = {"slow": [], "all": []}
        while len(got["all"]) < 250:
            message = recv(ws)
            got[message["sub"]] += [s["values"]["x"] for s in message["samples"]]
    assert got["all"] == list(range(250))
    assert got["slow"] == [0, 100, 200]


def test_unsubscribe_stops_delivery(server: Server, rig: Any) -> None:
    slug, device = rig
    with live(server, server.admin_token) as ws:
        recv(ws)
        subscribe(ws, "a", slug)
        subscribe(ws, "b", slug)
        post(server, device, 1, [{"time": T0, "values": {"x": 1}}])
        assert {recv(ws)["sub"], recv(ws)["sub"]} == {"a", "b"}
        send(ws, op="unsubscribe", id="a")
        assert recv(ws) == {"type": "unsubscribed", "id": "a"}
        post(server, device, 2, [{"time": T0 + MS, "values": {"x": 2}}])
        post(server, device, 3, [{"time": T0 + 2 * MS, "values": {"x": 3}}])
        # One queue in arrival order: had "a" got anything, it would come before b's last.
        seen = [recv(ws), recv(ws)]
    assert [(m["sub"], m["samples"][0]["values"]["x"]) for m in seen] == [("b", 2), ("b", 3)]


def test_auth_by_first_message(server: Server, rig: Any) -> None:
    slug, device = rig
    with live(server, None) as ws:
        send(ws, op="auth", token=server.admin_token)
        assert recv(ws)["type"] == "welcome"
        subscribe(ws, "a", slug)
        post(server, device, 1, [{"time": T0, "values": {"x": 1}}])
        assert recv(ws)["samples"] == [{"time": T0, "values": {"x": 1}}]


@pytest.mark.parametrize(
    ("headers", "first", "reason"),
    [
        ({"Authorization": "Bearer tl_not_a_token"}, None, "the token is not valid"),
        ({"Authorization": "Basic YWRtaW46eA=="}, None, "the Authorization header must be"),
        ({}, {"op": "auth", "token": "tl_not_a_token"}, "the token is not valid"),
        ({}, {"op": "subscribe", "id": "a", "twin": "x"}, "authenticate first"),
        ({}, {"op": "auth"}, "authenticate first"),
        ({}, "not json", "the message is not JSON"),
    ],
)
def test_no_or_a_bad_token_closes_with_4401(
    server: Server, headers: dict[str, str], first: Any, reason: str
) -> None:
    with connect(
        ws_url(server, "/api/v1/live"), additional_headers=headers, open_timeout=TIMEOUT_S
    ) as ws:
        if first is not None:
            ws.send(first if isinstance(first, str) else orjson.dumps(first).decode())
        code, text = closed_with(ws)
    assert code == 4401 and text.startswith(reason), text


def test_a_device_token_may_not_watch(server: Server, rig: Any) -> None:
    _, device = rig
    with live(server, device) as ws:
        assert closed_with(ws) == (4401, "the token is not valid")


def test_a_token_revoked_while_connected_closes_on_the_next_subscribe(
    server: Server, rig: Any
) -> None:
    slug, _ = rig
    token = make_user(server, unique("gone"))
    _grant(server, token, slug, "viewer")
    with live(server, token) as ws:
        recv(ws)
        subscribe(ws, "a", slug)
        with server.client(token) as c:
            assert c.post("/api/v1/auth/logout").status_code in (200, 204)
        send(ws, op="subscribe", id="b", twin=slug)
        code, reason = closed_with(ws)
    assert code == 4401 and reason == "the token has been revoked"


def _grant(server: Server, token: str, slug: str, role: str) -> None:
    with server.admin as admin:
        me = admin.get("/api/v1/auth/me", headers={"Authorization": f"Bearer {token}"}).json()
        r = admin.put(f"/api/v1/twins/{slug}/roles/{me['username']}", json={"role": role})
        assert r.status_code == 200, r.text


def test_a_public_document_does_not_open_the_live_data(server: Server, rig: Any) -> None:
    slug, _ = rig
    with live(server, make_user(server, unique("reader"))) as ws:
        recv(ws)
        send(ws, op="subscribe", id="p", twin=slug)
        refused = recv(ws)
    assert refused["type"] == "error"
    assert refused["message"] == f"the live streams of {slug!r} need the viewer role"


def test_viewers_watch_and_strangers_learn_nothing(server: Server) -> None:
    slug = unique("live-private")
    viewer, stranger = make_user(server, unique("viewer")), make_user(server, unique("nobody"))
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Rig", slug=slug, privacy="group-x"))
        me = admin.get("/api/v1/auth/me", headers={"Authorization": f"Bearer {viewer}"}).json()
        r = admin.put(f"/api/v1/twins/{slug}/roles/{me['username']}", json={"role": "viewer"})
        assert r.status_code == 200, r.text
        device = admin.post(f"/api/v1/twins/{slug}/devices", json={"name": "d"}).json()["token"]
    with live(server, viewer) as ws:
        recv(ws)
        subscribe(ws, "v", slug)
        post(server, device, 1, [{"time": T0, "values": {"x": 1}}])
        assert recv(ws)["samples"] == [{"time": T0, "values": {"x": 1}}]
    with live(server, stranger) as ws:
        recv(ws)
        send(ws, op="subscribe", id="s", twin=slug)
        hidden = recv(ws)
        send(ws, op="subscribe", id="s", twin=slug + "-missing")
        missing = recv(ws)
        send(ws, op="ping")
        assert recv(ws)["type"] == "pong"  # still open
    assert hidden == {"type": "error", "op": "subscribe", "id": "s", "message": f"no twin {slug!r}"}
    assert missing["message"] == f"no twin {slug + '-missing'!r}"


def test_bad_messages_get_errors_and_the_connection_stays_usable(server: Server, rig: Any) -> None:
    slug, device = rig
    with live(server, server.admin_token) as ws:
        recv(ws)
        ws.send("{nope")
        assert recv(ws)["message"].startswith("the message is not JSON")
        send(ws, op="fly")
        assert recv(ws) == {
            "type": "error",
            "op": "fly",
            "message": "unknown op 'fly'; expected one of subscribe, unsubscribe, command, ping",
        }
        ws.send(b'{"op": "subscribe", "id": "a", "twin": "' + slug.encode() + b'", "max_rate": -1}')
        assert recv(ws)["message"].startswith('"max_rate" must be a number')
        ws.send("x" * 70_000)
        assert recv(ws)["message"] == "a message holds at most 65536 bytes"
        send(ws, op="ping", id="p")
        assert recv(ws)["id"] == "p"
        subscribe(ws, "a", slug)
        post(server, device, 1, [{"time": T0, "values": {"x": 1}}])
        assert recv(ws)["type"] == "samples"


def slow_socket(server: Server) -> socket.socket:
    """A socket with a tiny receive buffer, so an unread connection backs up quickly."""
    host, port = server.url.removeprefix("http://").split(":")
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    sock.connect((host, int(port)))
    return sock


def send_buffer_max() -> int:
    """The most the kernel may buffer on the server's side of one TCP connection."""
    try:
        return int(Path("/proc/sys/net/ipv4/tcp_wmem").read_text().split()[2])
    except (OSError, IndexError, ValueError):
        return 4 * 1024 * 1024


def test_a_slow_client_is_told_it_lost_data_and_does_not_slow_another(
    server: Server, rig: Any
) -> None:
    slug, device = rig
    per_batch, pad = 100, "p" * 1000  # about 100 KB of JSON a message
    # Enough that the unread connection overflows whatever the kernel buffers on its way.
    batches = QUEUE + 2 * send_buffer_max() // (per_batch * len(pad))
    with ExitStack() as stack:
        slow = stack.enter_context(
            watch(server, server.admin_token, sock=slow_socket(server), max_queue=1,
                  compression=None)
        )  # fmt: skip
        fast = stack.enter_context(watch(server, server.admin_token))
        subscribe(slow, "slow", slug)
        subscribe(fast, "fast", slug)
        fast_got: list[dict[str, Any]] = []
        reader = threading.Thread(target=_read_batches, args=(fast, batches, fast_got))
        reader.start()
        for seq in range(batches):
            rows = [{"time": T0 + (seq * per_batch + i) * MS, "values": {"x": seq, "pad": pad}}
                    for i in range(per_batch)]  # fmt: skip
            post(server, device, seq + 1, rows)
        reader.join(timeout=TIMEOUT_S)
        assert not reader.is_alive(), "the reading client did not get every batch"
        # The reading client got everything, in order, and was never told of a loss.
        assert [m["type"] for m in fast_got] == ["samples"] * batches
        assert [m["samples"][0]["values"]["x"] for m in fast_got] == list(range(batches))
        slow_got = _read_until_batch(slow, batches - 1)
    dropped = [m for m in slow_got if m["type"] == "dropped"]
    assert dropped and all(m["sub"] == "slow" and m["messages"] > 0 for m in dropped)
    delivered = sum(len(m["samples"]) for m in slow_got if m["type"] == "samples")
    assert delivered + sum(m["samples"] for m in dropped) == batches * per_batch
    assert delivered < batches * per_batch


def _read_batches(ws: ClientConnection, count: int, into: list[dict[str, Any]]) -> None:
    while len(into) < count:
        into.append(recv(ws))


def _read_until_batch(ws: ClientConnection, last: int) -> list[dict[str, Any]]:
    got = []
    while True:
        message = recv(ws)
        got.append(message)
        if message["type"] == "samples" and message["samples"][0]["values"]["x"] == last:
            return got
