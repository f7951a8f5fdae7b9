"""The device SDK through outages of the real server: killed mid-stream and restarted on the
same port and data, it reconnects by itself and resends what had no ack, and nothing is lost
or stored twice; with a disk buffer, what waited survives a restart of the device too."""

from __future__ import annotations

import threading
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.conftest import Server, restart_server, start_server, stop_server
from tests.integration._live import device_twin
from tests.integration.test_edge_sdk import BASE_NS, TIMEOUT, history
from twinlink_edge import Ack, Device

pytestmark = pytest.mark.integration


@pytest.fixture
def servers(tmp_path: Path) -> Iterator[list[Server]]:
    """A server of this test's own (it gets killed); each restart is appended."""
    started = [start_server(tmp_path / "data")]
    try:
        yield started
    finally:
        for server in started:
            stop_server(server)


def test_a_server_killed_mid_stream_loses_nothing(servers: list[Server]) -> None:
    server = servers[0]
    slug, (token,) = device_twin(server)
    acks = 0
    killed = threading.Event()

    def kill_after_a_few(ack: Ack) -> None:  # runs on the SDK's thread, as acks arrive
        nonlocal acks
        acks += 1
        if acks == 13 and not killed.is_set():
            server.process.kill()  # SIGKILL while batches are in flight
            killed.set()

    options = {"batch_size": 100, "backoff_max": 0.5, "on_ack": kill_after_a_few}
    with Device(server.url, token, **options) as dev:
        for i in range(1000):
            dev.add({"n": i}, time_ns=BASE_NS + i)
        dev.flush(TIMEOUT)  # 10 acks
        for i in range(1000, 6000):
            dev.add({"n": i}, time_ns=BASE_NS + i)
        assert killed.wait(TIMEOUT)
        server.process.wait(TIMEOUT)
        for i in range(6000, 7000):  # the server is down: these wait in the buffer
            dev.add({"n": i}, time_ns=BASE_NS + i)
        assert dev.buffered_samples > 1000
        stop_server(server)
        servers.append(restart_server(server))
        dev.flush(60)
        stats = dev.stats()
    assert stats["connections"] >= 2 and stats["acked_samples"] == 7000
    assert stats["rejected"] == 0 and stats["refused_batches"] == 0
    values = [row["values"]["n"] for row in history(servers[-1], slug)]
    assert values == list(range(7000))  # each sample once, none missing


def test_the_disk_buffer_keeps_samples_across_a_restart_of_both(
    servers: list[Server], tmp_path: Path
) -> None:
    server = servers[0]
    slug, (token,) = device_twin(server)
    buffer = tmp_path / "buffer"
    with Device(server.url, token, buffer=buffer, batch_size=50) as dev:
        dev.add({"n": 0}, time_ns=BASE_NS)
        dev.flush(TIMEOUT)
    stop_server(server)
    # The device runs while the server is away, and stops before it is back.
    with Device(server.url, token, buffer=buffer, batch_size=50, close_timeout=0.1) as dev:
        for i in range(1, 501):
            dev.add({"n": i}, time_ns=BASE_NS + i)
    servers.append(restart_server(server))
    with Device(server.url, token, buffer=buffer) as dev:
        assert dev.buffered_samples == 500
        dev.flush(TIMEOUT)
        assert dev.acked_samples == 500
    assert [row["values"]["n"] for row in history(servers[-1], slug)] == list(range(501))
