"""Client processes of the live benchmark (see _live_client.py), seen from the orchestrator,
and the CPU the server, the clients and the rest of the machine use during a case."""

from __future__ import annotations

import asyncio
import contextlib
import signal
import sys
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import orjson
import psutil

from _load import _busy_cpu, _own_cpu, _tree_cpu

CLIENT = Path(__file__).resolve().parent / "_live_client.py"


class ClientError(RuntimeError):
    """A client process failed or said it could not do its part."""


class ClientProc:
    """One `_live_client.py` process: configure it, wait for its events, tell it go/stop."""

    def __init__(self, name: str, config: dict[str, Any]) -> None:
        self.name = name
        self.config = config
        self.proc: asyncio.subprocess.Process | None = None
        self._stderr: list[bytes] = []
        self._drain: asyncio.Task[None] | None = None

    @property
    def pid(self) -> int:
        assert self.proc is not None
        return self.proc.pid

    async def start(self) -> None:
        self.proc = await asyncio.create_subprocess_exec(
            sys.executable,
            str(CLIENT),
            stdin=asyncio.subprocess.PIPE,
            stdout=asyncio.subprocess.PIPE,
            stderr=asyncio.subprocess.PIPE,
            limit=2**24,
        )
        self._drain = asyncio.create_task(self._keep_stderr())
        self.send(self.config)

    async def _keep_stderr(self) -> None:
        assert self.proc is not None and self.proc.stderr is not None
        while chunk := await self.proc.stderr.read(65536):
            self._stderr.append(chunk)
            while sum(map(len, self._stderr)) > 65536 and len(self._stderr) > 1:
                self._stderr.pop(0)

    def stderr(self) -> str:
        return b"".join(self._stderr).decode(errors="replace")[-2000:]

    def send(self, message: dict[str, Any]) -> None:
        assert self.proc is not None and self.proc.stdin is not None
        with contextlib.suppress(BrokenPipeError, ConnectionResetError):
            self.proc.stdin.write(orjson.dumps(message) + b"\n")

    async def event(self, kind: str, timeout: float) -> dict[str, Any]:
        """The next event of `kind`; ClientError on an `error` event, an exit or a timeout."""
        assert self.proc is not None and self.proc.stdout is not None
        try:
            async with asyncio.timeout(timeout):
                while line := await self.proc.stdout.readline():
                    msg: dict[str, Any] = orjson.loads(line)
                    if msg["event"] == "error":
                        raise ClientError(f"{self.name}: {msg['message']}")
                    if msg["event"] == kind:
                        return msg
        except TimeoutError:
            raise ClientError(f"{self.name}: no {kind!r} within {timeout:g} s") from None
        await self.proc.wait()
        raise ClientError(f"{self.name} exited ({self.proc.returncode}):\n{self.stderr()}")

    async def close(self) -> None:
        if self.proc is None:
            return
        if self.proc.returncode is None:
            if self.proc.stdin is not None:
                self.proc.stdin.close()
            try:
                await asyncio.wait_for(self.proc.wait(), 10)
            except TimeoutError:
                self.proc.kill()
                await self.proc.wait()
        if self._drain is not None:
            await asyncio.gather(self._drain, return_exceptions=True)


class ClientGroup:
    """Several client processes started together, made ready together and closed together."""

    def __init__(self, procs: Iterable[ClientProc]) -> None:
        self.procs = list(procs)

    async def __aenter__(self) -> ClientGroup:
        try:
            for p in self.procs:
                await p.start()
        except BaseException:
            await self.close()
            raise
        return self

    async def __aexit__(self, *exc: object) -> None:
        await self.close()

    async def close(self) -> None:
        await asyncio.gather(*(p.close() for p in self.procs), return_exceptions=True)

    async def all(self, kind: str, timeout: float) -> list[dict[str, Any]]:
        return list(await asyncio.gather(*(p.event(kind, timeout) for p in self.procs)))

    def send(self, op: str) -> None:
        for p in self.procs:
            p.send({"op": op})

    @property
    def pids(self) -> list[int]:
        return [p.pid for p in self.procs]


class CpuWindow:
    """CPU seconds from its creation to `stop()` of the server, of the clients (some client
    processes, and this process when `here` is true: it is the client of HTTP cases) and of
    everything else; as percentages of one core over the window's wall time. A client process
    that exits counts with what it had used when last seen: call `sample()` when one is about
    to end (after its result)."""

    def __init__(self, server_pid: int, client_pids: Iterable[int] = (), here: bool = False):
        self.server = psutil.Process(server_pid)
        self.clients = [psutil.Process(p) for p in client_pids]
        self.me = psutil.Process() if here else None
        self.loop = asyncio.get_running_loop()
        self.t0 = self.loop.time()
        self.srv0 = _tree_cpu(self.server)
        self.seen: dict[int, float] = {}
        self.cli0 = self._clients()
        self.busy0 = _busy_cpu()

    def sample(self) -> None:
        for p in self.clients:
            with contextlib.suppress(psutil.NoSuchProcess):
                self.seen[p.pid] = _tree_cpu(p)

    def _clients(self) -> float:
        self.sample()
        own = _own_cpu(self.me) if self.me is not None else 0.0
        return own + sum(self.seen.values())

    def stop(self) -> dict[str, float]:
        wall = max(1e-9, self.loop.time() - self.t0)
        srv = _tree_cpu(self.server) - self.srv0
        cli = self._clients() - self.cli0
        busy = _busy_cpu() - self.busy0
        return {
            "seconds": round(wall, 3),
            "server_cpu_pct": round(100 * srv / wall, 1),
            "client_cpu_pct": round(100 * cli / wall, 1),
            "other_cpu_pct": round(max(0.0, 100 * (busy - srv - cli) / wall), 1),
        }


class Profiler:
    """`py-spy record` of the server while the block runs (with `enabled` and py-spy found);
    the flame graph goes to `svg`. Sampling costs the server little, but not nothing."""

    def __init__(self, enabled: bool, pid: int, svg: Path) -> None:
        exe = Path(sys.executable).with_name("py-spy")
        self.command = [str(exe), "record", "--pid", str(pid), "--rate", "200", "-o", str(svg)]
        self.enabled = enabled and exe.exists()
        self.svg = svg
        self.proc: asyncio.subprocess.Process | None = None

    async def __aenter__(self) -> Profiler:
        if self.enabled:
            self.proc = await asyncio.create_subprocess_exec(
                *self.command,
                stdout=asyncio.subprocess.DEVNULL,
                stderr=asyncio.subprocess.DEVNULL,
            )
            await asyncio.sleep(0.5)  # attached before the load starts
        return self

    async def __aexit__(self, *exc: object) -> None:
        if self.proc is None:
            return
        self.proc.send_signal(signal.SIGINT)  # py-spy writes the flame graph on SIGINT
        try:
            await asyncio.wait_for(self.proc.wait(), 30)
        except TimeoutError:
            self.proc.kill()
            await self.proc.wait()
