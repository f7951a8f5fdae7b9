"""One user's JupyterLab: a child process on a loopback port, in a process group of its own,
with a random token of its own that only the proxy sends.

It is not started again when it dies: a crashed workspace is shown `failed` with its last log
lines, and the user starts it again (a notebook that crashes its server at start would
otherwise crash it forever, using a CPU for nothing).
"""

from __future__ import annotations

import asyncio
import contextlib
import ctypes
import os
import resource
import secrets
import signal
import socket
import sys
from collections import deque
from dataclasses import dataclass
from pathlib import Path

import httpx
import psutil

from twinlink.domain.errors import TwinlinkError

LOG_LINES = 40
STOP_GRACE_S = 10.0
POLL_S = 0.2
READER_GRACE_S = 2.0
_PR_SET_PDEATHSIG = 1


@dataclass(frozen=True, slots=True)
class Launch:
    """What one JupyterLab is started with."""

    base_url: str  # "/workspaces/alice/": the proxy forwards paths unchanged
    root: Path  # the folder it shows, also its HOME
    env: dict[str, str]  # the whole environment of it and its kernels (jupyter's own added)
    memory_mb: int  # RLIMIT_AS of it and its kernels; 0: none


class StartFailed(TwinlinkError):
    """The JupyterLab ended or did not answer in time; the message says which. The service
    keeps it as the workspace's error and answers UnavailableError."""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


class JupyterProcess:
    def __init__(self, launch: Launch) -> None:
        self.launch = launch
        self.port = free_port()
        self.token = secrets.token_urlsafe(32)
        self.logs: deque[str] = deque(maxlen=LOG_LINES)
        self.proc: asyncio.subprocess.Process | None = None
        self._reader: asyncio.Task[None] | None = None
        self._ended: asyncio.Task[int] | None = None

    @property
    def origin(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    @property
    def running(self) -> bool:
        return self.proc is not None and self.proc.returncode is None

    def command(self) -> list[str]:
        command = [
            sys.executable, "-m", "jupyterlab", "--no-browser",
            "--ip", "127.0.0.1", "--port", str(self.port), "--ServerApp.port_retries=0",
            f"--ServerApp.base_url={self.launch.base_url}",
            f"--ServerApp.root_dir={self.launch.root}",
            # Installing extensions from PyPI would change the server's own environment.
            "--LabApp.extension_manager=readonly",
            # It answers the proxy alone: no X-Forwarded-* is trusted.
            "--ServerApp.trust_xheaders=False",
        ]  # fmt: skip
        if os.geteuid() == 0:  # a server run as root (a container) runs its workspaces so
            command.append("--allow-root")
        return command

    async def start(self, timeout_s: float) -> None:
        """Start it and wait until it answers; StartFailed (and nothing left running) if it
        ends first or does not answer within `timeout_s`."""
        env = {**self.launch.env, "JUPYTER_TOKEN": self.token, "JUPYTER_PLATFORM_DIRS": "1"}
        self.proc = await asyncio.create_subprocess_exec(
            *self.command(), cwd=self.launch.root, env=env,
            stdin=asyncio.subprocess.DEVNULL, stdout=asyncio.subprocess.PIPE,
            stderr=asyncio.subprocess.STDOUT, start_new_session=True, preexec_fn=self._limits,
        )  # fmt: skip
        assert self.proc.stdout is not None
        self._reader = asyncio.create_task(self._read_logs(self.proc.stdout))
        try:
            await asyncio.wait_for(self._answers(), timeout_s)
        except TimeoutError:
            await self.stop()
            raise StartFailed(f"JupyterLab did not answer within {timeout_s:g} s") from None
        except BaseException:
            await self.stop()
            raise

    def _limits(self) -> None:
        """In the child, before exec: the memory limit, and SIGTERM when the server dies
        (even by SIGKILL), so no JupyterLab outlives it."""
        if self.launch.memory_mb:
            limit = self.launch.memory_mb * 2**20
            resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)

    async def _answers(self) -> None:
        url = f"{self.origin}{self.launch.base_url}api/status"
        headers = {"Authorization": f"token {self.token}"}
        async with httpx.AsyncClient(timeout=5, trust_env=False) as client:
            while True:
                assert self.proc is not None
                if self.proc.returncode is not None:
                    raise StartFailed(f"JupyterLab ended with code {self.proc.returncode}")
                with contextlib.suppress(httpx.TransportError):
                    if (await client.get(url, headers=headers)).status_code == 200:
                        return
                with contextlib.suppress(TimeoutError):
                    await asyncio.wait_for(self.proc.wait(), POLL_S)

    async def _read_logs(self, stream: asyncio.StreamReader) -> None:
        while line := await stream.readline():
            # Its token is shown as "..." by JupyterLab itself; redacted here all the same.
            text = line.decode(errors="replace").rstrip().replace(self.token, "***")
            self.logs.append(text)

    async def wait(self) -> int:
        """Its exit code once it ended and its log is read (one waiter underneath, however
        many wait)."""
        if self._ended is None:
            self._ended = asyncio.create_task(self._wait())
        return await asyncio.shield(self._ended)

    async def _wait(self) -> int:
        assert self.proc is not None and self._reader is not None
        code = await self.proc.wait()
        # A child it left (a kernel) may hold the log pipe open after it ended: the lines
        # up to now are enough.
        with contextlib.suppress(TimeoutError):
            await asyncio.wait_for(asyncio.shield(self._reader), READER_GRACE_S)
        self._reader.cancel()
        await asyncio.gather(self._reader, return_exceptions=True)
        return code

    async def stop(self) -> None:
        """SIGTERM (JupyterLab then shuts its kernels down), SIGKILL after STOP_GRACE_S; then
        whatever it started that is still there (kernels and terminals are in sessions of
        their own) is killed, so nothing outlives a stop."""
        proc = self.proc
        if proc is None:
            return
        family = _descendants(proc.pid) if proc.returncode is None else []
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGTERM)
        try:
            await asyncio.wait_for(proc.wait(), STOP_GRACE_S)
        except TimeoutError:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(proc.pid, signal.SIGKILL)
        await self.wait()
        await asyncio.to_thread(_kill_all, family)


def _descendants(pid: int) -> list[psutil.Process]:
    try:
        return psutil.Process(pid).children(recursive=True)
    except psutil.Error:
        return []


def _kill_all(processes: list[psutil.Process]) -> None:
    """Kill what is left of `processes` and reap it; psutil checks each is still the
    process it was (a pid used again by another process is left alone)."""
    alive = [p for p in processes if p.is_running()]
    for process in alive:
        with contextlib.suppress(psutil.Error):
            process.kill()
    psutil.wait_procs(alive, timeout=5)
