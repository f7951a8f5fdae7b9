"""Processors end to end: a real server, worker processes, the bus, history and live views."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from tests.conftest import Server, stop_server
from tests.integration._live import device_twin
from tests.integration._processors import (
    create,
    post,
    processor_server,
    samples_until,
    wait_for,
    watching,
)

pytestmark = pytest.mark.integration


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    srv = processor_server(tmp_path_factory.mktemp("data"))
    try:
        yield srv
    finally:
        stop_server(srv)


def test_a_processor_turns_a_stream_into_another(server: Server) -> None:
    slug, [device] = device_twin(server)
    create(server, slug, name="doubled", blueprint="test-gain", params={"signals": ["x"]})
    wait_for(server, slug, "doubled", lambda p: p["state"] == "running")
    with watching(server, slug, "doubled") as ws:
        post(server, device, 1, [{"x": 1.0}, {"x": 2.5}, {"y": 7}])
        got = samples_until(ws, lambda s: len(s) >= 3)
    assert [s["values"] for s in got] == [
        {"x": 2.0, "seen": 1.0},
        {"x": 5.0, "seen": 2.0},
        {"seen": 3.0},
    ]
