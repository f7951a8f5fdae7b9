"""Processes a benchmark runs against: a real `twinlink up`, and nginx as a reference.

Both listen on a random loopback port, and both are stopped by `stop()`, which is safe to
call more than once and on a process that never started.
"""

from __future__ import annotations

import contextlib
import os
import secrets
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import httpx
import psutil

READY_LINE = "twinlink serving at"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _terminate(proc: subprocess.Popen[bytes], timeout: float = 20) -> None:
    if proc.poll() is None:
        proc.send_signal(signal.SIGTERM)
        try:
            proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


@dataclass
class Twinlink:
    """`python -m twinlink up` on a random loopback port with a preset admin token."""

    data_dir: Path
    admin_token: str = field(default_factory=lambda: "tl_bench_" + secrets.token_urlsafe(24))
    admin_password: str = field(default_factory=lambda: secrets.token_urlsafe(12))
    port: int = 0
    process: subprocess.Popen[bytes] | None = None
    output: list[str] = field(default_factory=list)
    _ready: threading.Event = field(default_factory=threading.Event)
    _reader: threading.Thread | None = None
    spawned_at: float = 0.0
    ready_line_at: float | None = None
    env: dict[str, str] = field(default_factory=dict)  # more environment (PostgreSQL, Kafka)

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    @property
    def pid(self) -> int:
        assert self.process is not None
        return self.process.pid

    def spawn(self) -> None:
        """Start the process and return at once; see wait_ready() and wait_healthy()."""
        self.port = free_port()
        env = {
            **os.environ,
            "TWINLINK_ADMIN_TOKEN": self.admin_token,
            "TWINLINK_ADMIN_PASSWORD": self.admin_password,
            "TWINLINK_LOG_LEVEL": "warning",
            "TWINLINK_MQTT_PORT": "0",
            **self.env,
        }
        env.pop("TWINLINK_CONFIG", None)
        self.output.clear()
        self._ready.clear()
        self.ready_line_at = None
        self.spawned_at = time.perf_counter()
        self.process = subprocess.Popen(
            [
                sys.executable,
                "-m",
                "twinlink",
                "up",
                "--port",
                str(self.port),
                "--data-dir",
                str(self.data_dir),
            ],
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
        )
        self._reader = threading.Thread(target=self._pump, args=(self.process,), daemon=True)
        self._reader.start()

    def _pump(self, proc: subprocess.Popen[bytes]) -> None:
        assert proc.stdout is not None
        for raw in proc.stdout:
            line = raw.decode(errors="replace")
            self.output.append(line)
            if line.startswith(READY_LINE) and self.ready_line_at is None:
                self.ready_line_at = time.perf_counter()
                self._ready.set()
        self._ready.set()

    def alive(self) -> bool:
        return self.process is not None and self.process.poll() is None

    def log(self) -> str:
        return "".join(self.output)

    def wait_healthy(self, timeout: float = 60) -> float:
        """Poll GET /healthz until it answers 200; returns seconds since spawn.

        The server listens before its startup runs, so an early request is queued until the
        app serves it; before the socket is bound the connection is refused and retried."""
        deadline = time.perf_counter() + timeout
        with httpx.Client(timeout=httpx.Timeout(timeout, connect=1.0)) as client:
            while time.perf_counter() < deadline:
                if not self.alive():
                    raise RuntimeError(f"twinlink exited while starting:\n{self.log()}")
                try:
                    if client.get(f"{self.url}/healthz").status_code == 200:
                        return time.perf_counter() - self.spawned_at
                except httpx.TransportError:
                    pass
                time.sleep(0.005)
        raise RuntimeError(f"twinlink did not answer /healthz within {timeout}s:\n{self.log()}")

    def start(self, timeout: float = 60) -> float:
        self.spawn()
        try:
            return self.wait_healthy(timeout)
        except BaseException:
            self.stop()
            raise

    def rss_bytes(self) -> int:
        """Resident set size of the server and any children it has."""
        proc = psutil.Process(self.pid)
        total = proc.memory_info().rss
        for child in proc.children(recursive=True):
            with contextlib.suppress(psutil.NoSuchProcess):
                total += child.memory_info().rss
        return total

    def settled_rss(self, settle_s: float = 1.0, max_wait_s: float = 8.0) -> int:
        """RSS once it stops moving: two samples 0.5 s apart within 0.5 %."""
        time.sleep(settle_s)
        last = self.rss_bytes()
        deadline = time.perf_counter() + max_wait_s
        while time.perf_counter() < deadline:
            time.sleep(0.5)
            now = self.rss_bytes()
            if abs(now - last) <= 0.005 * last:
                return now
            last = now
        return last

    def stop(self) -> None:
        if self.process is None:
            return
        _terminate(self.process)
        if self._reader is not None:
            self._reader.join(timeout=10)
        if self.process.stdout is not None:
            self.process.stdout.close()


NGINX_CONF = """\
worker_processes 1;
pid {prefix}/nginx.pid;
error_log {prefix}/error.log warn;
events {{ worker_connections 1024; }}
http {{
    access_log off;
    types {{ application/yaml yaml; }}
    default_type application/octet-stream;
    sendfile on;
    keepalive_requests 1000000;
    client_body_temp_path {prefix}/body;
    server {{
        listen 127.0.0.1:{port};
        root {prefix}/www;
        location / {{ }}
    }}
}}
"""


@dataclass
class Nginx:
    """nginx serving static files, as the floor for a small GET over the same client.

    It gets a temporary prefix of its own (mode 0755, removed by stop()): when the master runs
    as root its workers run as an unprivileged user, which must be able to reach the files."""

    prefix: Path | None = None
    port: int = 0
    process: subprocess.Popen[bytes] | None = None
    version: str = ""

    @staticmethod
    def binary() -> str | None:
        return shutil.which("nginx") or next(
            (p for p in ("/usr/sbin/nginx", "/usr/local/sbin/nginx") if os.access(p, os.X_OK)), None
        )

    def start(self, files: dict[str, bytes], timeout: float = 10) -> str:
        """Serve `files` (name -> content); returns the base URL."""
        exe = self.binary()
        if exe is None:
            raise FileNotFoundError("nginx is not installed")
        out = subprocess.run([exe, "-v"], capture_output=True, text=True, check=False)
        self.version = (out.stderr or out.stdout).strip().removeprefix("nginx version: ")
        self.prefix = Path(tempfile.mkdtemp(prefix="twinlink-bench-nginx-"))
        www = self.prefix / "www"
        www.mkdir()
        (self.prefix / "body").mkdir(exist_ok=True)
        for name, content in files.items():
            (www / name).write_bytes(content)
            (www / name).chmod(0o644)
        # Workers of a root master run as an unprivileged user and must be able to read.
        for folder in (self.prefix, www):
            folder.chmod(0o755)
        self.port = free_port()
        conf = self.prefix / "nginx.conf"
        conf.write_text(NGINX_CONF.format(prefix=self.prefix, port=self.port))
        self.process = subprocess.Popen(
            [exe, "-c", str(conf), "-p", str(self.prefix), "-g", "daemon off;"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
        )
        url = f"http://127.0.0.1:{self.port}"
        deadline = time.perf_counter() + timeout
        name = next(iter(files))
        with httpx.Client(timeout=2) as client:
            while time.perf_counter() < deadline:
                if self.process.poll() is not None:
                    err = (
                        self.process.stderr.read().decode(errors="replace")
                        if self.process.stderr
                        else ""
                    )
                    self.stop()
                    raise RuntimeError(f"nginx exited: {err.strip()}")
                try:
                    if client.get(f"{url}/{name}").status_code == 200:
                        return url
                except httpx.TransportError:
                    pass
                time.sleep(0.02)
        log = (self.prefix / "error.log").read_text(errors="replace").splitlines()[-1:]
        self.stop()
        raise RuntimeError(f"nginx did not serve within the timeout: {' '.join(log)}")

    def stop(self) -> None:
        if self.process is not None:
            # SIGQUIT is nginx's graceful shutdown; fall back to SIGTERM/SIGKILL.
            if self.process.poll() is None:
                self.process.send_signal(signal.SIGQUIT)
                try:
                    self.process.wait(timeout=5)
                except subprocess.TimeoutExpired:
                    _terminate(self.process)
            if self.process.stderr is not None:
                self.process.stderr.close()
            self.process = None
        if self.prefix is not None:
            shutil.rmtree(self.prefix, ignore_errors=True)
            self.prefix = None
