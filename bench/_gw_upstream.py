"""The Data Link paper's test API, served by nginx, and nginx as a plain reverse proxy to it.

Two nginx instances with one worker each, on random loopback ports, in one temporary prefix:

- the test API (server A): `GET /small` answers 2 key-value pairs as JSON, `GET /large`
  100 000 (2.6 MB), both static files. `POST` to either reads the whole request body and
  answers the 2 pairs, as the paper's test API did.
- the reverse proxy (server B): `proxy_pass` to A over kept-alive upstream connections, with
  nginx's defaults otherwise, as a user would set one up. Its one worker is the counterpart of
  twinlink's one process.
"""

from __future__ import annotations

import http.client
import json
import shutil
import signal
import socket
import subprocess
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

from _gw_cpu import tree
from _server import Nginx, _terminate, free_port

SMALL = json.dumps({"key1": "value1", "key2": "value2"}).encode()


def large_payload() -> bytes:
    """100 000 key-value pairs as JSON, 2.6 MB."""
    return json.dumps({f"key{i}": f"value{i}" for i in range(100_000)}).encode()


# Why not `return 200 '...'` for POST: nginx then answers at once and drops the body in the
# background, so a client would get the answer before the API had read what it sent (checked
# by waits_for_body below), and "direct" would leave out reading 2.6 MB while the gateway,
# which forwards the whole body before it waits for the answer, pays for it. So a POST goes
# to /sink, where `mirror_request_body on` makes nginx read the whole body into memory
# (client_body_buffer_size) before the content phase; the static handler then refuses POST
# with 405, which error_page turns into a 200 with the 2-pair answer. The mirror subrequest
# itself goes to an internal `return 204` and costs a few microseconds.
API_CONF = """\
worker_processes 1;
pid {prefix}/api.pid;
error_log {prefix}/api-error.log warn;
events {{ worker_connections 1024; }}
http {{
    access_log off;
    default_type application/json;
    sendfile on;
    keepalive_requests 1000000;
    client_max_body_size 16m;
    client_body_buffer_size 16m;
    client_body_temp_path {prefix}/api-body;
    server {{
        listen 127.0.0.1:{port};
        root {prefix}/www;
        location / {{
            if ($request_method = POST) {{ rewrite ^ /sink last; }}
        }}
        location = /sink {{
            internal;
            mirror /discard;
            mirror_request_body on;
            error_page 405 =200 /answer;
        }}
        location = /discard {{ internal; return 204; }}
        location = /answer {{ internal; }}
    }}
}}
"""

# A plain reverse proxy. client_max_body_size is raised (its default, 1 MB, refuses the large
# POST); everything else is nginx's default, so bodies and answers over its 8-16 KB buffers
# are buffered in temporary files, as they would be for a user who did not tune it.
PROXY_CONF = """\
worker_processes 1;
pid {prefix}/proxy.pid;
error_log {prefix}/proxy-error.log warn;
events {{ worker_connections 1024; }}
http {{
    access_log off;
    keepalive_requests 1000000;
    client_max_body_size 16m;
    client_body_temp_path {prefix}/proxy-body;
    proxy_temp_path {prefix}/proxy-temp;
    upstream api {{
        server 127.0.0.1:{api_port};
        keepalive 64;
    }}
    server {{
        listen 127.0.0.1:{port};
        location / {{
            proxy_pass http://api;
            proxy_http_version 1.1;
            proxy_set_header Connection "";
        }}
    }}
}}
"""


@dataclass
class TestApi:
    """The test API and the reverse proxy in front of it; stop() is safe to call always."""

    prefix: Path | None = None
    api_port: int = 0
    proxy_port: int = 0
    version: str = ""
    procs: dict[str, subprocess.Popen[bytes]] = field(default_factory=dict)

    @property
    def api_url(self) -> str:
        return f"http://127.0.0.1:{self.api_port}"

    @property
    def proxy_url(self) -> str:
        return f"http://127.0.0.1:{self.proxy_port}"

    def pids(self, name: str) -> list[int]:
        """The master and worker of `api` or `proxy`."""
        return tree(self.procs[name].pid)

    def start(self, large: bytes, timeout: float = 10) -> None:
        exe = Nginx.binary()
        if exe is None:
            raise FileNotFoundError("nginx is not installed (apt-get install -y nginx-light)")
        out = subprocess.run([exe, "-v"], capture_output=True, text=True, check=False)
        self.version = (out.stderr or out.stdout).strip().removeprefix("nginx version: ")
        self.prefix = prefix = Path(tempfile.mkdtemp(prefix="twinlink-bench-gw-"))
        www = prefix / "www"
        www.mkdir()
        files = {"small": SMALL, "large": large, "sink": SMALL, "answer": SMALL}
        for name, content in files.items():
            (www / name).write_bytes(content)
            (www / name).chmod(0o644)
        # Workers of a root master run as an unprivileged user and must be able to read.
        for folder in (prefix, www):
            folder.chmod(0o755)
        self.api_port, self.proxy_port = free_port(), free_port()
        confs = {
            "api": API_CONF.format(prefix=prefix, port=self.api_port),
            "proxy": PROXY_CONF.format(prefix=prefix, port=self.proxy_port, api_port=self.api_port),
        }
        for name, text in confs.items():
            conf = prefix / f"{name}.conf"
            conf.write_text(text)
            self.procs[name] = subprocess.Popen(
                [exe, "-c", str(conf), "-p", str(prefix), "-g", "daemon off;"],
                stdout=subprocess.DEVNULL,
                stderr=subprocess.PIPE,
            )
        for name, url in (("api", self.api_url), ("proxy", self.proxy_url)):
            self._wait(name, url, timeout)

    def _wait(self, name: str, url: str, timeout: float) -> None:
        """Until GET /small answers 200 through `url`."""
        port = int(url.rsplit(":", 1)[1])
        deadline = time.perf_counter() + timeout
        while time.perf_counter() < deadline:
            proc = self.procs[name]
            if proc.poll() is not None:
                err = proc.stderr.read().decode(errors="replace") if proc.stderr else ""
                raise RuntimeError(f"nginx ({name}) exited: {err.strip()}")
            conn = http.client.HTTPConnection("127.0.0.1", port, timeout=2)
            try:
                conn.request("GET", "/small")
                if conn.getresponse().status == 200:
                    return
            except OSError:
                pass
            finally:
                conn.close()
            time.sleep(0.02)
        raise RuntimeError(f"nginx ({name}) did not answer within {timeout:g} s")

    def stop(self) -> None:
        for proc in self.procs.values():
            # SIGQUIT is nginx's graceful shutdown; fall back to SIGTERM/SIGKILL.
            if proc.poll() is None:
                proc.send_signal(signal.SIGQUIT)
                try:
                    proc.wait(timeout=5)
                except subprocess.TimeoutExpired:
                    _terminate(proc)
            if proc.stderr is not None:
                proc.stderr.close()
        self.procs.clear()
        if self.prefix is not None:
            shutil.rmtree(self.prefix, ignore_errors=True)
            self.prefix = None


def waits_for_body(url: str, path: str, body: bytes, headers: dict[str, str]) -> bool:
    """Whether POST `path` waits for the whole body before answering: send the head and half
    the body, and see that no answer comes within 0.3 s; then the rest, and expect a 200."""
    host, port = url.removeprefix("http://").rsplit(":", 1)
    head = "".join(f"{k}: {v}\r\n" for k, v in headers.items())
    start = (
        f"POST {path} HTTP/1.1\r\nHost: {host}\r\n{head}Content-Length: {len(body)}\r\n\r\n"
    ).encode()
    half = len(body) // 2
    with socket.create_connection((host, int(port)), timeout=5) as sock:
        sock.sendall(start + body[:half])
        sock.settimeout(0.3)
        try:
            early = sock.recv(64)
        except TimeoutError:
            early = b""
        sock.settimeout(10)
        sock.sendall(body[half:])
        answer = early or sock.recv(64)
    if not answer.startswith(b"HTTP/1.1 200"):
        raise RuntimeError(f"POST {url}{path} did not answer 200: {answer[:40]!r}")
    return not early
