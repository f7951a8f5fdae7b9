"""A server whose data folder is on a small tmpfs that the test fills up and frees again:
issue 13's F1 (acknowledged samples under another signal's name after a failed commit), F2
(authentication while the disk is full) and F3 (the log, the metrics, the shutdown)."""

from __future__ import annotations

import contextlib
import json
import signal
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import connect

from tests.conftest import Server, start_server, stop_server
from tests.integration._live import (
    batch,
    device_socket,
    device_twin,
    receive,
    send,
    stored_values,
    ws_url,
)
from tests.integration._util import assert_problem, parse_time, poll_until

pytestmark = pytest.mark.integration

DISK_MB = 30


@contextlib.contextmanager
def small_disk(where: Path) -> Iterator[Path]:
    where.mkdir()
    mounted = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", f"size={DISK_MB}m", "tmpfs", str(where)],
        capture_output=True,
        text=True,
    )
    if mounted.returncode != 0:
        pytest.skip(f"cannot mount a {DISK_MB} MB tmpfs (needs root): {mounted.stderr.strip()}")
    try:
        yield where
    finally:
        subprocess.run(["umount", "-l", str(where)], check=False)


class Ballast:
    """A file that takes all the space left on the disk, until `free`."""

    def __init__(self, disk: Path) -> None:
        self.path = disk / "ballast"

    def fill(self) -> None:
        # Unbuffered, so that nothing is left to flush (and fail) on close; ever smaller
        # writes take the last bytes too.
        with self.path.open("ab", buffering=0) as f:
            for size in (1 << 20, 1 << 12, 1):
                with contextlib.suppress(OSError):
                    while True:
                        f.write(b"\0" * size)

    def free(self) -> None:
        self.path.unlink(missing_ok=True)


@pytest.fixture(scope="module")
def disk(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    with small_disk(tmp_path_factory.mktemp("disk") / "mnt") as mounted:
        yield mounted


@pytest.fixture(scope="module")
def server(disk: Path) -> Iterator[Server]:
    srv = start_server(disk / "data", {"TWINLINK_DEVICE_TOKEN_RECHECK_S": "0.2"})
    try:
        yield srv
    finally:
        Ballast(disk).free()
        stop_server(srv)


def new_token(server: Server) -> str:
    with server.admin as admin:
        r = admin.post("/api/v1/tokens", json={"name": "disk-full"})
    assert r.status_code == 201, r.text
    return str(r.json()["token"])


def metric(server: Server, name: str) -> float:
    with server.admin as admin:
        text = admin.get("/metrics").text
    line = next(x for x in text.splitlines() if x.startswith(name + " "))
    return float(line.split()[1])


def last_seen(server: Server, slug: str) -> float:
    with server.admin as admin:
        r = admin.get(f"/api/v1/twins/{slug}/devices/dev0")
    assert r.status_code == 200, r.text
    return parse_time(r.json()["last_seen"])


def test_a_full_disk_refuses_batches_without_mixing_up_signals(server: Server, disk: Path) -> None:
    ballast = Ballast(disk)
    slug, (token,) = device_twin(server)
    fresh = [new_token(server) for _ in range(2)]  # never used: their first use is later
    a_values = [float(i) for i in range(20_000)]
    seq2 = batch(2, [{"time": 10**18 + i, "values": {"A": v}} for i, v in enumerate(a_values)])
    with device_socket(server, token) as ws:
        receive(ws, "welcome")
        send(ws, batch(1, [{"values": {"w": 1.5}}]))
        assert receive(ws, "ack")["accepted"] == 1

        ballast.fill()
        full_since = time.time()
        send(ws, seq2)
        error = receive(ws, "error")
        assert (error["seq"], error["retry"]) == (2, True)
        assert (
            "storage is full" in error["message"]
            and "nothing of this was stored" in (error["message"])
        )
        with server.client(token) as device:  # the same over HTTP: 507, try again later
            r = device.post("/api/v1/device/samples", json={**seq2, "seq": 9})
            body = assert_problem(r, 507)
            assert "storage is full" in body["detail"] and r.headers["retry-after"] == "30"

        # Authentication keeps working, though a token's first use is a "last used" time
        # to store: requests, live views and new device connections (the times wait in
        # memory until the disk takes them).
        with server.client(fresh[0]) as user:
            assert user.get("/api/v1/twins").status_code == 200
        bearer = {"Authorization": f"Bearer {fresh[1]}"}
        with connect(ws_url(server, "/api/v1/live"), additional_headers=bearer) as live:
            assert json.loads(live.recv(timeout=30))["type"] == "welcome"
            live.send(json.dumps({"op": "subscribe", "id": "a", "twin": slug}))
            assert json.loads(live.recv(timeout=30))["type"] == "subscribed"
        with device_socket(server, token) as second:
            assert receive(second, "welcome")["device"] == "dev0"
        # The first connection was replaced (4409) by the second: the rest goes on a third.
    with device_socket(server, token) as ws:
        receive(ws, "welcome")
        # The token is checked again every 0.2 s, while the disk is full too.
        poll_until(lambda: last_seen(server, slug) > full_since + 0.5, "token rechecks")
        assert metric(server, "twinlink_storage_full_total") >= 2

        ballast.free()
        send(ws, batch(3, [{"values": {"B": v}} for v in (7.0, 8.0, 9.0)]))
        assert receive(ws, "ack")["accepted"] == 3
        send(ws, seq2)  # resent: stored now, once, under its own name
        ack = receive(ws, "ack")
        assert (ack["accepted"], ack["duplicate"]) == (20_000, False)
        send(ws, seq2)
        assert receive(ws, "ack")["duplicate"] is True

    assert stored_values(server, slug, "w") == [1.5]
    assert stored_values(server, slug, "B") == [7.0, 8.0, 9.0]
    assert stored_values(server, slug, "A") == a_values
    log = server.log()
    assert "Traceback" not in log
    # One line when it began (for each file that refused), not one per failed batch.
    assert 1 <= log.count('"storage full: database or disk is full') <= 3, log[-3000:]
    assert "storage writable again" in log


def test_a_replaced_device_token_is_cut_off_after_the_disk_was_full(
    server: Server, disk: Path
) -> None:
    ballast = Ballast(disk)
    slug, (token,) = device_twin(server)
    with device_socket(server, token) as ws:
        receive(ws, "welcome")
        ballast.fill()
        full_since = time.time()
        poll_until(lambda: last_seen(server, slug) > full_since + 0.5, "token rechecks")
        with server.admin as admin:  # replacing it is a write: refused while full
            assert_problem(admin.post(f"/api/v1/twins/{slug}/devices/dev0/token"), 507)
        ballast.free()
        with server.admin as admin:
            r = admin.post(f"/api/v1/twins/{slug}/devices/dev0/token")
            assert r.status_code == 200, r.text
        with pytest.raises(ConnectionClosed) as closed:
            while True:
                receive(ws)
        assert closed.value.rcvd is not None and closed.value.rcvd.code == 4401


def test_the_server_shuts_down_cleanly_on_a_full_disk(server: Server, disk: Path) -> None:
    ballast = Ballast(disk)
    _, (token,) = device_twin(server)
    with device_socket(server, token) as ws:
        receive(ws, "welcome")
        send(ws, batch(1, [{"values": {"x": 1}}]))
        assert receive(ws, "ack")["accepted"] == 1
    ballast.fill()
    stop_server(server)
    # uvicorn ends with the signal that stopped it once shut down; a kill would be -9
    assert server.process.returncode in (0, -signal.SIGTERM), server.log()[-3000:]
    log = server.log()
    assert "Application shutdown failed" not in log
    assert "Traceback" not in log
