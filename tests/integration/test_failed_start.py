"""A start that fails part way stops what the steps before it started: here the embedded MQTT
listener's port is taken, one of the last steps, after the stores, the history writer, the
gateway and the processors have started. No task or thread of the platform is left running,
and the error raised is the start's, even when stopping one of the others fails too."""

from __future__ import annotations

import asyncio
import logging
import os
import socket
import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from twinlink.app import Services, build_services, create_app, start_services, stop_services
from twinlink.config import Settings
from twinlink.ingest.mqtt.listener import ListenerError

pytestmark = pytest.mark.integration

# The workers of the loop's default executor (asyncio.to_thread) live as long as the loop.
EXECUTOR_THREAD = "asyncio_"


@pytest.fixture
def taken_port() -> Iterator[int]:
    """A loopback port another socket listens on."""
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        sock.listen()
        yield int(sock.getsockname()[1])


def platform(data_dir: Path, mqtt_port: int) -> tuple[Services, Settings]:
    settings = Settings(data_dir=data_dir, mqtt_host="127.0.0.1", mqtt_port=mqtt_port)
    return build_services(settings), settings


def running() -> tuple[set[asyncio.Task[Any]], set[threading.Thread]]:
    """This loop's other tasks and this process's threads but the executor's."""
    tasks = asyncio.all_tasks() - {asyncio.current_task()}
    threads = {t for t in threading.enumerate() if not t.name.startswith(EXECUTOR_THREAD)}
    return tasks, threads


async def test_a_failed_start_leaves_nothing_running(tmp_path: Path, taken_port: int) -> None:
    # what a start that succeeds runs, so that the check below cannot pass for want of it
    services, settings = platform(tmp_path / "good", 0)
    before_tasks, before_threads = running()
    await start_services(services, settings)
    try:
        tasks, _ = running()
        names = {task.get_name() for task in tasks - before_tasks}
        assert {"history-writer", "last-used-writer", "gateway-health"} <= names, names
    finally:
        await stop_services(services)

    services, settings = platform(tmp_path / "bad", taken_port)
    with pytest.raises(ListenerError, match=f"cannot listen on 127.0.0.1:{taken_port}"):
        await start_services(services, settings)
    tasks, threads = running()
    assert tasks - before_tasks == set()
    assert threads - before_threads == set()


async def test_the_starts_error_is_raised_when_stopping_another_fails(
    tmp_path: Path,
    taken_port: int,
    caplog: pytest.LogCaptureFixture,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    services, settings = platform(tmp_path, taken_port)
    close_gateway = services.gateway.close

    async def gateway_fails_to_close() -> None:
        await close_gateway()
        raise OSError("the audit log's disk is gone")

    monkeypatch.setattr(services.gateway, "close", gateway_fails_to_close)
    before_tasks, before_threads = running()
    with pytest.raises(ListenerError, match="cannot listen"):
        await start_services(services, settings)
    tasks, threads = running()
    assert tasks - before_tasks == set()  # the others were stopped all the same
    assert threads - before_threads == set()
    [record] = [r for r in caplog.records if r.levelno == logging.ERROR]
    assert record.getMessage() == "stopping after a failed start"
    assert record.exc_info is not None and "disk is gone" in str(record.exc_info[1])


async def test_the_app_stops_its_services_when_its_ready_hook_fails(tmp_path: Path) -> None:
    # `twinlink demo` starts its devices in on_ready: one that fails must not leave the
    # platform's services running behind the error
    def ready(services: Services) -> None:
        raise RuntimeError("the demo's rig could not start")

    settings = Settings(data_dir=tmp_path, mqtt_host="127.0.0.1", mqtt_port=0)
    app = create_app(settings, on_ready=ready)
    before_tasks, before_threads = running()
    with pytest.raises(RuntimeError, match="rig could not start"):
        async with app.router.lifespan_context(app):
            pass
    tasks, threads = running()
    assert tasks - before_tasks == set()
    assert threads - before_threads == set()


def test_twinlink_up_says_why_it_cannot_start_without_a_traceback(tmp_path: Path) -> None:
    # a PostgreSQL that cannot be reached: a reason a person can act on, so one clear line
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        closed = sock.getsockname()[1]  # nothing listens here once the socket is closed
    env = {
        **os.environ,
        "TWINLINK_DATA_DIR": str(tmp_path),
        "TWINLINK_STORE_URL": f"postgresql://twin:pa55word@127.0.0.1:{closed}/twinlink",
        "TWINLINK_MQTT_MODE": "off",
    }
    done = subprocess.run(
        [sys.executable, "-m", "twinlink", "up", "--port", "0"],
        env=env,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode != 0
    assert "cannot start: Cannot connect to PostgreSQL" in done.stderr
    assert "Traceback" not in done.stderr and "pa55word" not in done.stderr
