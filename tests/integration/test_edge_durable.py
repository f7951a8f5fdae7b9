"""The device SDK's durable mode against the real server: a device process killed with SIGKILL
right after `add()` returned for sample k loses none of samples 0..k. A new device on the same
folder delivers each of them, once, together with whatever the killed one added after k."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import Server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._live import device_twin
from tests.integration.test_edge_sdk import BASE_NS, TIMEOUT, history
from twinlink_edge import Device

pytestmark = pytest.mark.integration

# Adds samples i = 0, 1, ... as fast as it can and prints each i once add() has returned.
CHILD = """
import sys
from twinlink_edge import Device

url, token, folder, batch_size, flush_interval, base_ns = sys.argv[1:]
dev = Device(url, token, buffer=folder, durable=True, batch_size=int(batch_size),
             flush_interval=float(flush_interval))
dev.start()
i = 0
while True:
    dev.add({"i": i}, time_ns=int(base_ns) + i)
    print(i, flush=True)
    i += 1
"""


@pytest.mark.parametrize(
    ("batch_size", "flush_interval", "k"),
    [
        (100, 0.05, 1234),  # batches sealed and in flight when it dies, acks lost with it
        (100, 3600.0, 1234),  # the 35 samples after the last full batch: never sealed
    ],
)
def test_a_device_killed_after_add_loses_no_sample_added(
    server: Server, tmp_path: Path, batch_size: int, flush_interval: float, k: int
) -> None:
    slug, (token,) = device_twin(server)
    folder = tmp_path / "buffer"
    args = [server.url, token, str(folder), str(batch_size), str(flush_interval), str(BASE_NS)]
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD, *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert child.stdout is not None
        for line in child.stdout:
            if int(line) == k:  # add() returned for sample k: kill it now
                os.kill(child.pid, signal.SIGKILL)
                break
    finally:
        child.kill()
        _, stderr = child.communicate(timeout=TIMEOUT)
    assert child.returncode == -signal.SIGKILL, stderr
    with Device(server.url, token, buffer=folder) as dev:
        assert dev.buffered_samples > 0
        dev.flush(TIMEOUT)
        assert dev.buffered_samples == 0
    values = [row["values"]["i"] for row in history(server, slug)]
    # Samples 0..k, and those the child added between printing k and dying: each once.
    assert len(values) > k and values == list(range(len(values)))
