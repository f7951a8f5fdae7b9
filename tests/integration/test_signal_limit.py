"""TWINLINK_MAX_SIGNALS_PER_STREAM: a batch that would give its stream more signals is
refused whole, over HTTP (422) and the device WebSocket (an error without retry)."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from tests.conftest import Server, start_server, stop_server
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

LIMIT = 5


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    srv = start_server(
        tmp_path_factory.mktemp("data"), {"TWINLINK_MAX_SIGNALS_PER_STREAM": str(LIMIT)}
    )
    try:
        yield srv
    finally:
        stop_server(srv)


def signals(first: int, count: int) -> dict[str, float]:
    return {f"s{i}": float(i) for i in range(first, first + count)}


def test_http_refuses_a_batch_that_would_pass_the_limit_whole(server: Server) -> None:
    slug, (token,) = device_twin(server)
    with server.client(token) as device:
        ok = device.post("/api/v1/device/samples", json={"seq": 1, "samples": [
            {"values": signals(0, 3)}]})  # fmt: skip
        assert ok.status_code == 200 and ok.json()["accepted"] == 1, ok.text
        r = device.post("/api/v1/device/samples", json={"seq": 2, "samples": [
            {"values": signals(0, 1)}, {"values": signals(3, 4)}]})  # fmt: skip
        body = assert_problem(r, 422)
        assert body["detail"] == (
            f"this batch would give stream 'telemetry' of twin '{slug}' 7 signals (new: 's3', "
            "'s4', 's5' and 1 more); a stream may have at most 5 (the server's "
            "TWINLINK_MAX_SIGNALS_PER_STREAM). The batch was not stored."
        )
        # Nothing of it was stored, not the known signal's sample either; within the
        # limit the same seq is taken (it was not recorded as stored).
        assert stored_values(server, slug, "s0") == [0.0]
        again = device.post("/api/v1/device/samples", json={"seq": 2, "samples": [
            {"values": signals(0, 5)}]})  # fmt: skip
        assert again.status_code == 200 and again.json()["duplicate"] is False, again.text
    assert stored_values(server, slug, "s4") == [4.0]


def test_websocket_answers_an_error_without_retry_and_stays_open(server: Server) -> None:
    slug, (token,) = device_twin(server)
    with device_socket(server, token) as ws:
        receive(ws, "welcome")
        send(ws, batch(1, [{"values": signals(0, LIMIT)}]))
        assert receive(ws, "ack")["accepted"] == 1
        send(ws, batch(2, [{"values": {"new": 1.0}}]))
        error = receive(ws, "error")
        assert error["seq"] == 2 and "retry" not in error
        assert "a stream may have at most 5" in error["message"]
        # known signals still go in, and another stream has a limit of its own
        send(ws, batch(3, [{"values": signals(0, 2)}]))
        assert receive(ws, "ack")["accepted"] == 1
        send(ws, batch(4, [{"values": {"new": 1.0}}], stream="other"))
        assert receive(ws, "ack")["accepted"] == 1
    assert stored_values(server, slug, "new") == [1.0]  # the one in stream "other"
