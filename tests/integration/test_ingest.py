"""Device ingest over HTTP and the device WebSocket: acks, dedupe, checks, errors, scoping."""

from __future__ import annotations

import json
import time

import pytest
from websockets.exceptions import ConnectionClosed

from tests.conftest import Server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._live import (
    batch,
    device_socket,
    device_twin,
    receive,
    send,
    stored_values,
)
from tests.integration._util import assert_problem

pytestmark = pytest.mark.integration

INTERFACE = {
    "signals": [
        {"name": "angle", "type": "number", "min": 0, "max": 1},
        {"name": "count", "type": "integer"},
        {"name": "on", "type": "bool"},
        {"name": "mode", "type": "string"},
    ]
}


def _post(server: Server, token: str, body: object) -> dict[str, object]:
    with server.client(token) as device:
        r = device.post("/api/v1/device/samples", json=body)
    assert r.status_code == 200, r.text
    return r.json()  # type: ignore[no-any-return]


def test_http_batch_is_stored_and_a_resend_is_stored_once(server: Server) -> None:
    slug, (token,) = device_twin(server)
    now = time.time_ns()
    body = {"seq": 7, "samples": [{"time": now + i, "values": {"x": float(i)}} for i in range(5)]}
    first = _post(server, token, body)
    assert (first["accepted"], first["duplicate"], first["rejected_count"]) == (5, False, 0)
    again = _post(server, token, body)
    assert (again["accepted"], again["duplicate"]) == (0, True)
    assert stored_values(server, slug, "x") == [0.0, 1.0, 2.0, 3.0, 4.0]


def test_the_same_seq_from_two_devices_is_two_batches(server: Server) -> None:
    slug, tokens = device_twin(server, devices=2)
    for i, token in enumerate(tokens):
        ack = _post(server, token, {"seq": 1, "samples": [{"values": {"x": i}}]})
        assert ack["duplicate"] is False and ack["server_timed"] == 1
    assert sorted(stored_values(server, slug, "x")) == [0, 1]


def test_bad_samples_are_rejected_with_reasons_and_the_rest_kept(server: Server) -> None:
    slug, (token,) = device_twin(server, INTERFACE)
    rows = [
        {"values": {"angle": 0.5, "count": 3, "on": True, "mode": "run"}},
        {"values": {"angle": "high"}},
        {"values": {"angle": 1.5}},
        {"values": {"count": 2.5}},
        {"values": {"on": 1}},
        {"values": {"angle": None}},
        {"time": "yesterday", "values": {"angle": 0.1}},
        {"values": {}},
        "not a sample",
        {"values": {"angle": 0.25, "extra": 1}},  # unknown signals are accepted by default
    ]
    ack = _post(server, token, {"seq": 1, "samples": rows})
    assert ack["accepted"] == 2 and ack["rejected_count"] == 8
    reasons = {r["index"]: r["reason"] for r in ack["rejected"]}  # type: ignore[attr-defined]
    assert "not a number" in reasons[1] and "above the maximum 1" in reasons[2]
    assert "not an integer" in reasons[3] and "not a bool" in reasons[4]
    assert "null" in reasons[5].lower() or "None" in reasons[5]
    assert "ISO 8601" in reasons[6] and "at least one signal" in reasons[7]
    assert "object" in reasons[8]
    assert stored_values(server, slug, "angle") == [0.5, 0.25]
    assert stored_values(server, slug, "extra") == [1]


@pytest.mark.parametrize(
    ("policy", "accepted", "dropped", "stored"),
    [("accept", 1, 0, [7]), ("drop", 1, 1, []), ("reject", 0, 0, [])],
)
def test_unknown_signal_policy(
    server: Server, policy: str, accepted: int, dropped: int, stored: list[int]
) -> None:
    slug, (token,) = device_twin(server, {**INTERFACE, "unknown_signals": policy})
    ack = _post(server, token, {"seq": 1, "samples": [{"values": {"angle": 0.5, "other": 7}}]})
    assert (ack["accepted"], ack["dropped"]) == (accepted, dropped)
    assert stored_values(server, slug, "other") == stored


def test_out_of_range_may_be_accepted(server: Server) -> None:
    slug, (token,) = device_twin(server, {**INTERFACE, "out_of_range": "accept"})
    ack = _post(server, token, {"seq": 1, "samples": [{"values": {"angle": 3.0}}]})
    assert ack["accepted"] == 1
    assert stored_values(server, slug, "angle") == [3.0]


def test_an_interface_change_applies_to_the_next_batch(server: Server) -> None:
    slug, (token,) = device_twin(server, INTERFACE)
    assert (
        _post(server, token, {"seq": 1, "samples": [{"values": {"angle": 2.0}}]})["accepted"] == 0
    )
    with server.admin as admin:
        doc = admin.get(f"/api/v1/twins/{slug}").json()["document"]
        doc["interface"]["signals"][0]["max"] = 5
        r = admin.put(f"/api/v1/twins/{slug}", json=doc)
        assert r.status_code == 200, r.text
    assert (
        _post(server, token, {"seq": 2, "samples": [{"values": {"angle": 2.0}}]})["accepted"] == 1
    )


@pytest.mark.parametrize(
    ("body", "message"),
    [
        (b"{not json", "not JSON"),
        (b"[1, 2]", "JSON object"),
        (b'{"samples": []}', "`seq`"),
        (b'{"seq": -1, "samples": []}', "`seq`"),
        (b'{"seq": 1, "samples": {}}', "`samples` must be a list"),
        (b'{"seq": 1, "stream": "Bad Name", "samples": []}', "`stream`"),
        (b'{"seq": 1, "time_unit": "days", "samples": []}', "`time_unit`"),
    ],
)
def test_unreadable_batches_are_refused_whole(server: Server, body: bytes, message: str) -> None:
    _, (token,) = device_twin(server)
    with server.client(token) as device:
        r = device.post(
            "/api/v1/device/samples", content=body, headers={"Content-Type": "application/json"}
        )
    assert message in assert_problem(r, 422)["detail"]


def test_ingest_needs_a_device_token(server: Server) -> None:
    with server.client() as anonymous:
        assert_problem(anonymous.post("/api/v1/device/samples", json={"seq": 1}), 401)
    with server.admin as admin:  # a user token, even an admin's, is not a device token
        assert_problem(admin.post("/api/v1/device/samples", json={"seq": 1}), 401)


def test_a_device_writes_only_its_own_twin(server: Server) -> None:
    slug_a, (token_a,) = device_twin(server)
    slug_b, _ = device_twin(server)
    # There is no way to name another twin: the token decides; a `twin` key is ignored.
    _post(server, token_a, {"seq": 1, "twin": slug_b, "samples": [{"values": {"x": 1}}]})
    assert stored_values(server, slug_a, "x") == [1]
    assert stored_values(server, slug_b, "x") == []


def test_websocket_acks_each_batch_after_storing_it(server: Server) -> None:
    slug, (token,) = device_twin(server, INTERFACE)
    with device_socket(server, token) as ws:
        welcome = receive(ws, "welcome")
        assert (welcome["twin"], welcome["device"]) == (slug, "dev0")
        now = time.time_ns()
        for seq in range(1, 21):
            rows = [
                {"time": now + seq * 1000 + i, "values": {"angle": 0.01 * i}} for i in range(50)
            ]
            send(ws, batch(seq, rows))
        send(ws, batch(21, [{"values": {"angle": 9}}]))
        acks = {}
        while len(acks) < 21:
            ack = receive(ws, "ack")
            acks[ack["seq"]] = ack
        assert all(acks[s]["accepted"] == 50 for s in range(1, 21))
        assert (
            acks[21]["accepted"] == 0 and "above the maximum" in acks[21]["rejected"][0]["reason"]
        )
        send(ws, batch(5, [{"values": {"angle": 0.5}}]))  # a resend: stored once
        assert receive(ws, "ack")["duplicate"] is True
    assert len(stored_values(server, slug, "angle")) == 20 * 50


def test_websocket_errors_keep_the_connection_open(server: Server) -> None:
    _, (token,) = device_twin(server)
    with device_socket(server, token) as ws:
        receive(ws, "welcome")
        ws.send("not json")
        assert "not JSON" in receive(ws, "error")["message"]
        ws.send("[1]")
        assert "JSON object" in receive(ws, "error")["message"]
        send(ws, {"type": "launch"})
        assert "unknown message type 'launch'" in receive(ws, "error")["message"]
        send(ws, {"type": "samples", "seq": 3, "samples": "many"})
        error = receive(ws, "error")
        assert error["seq"] == 3 and error["fatal"] is False
        send(ws, {"type": "ping"})
        assert receive(ws, "pong")["server_time"] > 0
        send(ws, batch(4, [{"values": {"x": 1}}]))
        assert receive(ws, "ack")["accepted"] == 1


def test_websocket_without_a_valid_token_is_closed_with_4401(server: Server) -> None:
    for token in (None, "tld_not-a-real-token", server.admin_token):
        with device_socket(server, token) as ws, pytest.raises(ConnectionClosed) as closed:
            receive(ws)
        assert closed.value.rcvd is not None and closed.value.rcvd.code == 4401


def test_an_oversized_frame_closes_the_connection_with_1009(server: Server) -> None:
    _, (token,) = device_twin(server)
    big = json.dumps(batch(1, [{"values": {"s": "x" * 1000}}] * 17_000))
    assert len(big) > 16 * 1024 * 1024
    with device_socket(server, token) as ws:
        receive(ws, "welcome")
        with pytest.raises(ConnectionClosed) as closed:
            ws.send(big)
            receive(ws)
        assert closed.value.rcvd is not None and closed.value.rcvd.code == 1009
    with device_socket(server, token) as ws:  # the device can come back
        receive(ws, "welcome")
        send(ws, batch(2, [{"values": {"x": 1}}]))
        assert receive(ws, "ack")["accepted"] == 1


def test_a_revoked_device_token_is_refused(server: Server) -> None:
    slug, (token,) = device_twin(server)
    with server.admin as admin:
        assert admin.post(f"/api/v1/twins/{slug}/devices/dev0/token").status_code == 200
    with server.client(token) as device:
        assert_problem(device.post("/api/v1/device/samples", json={"seq": 1}), 401)
    with device_socket(server, token) as ws, pytest.raises(ConnectionClosed) as closed:
        receive(ws)
    assert closed.value.rcvd is not None and closed.value.rcvd.code == 4401


def test_a_second_connection_of_a_device_replaces_the_first(server: Server) -> None:
    _, (token,) = device_twin(server)
    with device_socket(server, token) as first:
        receive(first, "welcome")
        with device_socket(server, token) as second:
            receive(second, "welcome")
            with pytest.raises(ConnectionClosed) as closed:
                receive(first)
            assert closed.value.rcvd is not None and closed.value.rcvd.code == 4409
            send(second, batch(1, [{"values": {"x": 1}}]))
            assert receive(second, "ack")["accepted"] == 1


def test_metrics_count_samples_and_connected_devices(server: Server) -> None:
    def figure(name: str) -> float:
        with server.admin as admin:
            text = admin.get("/metrics").text
        line = next(x for x in text.splitlines() if x.startswith(name + " "))
        return float(line.split()[1])

    _, (token,) = device_twin(server, INTERFACE)
    accepted, rejected = (
        figure("twinlink_samples_accepted_total"),
        figure("twinlink_samples_rejected_total"),
    )
    _post(
        server,
        token,
        {"seq": 1, "samples": [{"values": {"angle": 0.5}}] * 3 + [{"values": {"angle": 7}}]},
    )
    assert figure("twinlink_samples_accepted_total") == accepted + 3
    assert figure("twinlink_samples_rejected_total") == rejected + 1
    assert figure("twinlink_history_commits_total") >= 1
    with device_socket(server, token) as ws:
        receive(ws, "welcome")
        assert figure("twinlink_devices_connected") >= 1
