"""Supervising one processor's worker process: start, feed, watch, restart, stop.

A worker that dies (an exception in the blueprint, a segfault in native FMU code, the memory
limit) is restarted after a backoff that doubles up to 30 s and resets once a worker has run for
a minute; each death is reported as an event with its cause and the last lines of its log.
Inputs that arrive while a worker is busy are sent as one batch when it is free (at most
MAX_INFLIGHT batches are in the worker at once), so a burst costs one round trip, not many;
inputs beyond `max_pending` samples, or while no worker runs, are dropped and counted.
A blueprint that finished (an FMU that ended its simulation) ends its worker normally: the
processor is then `finished`, with an event, and is neither restarted nor counted as crashed
until it is started again (`restart`).
`processed_t` is how far the worker got: the newest input time of the batches it answered
(a processor's position, saved on a shared store so another node can go on from there).
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import socket
import time
from collections import deque
from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import psutil

from twinlink.processors.blueprint import Batch
from twinlink.processors.exits import STOP_GRACE_S, ask_to_stop, exit_cause
from twinlink.processors.stats import ProcessorStats
from twinlink.processors.wire import ChannelClosed, frame, pack_batch, read_frame, unpack_batch
from twinlink.processors.workerenv import Cause, Interpreter, worker_environment, worker_python
from twinlink.processors.workerenv import EventTuple as EventTuple  # where others have it from

log = logging.getLogger("twinlink.processors")

MAX_INFLIGHT = 2
START_TIMEOUT_S = 60.0
BACKOFF_FIRST_S = 0.5
BACKOFF_MAX_S = 30.0
STABLE_AFTER_S = 60.0
MEMORY_POLL_S = 0.25
LOG_LINES = 500


@dataclass(slots=True)
class WorkerConfig:
    processor_id: int
    name: str
    twin: str
    ref: dict[str, str]
    params: dict[str, Any]
    inputs: dict[str, Any]
    rates: dict[str, Any]
    files: Path
    workdir: Path
    memory_limit_bytes: int
    batch_timeout_s: float = 30.0
    interpreter: Interpreter | None = None  # None: the server's Python

    def init_message(self) -> dict[str, Any]:
        return {
            "t": "init",
            "processor": self.name,
            "twin": self.twin,
            "ref": self.ref,
            "params": self.params,
            "inputs": self.inputs,
            "rates": self.rates,
            "files": str(self.files),
            "workdir": str(self.workdir),
        }

    @property
    def max_pending(self) -> int:
        return max(100_000, 10 * int(self.rates.get("max_batch", 10_000)))


class Supervisor:
    def __init__(
        self,
        config: WorkerConfig,
        on_output: Callable[[Batch], Awaitable[None]],
        on_events: Callable[[list[EventTuple]], None],
        on_commands: Callable[[list[list[Any]]], None],
    ) -> None:
        self.config = config
        self.on_output = on_output
        self.on_events = on_events
        self.on_commands = on_commands
        self.state = "stopped"  # starting, running, backoff, stopping, stopped, finished
        self.stats = ProcessorStats()
        self.logs: deque[tuple[int, str]] = deque(maxlen=LOG_LINES)
        self.info: dict[str, Any] = {}
        self.pid: int | None = None
        self.last_error: str | None = None
        self.restart_at: float | None = None
        self._pending: deque[tuple[Batch, float]] = deque()
        self._pending_samples = 0
        # (id, arrived, sent, newest input time) of each batch the worker has not answered
        self._inflight: deque[tuple[int, float, float, int | None]] = deque()
        self.processed_t: int | None = None
        self._room = asyncio.Event()  # set when queued input was taken or dropped
        self._next_id = 0
        self._wake = asyncio.Event()
        self._stop = asyncio.Event()
        self._task: asyncio.Task[None] | None = None
        self._proc: asyncio.subprocess.Process | None = None
        self._writer: asyncio.StreamWriter | None = None
        self._restart_requested = False
        self._over_memory: int | None = None
        self._hung: float | None = None
        self._failure: str | None = None
        self._configured: asyncio.Future[bool] | None = None
        self._finished: tuple[str, dict[str, Any]] | None = None  # the blueprint's last word

    # -- the server's side --------------------------------------------------------------

    def start(self) -> None:
        if self._task is not None and not self._task.done():
            return
        self._stop.clear()
        self._task = asyncio.create_task(self._run(), name=f"processor {self.config.name}")

    def finished(self, message: str) -> None:
        """Take up as finished (it was when the server stopped), without starting a worker."""
        self.state, self.last_error = "finished", None
        self.logs.append((time.time_ns(), f"finished before the server started: {message}"))

    def feed(self, batch: Batch, arrived: float) -> None:
        """Queue input for the worker (`arrived`: perf_counter when it reached the server)."""
        if self.state not in ("running", "starting"):  # a worker that starts gets it soon
            self.stats.dropped += len(batch)
            return
        self._pending.append((batch, arrived))
        self._pending_samples += len(batch)
        while self._pending_samples > self.config.max_pending and len(self._pending) > 1:
            old, _ = self._pending.popleft()
            self._pending_samples -= len(old)
            self.stats.dropped += len(old)
        self._wake.set()

    async def feed_in_turn(self, batch: Batch) -> None:
        """Queue `batch` once there is room for it (input replayed from history, which must
        not push out what is queued as `feed` would); dropped as by `feed` when no worker
        runs."""
        while (
            self._pending
            and self._pending_samples + len(batch) > self.config.max_pending
            and self.state in ("running", "starting")
        ):
            self._room.clear()
            await self._room.wait()
        self.feed(batch, time.perf_counter())

    async def reconfigure(self, config: WorkerConfig, params_only: bool) -> bool:
        """Use `config` from now on. True when the running worker kept its state."""
        self.config = config
        if self.state in ("finished", "failed"):  # changed: it starts again, from the start
            self.start()
            return False
        if self.state == "starting":  # it may have been sent the config before: start anew
            self._restart_requested = True
            await self._ask_to_stop()
            return False
        if self.state != "running" or self._writer is None:
            return False
        if params_only:
            self._configured = asyncio.get_running_loop().create_future()
            self._writer.write(frame({"t": "configure", "params": config.params}))
            with contextlib.suppress(TimeoutError):
                if await asyncio.wait_for(self._configured, 30):
                    return True
        await self.restart()
        return False

    async def restart(self) -> None:
        """Start a fresh worker now (not counted as a crash); a finished one (or one whose
        Python env could not be built) starts again."""
        if self.state in ("finished", "failed"):
            self.start()
        elif self.state == "running":
            self._restart_requested = True
            await self._ask_to_stop()

    async def stop(self) -> None:
        """Stop gracefully (the blueprint's `stop` runs), then by force."""
        self._stop.set()
        self._wake.set()
        self._room.set()
        if self.state == "running":
            self.state = "stopping"
        await self._ask_to_stop()
        if self._task is not None:
            await self._task

    # -- one worker after another ------------------------------------------------------

    async def _run(self) -> None:
        failures = 0
        loop = asyncio.get_running_loop()
        while not self._stop.is_set():
            began = loop.time()
            cause = await self._life()
            if self._stop.is_set():
                break
            if self._finished is not None:
                message, data = self._finished
                self.state, self.restart_at = "finished", None
                self.on_events([("finished", message, time.time_ns(), data)])
                return
            if cause is None:  # a restart that was asked for
                continue
            if cause[0] == "env_failed":  # building it again would fail the same way
                self.last_error = cause[1]
                self.on_events([("failed", cause[1], time.time_ns(), cause[2])])
                self.state = "failed"
                return
            failures = 1 if loop.time() - began >= STABLE_AFTER_S else failures + 1
            delay = min(BACKOFF_MAX_S, BACKOFF_FIRST_S * 2 ** (failures - 1))
            self.stats.restarts += 1
            kind, message, data = cause
            self.last_error = message
            self.on_events([(kind, message, time.time_ns(), {**data, "restart_in_s": delay})])
            self.state = "backoff"
            self.restart_at = time.time() + delay
            with contextlib.suppress(TimeoutError):
                await asyncio.wait_for(self._stop.wait(), delay)
        self.state = "stopped"
        self.restart_at = None
        self.on_events([("stopped", "stopped", time.time_ns(), {})])

    async def _life(self) -> Cause | None:
        """Run one worker until it exits; why it exited (None: it was asked to)."""
        self.state = "starting"
        self._restart_requested = False
        self._over_memory = self._hung = self._failure = self._finished = None
        python = await worker_python(self.config.interpreter, self._stop, self.on_events)
        if not isinstance(python, str) or self._restart_requested:
            return None if isinstance(python, str) else python
        parent, child = socket.socketpair()
        proc = await asyncio.create_subprocess_exec(
            python, "-m", "twinlink.processors.worker", str(child.fileno()),
            pass_fds=(child.fileno(),), stdin=asyncio.subprocess.DEVNULL,
            stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.STDOUT,
            start_new_session=True, env=worker_environment(),
        )  # fmt: skip
        child.close()
        self._proc, self.pid = proc, proc.pid
        assert proc.stdout is not None
        logs = asyncio.create_task(self._read_logs(proc.stdout))
        reader, writer = await asyncio.open_connection(sock=parent)
        self._writer = writer
        try:
            if await self._started(reader, writer):
                await self._serve(proc, reader, writer)
        finally:
            self._writer = None
            writer.close()
            # The channel closed: the worker is exiting (or hung); give it a moment to finish.
            with contextlib.suppress(TimeoutError):
                await asyncio.wait_for(proc.wait(), STOP_GRACE_S)
            if proc.returncode is None:
                proc.kill()
            await proc.wait()
            await logs
            self._proc = None
            self._abandon_inflight()
        return self._cause(proc.returncode)

    async def _started(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> bool:
        writer.write(frame(self.config.init_message()))
        try:
            ready = await asyncio.wait_for(read_frame(reader), START_TIMEOUT_S)
        except (ChannelClosed, TimeoutError):
            return False
        if ready["t"] != "ready":
            self._failure = f"could not start: {ready.get('error', ready)}"
            return False
        self.info = {k: ready[k] for k in ("inputs", "outputs", "describe")}
        self.state = "stopping" if self._stop.is_set() else "running"
        self.restart_at = None
        self.on_events([("started", "started", time.time_ns(), {"pid": ready["pid"]})])
        return True

    async def _serve(
        self,
        proc: asyncio.subprocess.Process,
        reader: asyncio.StreamReader,
        writer: asyncio.StreamWriter,
    ) -> None:
        tasks = [
            asyncio.create_task(self._send(writer)),
            asyncio.create_task(self._watch(proc)),
        ]
        try:
            await self._receive(reader)
        finally:
            for task in tasks:
                task.cancel()
            await asyncio.gather(*tasks, return_exceptions=True)

    async def _send(self, writer: asyncio.StreamWriter) -> None:
        while True:
            await self._wake.wait()
            self._wake.clear()
            while self._pending and len(self._inflight) < MAX_INFLIGHT:
                batches = [b for b, _ in self._pending]
                arrived = self._pending[0][1]
                self._pending.clear()
                self._pending_samples = 0
                self._room.set()
                batch = Batch.concat(batches)
                self._next_id += 1
                newest = int(batch.times.max()) if len(batch) else None
                self._inflight.append((self._next_id, arrived, time.monotonic(), newest))
                writer.write(frame({"t": "data", "id": self._next_id, **pack_batch(batch)}))
                self.stats.samples_in += len(batch)
                self.stats.batches += 1
            await writer.drain()

    async def _receive(self, reader: asyncio.StreamReader) -> None:
        with contextlib.suppress(ChannelClosed):
            while True:
                message = await read_frame(reader)
                kind = message["t"]
                if kind == "out":
                    await self._took_output(message)
                elif kind == "configured" and self._configured is not None:
                    if message["kept_state"]:
                        self.info = {k: message[k] for k in ("inputs", "outputs", "describe")}
                    if not self._configured.done():
                        self._configured.set_result(bool(message["kept_state"]))
                elif kind == "failed":
                    self._failure = f"{message['where']} failed: {message['error']}"

    async def _took_output(self, message: dict[str, Any]) -> None:
        _, arrived, _, newest = self._inflight.popleft()
        self._wake.set()
        self.stats.timed(message["timings"])
        if message["events"]:
            self.on_events([tuple(e) for e in message["events"]])
        if message["commands"]:
            self.on_commands(message["commands"])
        if "times" in message:
            out = unpack_batch(message)
            self.stats.samples_out += len(out)
            await self.on_output(out)
        if "finished" in message:  # the worker ends now, normally
            self._finished = (str(message["finished"][0]), dict(message["finished"][1]))
        if newest is not None and (self.processed_t is None or newest > self.processed_t):
            self.processed_t = newest  # answered, and its output handed on
        self.stats.latency_s.add(time.perf_counter() - arrived)

    async def _watch(self, proc: asyncio.subprocess.Process) -> None:
        """Kill a worker over its memory limit, or one stuck on a batch (a hung model)."""
        limit = self.config.memory_limit_bytes
        with contextlib.suppress(psutil.Error):
            watched = psutil.Process(proc.pid)
            while proc.returncode is None:
                rss = int(watched.memory_info().rss)
                self.stats.rss_bytes = rss
                if rss > limit:
                    self._over_memory = rss
                    proc.kill()
                    return
                if self._inflight:
                    waited = time.monotonic() - self._inflight[0][2]
                    if waited > self.config.batch_timeout_s:
                        self._hung = waited
                        proc.kill()
                        return
                await asyncio.sleep(MEMORY_POLL_S)

    async def _read_logs(self, stream: asyncio.StreamReader) -> None:
        while line := await stream.readline():
            text = line.decode("utf-8", "replace").rstrip()[:2000]
            self.logs.append((time.time_ns(), text))
            log.debug("%s: %s", self.config.name, text)

    async def _ask_to_stop(self) -> None:
        await ask_to_stop(self._proc, self._writer)

    def _abandon_inflight(self) -> None:
        """Input the dead worker never answered is lost (not re-sent: it may be what killed
        it), and so is input queued for it."""
        lost = sum(len(b) for b, _ in self._pending)
        self.stats.dropped += lost
        self._pending.clear()
        self._pending_samples = 0
        self._inflight.clear()
        self._room.set()

    def _cause(self, code: int | None) -> Cause | None:
        if self._restart_requested or self._stop.is_set() or self._finished is not None:
            return None
        tail = [line for _, line in list(self.logs)[-20:]]
        cause = exit_cause(
            code, tail, self.config.memory_limit_bytes, self._over_memory, self._hung,
            self._failure,
        )  # fmt: skip
        if cause[0] in ("failed", "crashed"):  # not its limits: the worker's own fault
            self.stats.crashes += 1
        return cause
