"""twinlink.client against a real server: history as a DataFrame (values and times of
samples a device sent, pages followed), search, twins, and refusals as ApiError."""

from __future__ import annotations

import math
from collections.abc import Iterator
from datetime import UTC, datetime
from typing import Any

import pandas as pd
import pytest

from tests.conftest import Server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._live import device_twin
from twinlink.client import ApiError, Client
from twinlink.client import history as client_history

pytestmark = pytest.mark.integration

S = 10**9
T0 = 1_767_225_600 * S  # 2026-01-01T00:00:00Z
ROWS = 2_500


def _rows() -> list[dict[str, Any]]:
    rows = []
    for i in range(ROWS):
        values: dict[str, Any] = {"x": i / 4, "n": 3 * i}
        if i % 10 == 0:
            values["mode"] = "run" if i % 20 else "idle"
        rows.append({"time": T0 + i * S // 10, "values": values})
    return rows


@pytest.fixture(scope="module")
def twin(server: Server) -> str:
    slug, [token] = device_twin(server)
    rows = _rows()
    with server.client(token) as device:
        for seq, first in enumerate(range(0, ROWS, 1000), start=1):
            r = device.post(
                "/api/v1/device/samples", json={"seq": seq, "samples": rows[first : first + 1000]}
            )
            assert r.status_code == 200, r.text
    return slug


@pytest.fixture
def client(server: Server) -> Iterator[Client]:
    with Client(server.url, server.admin_token) as c:
        yield c


def test_history_is_a_dataframe_of_the_samples_sent(
    client: Client, twin: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(client_history, "PAGE_ROWS", 700)  # four pages: the cursor followed
    frame = client.history(twin)
    assert len(frame) == ROWS
    assert isinstance(frame.index, pd.DatetimeIndex) and str(frame.index.tz) == "UTC"
    assert frame.index.name == "time"
    assert frame.index[0] == pd.Timestamp("2026-01-01T00:00:00Z")
    assert [t.value for t in frame.index] == [T0 + i * S // 10 for i in range(ROWS)]
    assert sorted(frame.columns) == ["mode", "n", "x"]
    assert frame["x"].tolist() == [i / 4 for i in range(ROWS)]
    assert frame["n"].tolist() == [3 * i for i in range(ROWS)]
    assert frame["mode"].iloc[10] == "run" and frame["mode"].iloc[20] == "idle"
    assert frame["mode"].iloc[11] is None or math.isnan(frame["mode"].iloc[11])


def test_history_narrowed_by_time_and_signals(client: Client, twin: str) -> None:
    start = datetime(2026, 1, 1, 0, 1, tzinfo=UTC)  # sample 600
    frame = client.history(twin, start=start, end=T0 + 609 * S // 10, signals=["n", "x"])
    assert list(frame.columns) == ["n", "x"]  # in the order asked for
    assert frame["n"].tolist() == [3 * i for i in range(600, 610)]
    naive = client.history(twin, start=datetime(2026, 1, 1, 0, 4, 9, 900_000), signals=["n"])
    assert naive["n"].tolist() == [3 * (ROWS - 1)]  # a naive datetime is taken as UTC
    empty = client.history(twin, start="2030-01-01T00:00:00Z", signals=["x", "n"])
    assert empty.empty and list(empty.columns) == ["x", "n"]
    assert isinstance(empty.index, pd.DatetimeIndex)


def test_search_twins_and_streams(client: Client, twin: str) -> None:
    assert any(t["slug"] == twin for t in client.twins())
    assert twin in [hit.get("slug") for hit in client.search(twin.split("-")[0])]
    [stream] = client.streams(twin)
    assert stream["name"] == "telemetry" and stream["samples"] == ROWS
    assert client.me()["is_admin"] is True


def test_refusals_are_api_errors_with_the_problem(
    server: Server, client: Client, twin: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    with pytest.raises(ApiError) as missing:
        client.history("no-such-twin")
    assert missing.value.status == 404 and "no-such-twin" in missing.value.detail
    with pytest.raises(ApiError) as bad:
        client.history(twin, start="yesterday-ish")
    assert bad.value.status == 422 and "start" in bad.value.detail
    with pytest.raises(ApiError, match="has no signal 'gone'"):
        client.history(twin, signals=["x", "gone"])
    monkeypatch.setenv("TWINLINK_URL", server.url)
    monkeypatch.setenv("TWINLINK_TOKEN", "tl_not_a_token")
    with Client() as stranger, pytest.raises(ApiError) as refused:
        stranger.twins()
    assert refused.value.status == 401 and "TWINLINK_TOKEN" in str(refused.value)
    with Client("http://127.0.0.1:9", "x") as away, pytest.raises(ApiError) as unreachable:
        away.twins()
    assert unreachable.value.status is None and "cannot reach" in str(unreachable.value)
