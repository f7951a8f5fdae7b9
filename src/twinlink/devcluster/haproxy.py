"""haproxy in front of twinlink nodes: the load balancer of the local cluster and of the
scale-out fault tests and benchmark.

HTTP mode, so WebSocket upgrades pass and each request may go to another node; the nodes'
health check (`GET /readyz` by default, 200 when the node's store and bus answer) takes a
node out after two failed checks (closing its open connections, so its devices reconnect to
another node) and back after two good ones. A request whose connection to
a node failed is sent to another (nothing reached the node); other failures are retried on
another node only for requests that may be repeated (GET, HEAD, OPTIONS): a POST of telemetry
that a node may have stored is never sent twice by the load balancer, the device's own retry
with the same seq is what makes that safe. Each answer names the node that gave it in
`X-Twinlink-Node` (node1, node2, ...), for tests and for a person reading a trace.

Debian's package (`/usr/sbin/haproxy`, 2.6) runs in the foreground (-db) as a child that dies
with its parent; its log (one line per request) is `haproxy.log` beside its config.
"""

from __future__ import annotations

import csv
import shutil
import signal
import socket
import subprocess
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from twinlink.devcluster._process import dying_with_parent, free_ports, listening, stop_process
from twinlink.domain.errors import TwinlinkError

START_S = 30.0
STOP_S = 10.0
NODE_HEADER = "X-Twinlink-Node"
STATS_SOCKET = "haproxy.sock"  # in its folder, for HAProxy.server_states


class HAProxyError(TwinlinkError):
    """haproxy is missing, refused its config or did not start listening."""


@dataclass
class HAProxy:
    port: int  # the front end's port on 127.0.0.1
    directory: Path  # its config and log
    process: subprocess.Popen[bytes]
    stats_socket: Path | None = None  # haproxy's admin socket (server_states)
    mqtt_port: int | None = None  # the MQTT front end's port, when it has one

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    def log(self, tail: int = 4000) -> str:
        try:
            return (self.directory / "haproxy.log").read_text(errors="replace")[-tail:]
        except OSError:
            return ""

    def server_states(self, proxy: str = "nodes") -> dict[str, str]:
        """Each node's state as haproxy sees it ("UP", "DOWN", "UP 1/2", "MAINT", ...), by
        server name (node1, node2, ...), from its stats socket: the HTTP back end's, or
        `proxy="mqtt"`'s."""
        with socket.socket(socket.AF_UNIX) as conn:
            conn.settimeout(5)
            conn.connect(str(self.stats_socket or self.directory / STATS_SOCKET))
            conn.sendall(b"show stat -1 4 -1\n")  # every proxy, servers only, every server
            answer = b"".join(iter(lambda: conn.recv(65536), b""))
        rows = csv.reader(answer.decode().lstrip("# ").splitlines())
        header = next(rows, [])
        if "svname" not in header or "status" not in header:
            raise HAProxyError(f"haproxy's stats socket answered {answer[:200]!r}")
        proxies, name, status = (header.index(k) for k in ("pxname", "svname", "status"))
        return {
            row[name]: row[status] for row in rows if len(row) > status and row[proxies] == proxy
        }

    def stop(self) -> None:
        """SIGTERM: haproxy closes every connection at once (SIGUSR1 would wait for open
        WebSockets, up to the tunnel timeout of an hour)."""
        stop_process(self.process, signal.SIGTERM, STOP_S)
        if self.stats_socket is not None and self.stats_socket.parent != self.directory.resolve():
            shutil.rmtree(self.stats_socket.parent, ignore_errors=True)  # its private folder


def haproxy_bin() -> Path:
    found = shutil.which("haproxy") or shutil.which("haproxy", path="/usr/sbin:/usr/local/sbin")
    if found is None:
        raise HAProxyError(
            "haproxy not found: install the Debian package haproxy "
            "(scripts/ensure-packages.sh haproxy, which make test and make cluster run)"
        )
    return Path(found)


def start_haproxy(
    directory: Path,
    port: int,
    backends: list[tuple[str, int]],
    health_path: str = "/readyz",
    check_interval_ms: int = 500,
    *,
    mqtt_backends: list[tuple[str, int]] | None = None,
    mqtt_port: int = 0,
) -> HAProxy:
    """Start haproxy on 127.0.0.1:`port` (0: a free port, see `HAProxy.port`) in front of
    `backends` (host, port); returns once it accepts connections. The nodes need not be up
    yet: until their health checks pass haproxy answers 503.

    With `mqtt_backends` (each node's MQTT listener, in the order of `backends`), MQTT
    connections to 127.0.0.1:`mqtt_port` (0: a free port, `HAProxy.mqtt_port`) go to a ready
    node too, in TCP mode: a device's session stays on one node until it reconnects."""
    if not backends:
        raise ValueError("haproxy needs at least one backend")
    if mqtt_backends is not None and len(mqtt_backends) != len(backends):
        raise ValueError("mqtt_backends must name one MQTT listener per backend")
    directory.mkdir(parents=True, exist_ok=True)
    binary = haproxy_bin()
    stats_socket = _stats_socket_path(directory)
    for _attempt in range(3):
        free = free_ports(2)
        chosen, chosen_mqtt = port or free[0], mqtt_port or free[1]
        config = directory / "haproxy.cfg"
        text = haproxy_config(chosen, backends, health_path, check_interval_ms, stats_socket)
        if mqtt_backends is not None:
            text += mqtt_config(chosen_mqtt, backends, mqtt_backends, health_path)
        config.write_text(text)
        with (directory / "haproxy.log").open("wb") as log:
            process = subprocess.Popen(
                [binary, "-db", "-f", config],
                stdout=log,
                stderr=subprocess.STDOUT,
                stdin=subprocess.DEVNULL,
                preexec_fn=dying_with_parent(signal.SIGTERM),
                process_group=0,  # a Ctrl-C in the terminal reaches the launcher alone
            )
        proxy = HAProxy(chosen, directory, process, stats_socket)
        if mqtt_backends is not None:
            proxy.mqtt_port = chosen_mqtt
        if _wait_listening(proxy):
            return proxy
        proxy.stop()
        # a port picked free was taken before haproxy bound it: pick another
        if (port == 0 or mqtt_port == 0) and "cannot bind socket" in proxy.log():
            continue
        break
    raise HAProxyError(f"haproxy did not start on port {chosen}:\n{proxy.log()}")


def _stats_socket_path(directory: Path) -> Path:
    """The stats socket in haproxy's folder, unless that path is too long for a Unix socket
    (108 bytes on Linux; pytest's folders can be): then a private folder in /tmp."""
    path = directory.resolve() / STATS_SOCKET
    if len(str(path)) < 100:
        return path
    return Path(tempfile.mkdtemp(prefix="twinlink-haproxy-")) / STATS_SOCKET


def _wait_listening(proxy: HAProxy) -> bool:
    deadline = time.monotonic() + START_S
    while time.monotonic() < deadline:
        if proxy.process.poll() is not None:
            return False
        if listening("127.0.0.1", proxy.port):
            return True
        time.sleep(0.05)  # polling the real state, with a deadline
    return False


def haproxy_config(
    port: int,
    backends: list[tuple[str, int]],
    health_path: str,
    check_interval_ms: int,
    stats_socket: Path,
) -> str:
    servers = "\n".join(
        f"    server node{i} {host}:{node_port} check"
        for i, (host, node_port) in enumerate(backends, 1)
    )
    return f"""\
global
    log stdout format raw local0 info
    stats socket {stats_socket} mode 600 level operator

defaults
    mode http
    log global
    option httplog
    option dontlognull
    timeout connect 5s
    timeout client 60s
    timeout server 60s
    timeout http-request 10s
    # an open WebSocket (device or browser) may be idle much longer than a request
    timeout tunnel 1h
    timeout client-fin 5s
    # A health check's answer may take this long: /readyz answers within its own bound (1 s)
    # however it ends, so a node busy under load is not taken out (and its sessions cut)
    # for answering a check later than the check interval.
    timeout check 2s

frontend twinlink
    bind 127.0.0.1:{port}
    option forwardfor
    default_backend nodes

backend nodes
    balance roundrobin
    option httpchk
    http-check send meth GET uri {health_path} ver HTTP/1.1 hdr Host localhost
    http-check expect status 200
    # A node taken out also loses its open connections: a device WebSocket on a node cut off
    # from its database would otherwise stay there, its batches refused until it is back.
    default-server inter {check_interval_ms} fall 2 rise 2 on-marked-down shutdown-sessions
    # a failed connection sent nothing: try another node. An empty answer may come from a
    # node that died after storing the request, so only requests that may be repeated are
    # retried after one (a device resends its own batches with the same seq).
    option redispatch 1
    retries 2
    retry-on conn-failure empty-response
    http-request disable-l7-retry unless METH_GET or METH_OPTIONS
    http-response set-header {NODE_HEADER} %[srv_name]
{servers}
"""


def mqtt_config(
    port: int,
    backends: list[tuple[str, int]],
    mqtt_backends: list[tuple[str, int]],
    health_path: str,
) -> str:
    """MQTT in TCP mode, each node checked on its HTTP port: a node that is not ready gets no
    new MQTT device either."""
    servers = "\n".join(
        f"    server node{i} {host}:{mqtt} check port {http}"
        for i, ((host, mqtt), (_, http)) in enumerate(zip(mqtt_backends, backends, strict=True), 1)
    )
    return f"""
listen mqtt
    mode tcp
    option tcplog
    bind 127.0.0.1:{port}
    balance leastconn
    # a device's connection lives for hours, quiet but for its keep-alive pings
    timeout client 1h
    timeout server 1h
    option httpchk
    http-check send meth GET uri {health_path} ver HTTP/1.1 hdr Host localhost
    http-check expect status 200
    default-server inter 500 fall 2 rise 2 on-marked-down shutdown-sessions
{servers}
"""
