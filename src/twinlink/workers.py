"""`twinlink up --workers N`: N server processes on one machine, nodes of one scale-out setup.

The parent binds the HTTP port once and hands the listening socket to every worker (they
accept from one queue, as uvicorn's and gunicorn's workers do); the embedded MQTT listener's
port is shared with SO_REUSEPORT (the kernel spreads the connections). State and messages go
through PostgreSQL and Kafka as between nodes on several machines, which is why more than one
worker needs them (config.py checks). The parent serves nothing itself: it starts the first
worker alone (it migrates the database and makes the first admin), then the others, says
`twinlink serving at` once all serve, starts again a worker that dies (after a back-off),
and stops them all on SIGINT or SIGTERM.

A worker is `python -m twinlink.workers`, given its settings on stdin (the parent's, secrets
included: never on the command line or in the environment, which other users may read)."""

from __future__ import annotations

import asyncio
import contextlib
import ctypes
import json
import logging
import os
import signal
import socket
import sys
from typing import Any

from pydantic import SecretStr

from twinlink.auth.vault import Vault
from twinlink.config import Settings
from twinlink.logs import setup_logging
from twinlink.server import listen, serve

log = logging.getLogger("twinlink.workers")

STOP_TIMEOUT_S = 20.0  # a worker's clean stop: requests end within 5 s, then its parts stop
BACKOFF_S = (1.0, 2.0, 5.0, 10.0, 30.0)  # before starting again a worker that died
HEALTHY_S = 60.0  # a worker that served this long starts again after the shortest back-off
_PR_SET_PDEATHSIG = 1


def run(settings: Settings) -> int:
    """Run `settings.workers` workers until SIGINT or SIGTERM; the exit status."""
    setup_logging(settings.log_level, settings.log_format)
    if settings.secret_key is None:
        # Made once here: workers racing to create secret.key would each make their own.
        Vault.open(settings.data_dir, None)
    sock = listen(settings)  # binds the port (port 0: picks one) and checks MQTT's is free
    mqtt = _reserve_mqtt_port(settings)
    try:
        return asyncio.run(_Supervisor(settings, sock).run())
    finally:
        sock.close()
        if mqtt is not None:
            mqtt.close()


def _reserve_mqtt_port(settings: Settings) -> socket.socket | None:
    """The embedded MQTT listener's port bound (not listening: it takes no connections) with
    SO_REUSEPORT, so that port 0 becomes one port every worker listens on, and no other
    program takes it while a worker restarts."""
    if settings.mqtt_mode != "embedded":
        return None
    family = socket.AF_INET6 if ":" in settings.mqtt_host else socket.AF_INET
    holder = socket.socket(family, socket.SOCK_STREAM)
    holder.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    holder.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEPORT, 1)
    holder.bind((settings.mqtt_host, settings.mqtt_port))
    settings.mqtt_port = holder.getsockname()[1]
    return holder


def _revealed(settings: Settings) -> dict[str, Any]:
    """The settings as JSON values, secrets in clear: for the worker's stdin only."""
    data = settings.model_dump(mode="json")
    for name in type(settings).model_fields:
        value = getattr(settings, name)
        if isinstance(value, SecretStr):
            data[name] = value.get_secret_value()
    return data


def _die_with_parent() -> None:
    """In the worker, before exec: SIGTERM when the parent dies, even by SIGKILL, so no
    worker outlives it (they are in a session of their own, apart from the terminal's
    Ctrl-C, which the parent passes on)."""
    libc = ctypes.CDLL(None, use_errno=True)
    libc.prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)


class _Supervisor:
    def __init__(self, settings: Settings, sock: socket.socket) -> None:
        self.settings = settings
        self.sock = sock
        self.workers: dict[int, asyncio.subprocess.Process] = {}
        self.stopping = asyncio.Event()

    async def run(self) -> int:
        loop = asyncio.get_running_loop()
        for sig in (signal.SIGINT, signal.SIGTERM):
            loop.add_signal_handler(sig, self.stopping.set)
        indexes = range(1, self.settings.workers + 1)
        # The first alone: it migrates the database and makes the first admin, once.
        started = [await self._start(1)]
        if started[0]:
            started += await asyncio.gather(*(self._start(i) for i in indexes[1:]))
        if not all(started) or self.stopping.is_set():
            await self._stop_all()
            return 0 if all(started) else 1  # a worker that failed said why on stderr
        print(
            f"twinlink serving at {self.settings.base_url} ({self.settings.workers} workers)",
            file=sys.stderr,
            flush=True,
        )
        watchers = [asyncio.create_task(self._watch(i)) for i in indexes]
        await self.stopping.wait()
        for watcher in watchers:
            watcher.cancel()
        await asyncio.gather(*watchers, return_exceptions=True)
        await self._stop_all()
        return 0

    async def _start(self, index: int) -> bool:
        """Start worker `index`; True once it serves, False when it ended first (or a stop
        came)."""
        ready_r, ready_w = os.pipe()
        fd = self.sock.fileno()
        job = {"index": index, "fd": fd, "ready_fd": ready_w, "settings": _revealed(self.settings)}
        try:
            proc = await asyncio.create_subprocess_exec(
                sys.executable, "-m", "twinlink.workers",
                stdin=asyncio.subprocess.PIPE, pass_fds=(fd, ready_w),
                start_new_session=True, preexec_fn=_die_with_parent,
            )  # fmt: skip
        finally:
            os.close(ready_w)
        self.workers[index] = proc
        assert proc.stdin is not None
        proc.stdin.write(json.dumps(job).encode())
        proc.stdin.close()
        ready = asyncio.ensure_future(_read_byte(ready_r))
        ended = asyncio.ensure_future(proc.wait())
        stop = asyncio.ensure_future(self.stopping.wait())
        await asyncio.wait((ready, ended, stop), return_when=asyncio.FIRST_COMPLETED)
        for waiter in (ready, ended, stop):
            waiter.cancel()
        await asyncio.gather(ready, ended, stop, return_exceptions=True)
        served = ready.done() and not ready.cancelled() and ready.result()
        if served:
            log.info("worker %d serving (pid %d)", index, proc.pid,
                     extra={"event": "worker_ready", "worker": index, "pid": proc.pid})  # fmt: skip
        return bool(served) and not self.stopping.is_set()

    async def _watch(self, index: int) -> None:
        """Start worker `index` again each time it dies, after a back-off that grows while it
        keeps dying and goes back to the shortest once it served for a while."""
        failures = 0
        loop = asyncio.get_running_loop()
        while True:
            proc = self.workers[index]
            began = loop.time()
            code = await proc.wait()
            failures = 0 if loop.time() - began > HEALTHY_S else failures + 1
            delay = BACKOFF_S[min(max(failures - 1, 0), len(BACKOFF_S) - 1)]
            log.warning(
                "worker %d (pid %d) ended with code %s; starting it again in %.0f s",
                index, proc.pid, code, delay,
                extra={"event": "worker_ended", "worker": index, "code": code},
            )  # fmt: skip
            with contextlib.suppress(TimeoutError):
                await asyncio.wait_for(self.stopping.wait(), delay)
                return
            await self._start(index)

    async def _stop_all(self) -> None:
        live = [p for p in self.workers.values() if p.returncode is None]
        for proc in live:
            with contextlib.suppress(ProcessLookupError):
                proc.send_signal(signal.SIGTERM)
        try:
            await asyncio.wait_for(asyncio.gather(*(p.wait() for p in live)), STOP_TIMEOUT_S)
        except TimeoutError:
            for proc in live:
                if proc.returncode is None:
                    log.warning("worker pid %d did not stop in %.0f s; killed", proc.pid,
                                STOP_TIMEOUT_S, extra={"event": "worker_killed"})  # fmt: skip
                    with contextlib.suppress(ProcessLookupError):
                        proc.kill()
            await asyncio.gather(*(p.wait() for p in live))


async def _read_byte(fd: int) -> bool:
    """Whether the worker wrote its "serving" byte before closing the pipe (by ending)."""
    loop = asyncio.get_running_loop()
    reader = asyncio.StreamReader()
    transport, _ = await loop.connect_read_pipe(
        lambda: asyncio.StreamReaderProtocol(reader), os.fdopen(fd, "rb", 0)
    )
    try:
        return await reader.read(1) == b"1"
    finally:
        transport.close()


def worker_main() -> None:
    """A worker: serve on the inherited socket with the settings read from stdin."""
    job = json.loads(sys.stdin.read())
    settings = Settings(**job["settings"])
    sock = socket.socket(fileno=job["fd"])
    ready_fd: int = job["ready_fd"]

    def serving(_: Settings) -> None:
        os.write(ready_fd, b"1")
        os.close(ready_fd)

    serve(settings, sock=sock, serving=serving)


if __name__ == "__main__":
    worker_main()
