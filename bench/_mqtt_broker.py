"""A real Mosquitto broker for bench/mqtt.py (a temporary config and password file on a free
loopback port), and `twinlink up` with extra environment (the external MQTT mode)."""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

from _server import Twinlink, _terminate, free_port

# Mosquitto's defaults are 20 messages in flight to a subscriber and 1000 queued for it (more
# are dropped): both far too few for a platform that takes all devices' telemetry
# (docs/mqtt.md, external mode).
BROKER_SETTINGS = {"max_inflight_messages": 1000, "max_queued_messages": 10_000_000}


@dataclass
class Mosquitto:
    users: dict[str, str]
    port: int = 0
    folder: Path | None = None
    process: subprocess.Popen[bytes] | None = None
    version: str = ""

    @property
    def pid(self) -> int:
        assert self.process is not None
        return self.process.pid

    @property
    def url(self) -> str:
        return f"mqtt://127.0.0.1:{self.port}"

    def start(self, timeout: float = 10) -> None:
        exe = shutil.which("mosquitto") or "/usr/sbin/mosquitto"
        if not os.access(exe, os.X_OK):
            raise FileNotFoundError("mosquitto is not installed (Debian: apt install mosquitto)")
        out = subprocess.run([exe, "-h"], capture_output=True, text=True, check=False)
        self.version = (out.stdout or out.stderr).splitlines()[0].strip()
        self.folder = Path(tempfile.mkdtemp(prefix="twinlink-bench-mosquitto-"))
        passwd = self.folder / "passwd"
        passwd.write_text("".join(f"{u}:{p}\n" for u, p in self.users.items()))
        subprocess.run(["mosquitto_passwd", "-U", str(passwd)], check=True)
        self.port = free_port()
        settings = "".join(f"{k} {v}\n" for k, v in BROKER_SETTINGS.items())
        config = self.folder / "mosquitto.conf"
        # `user root`: as root Mosquitto would switch to the user `mosquitto`, who cannot
        # read the temporary folder; as anyone else the line has no effect.
        config.write_text(
            f"listener {self.port} 127.0.0.1\nallow_anonymous false\npassword_file {passwd}\n"
            f"persistence false\nlog_dest stderr\nuser root\n{settings}"
        )
        log = (self.folder / "mosquitto.log").open("ab")
        self.process = subprocess.Popen(
            [exe, "-c", str(config)], stdout=subprocess.DEVNULL, stderr=log
        )
        log.close()
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if self.process.poll() is not None:
                raise RuntimeError((self.folder / "mosquitto.log").read_text())
            try:
                socket.create_connection(("127.0.0.1", self.port), timeout=1).close()
                return
            except OSError:
                time.sleep(0.02)
        raise RuntimeError(f"mosquitto did not listen within {timeout}s")

    def stop(self) -> None:
        if self.process is not None:
            _terminate(self.process)  # type: ignore[arg-type]
            self.process = None
        if self.folder is not None:
            shutil.rmtree(self.folder, ignore_errors=True)
            self.folder = None


@dataclass
class TwinlinkWithEnv(Twinlink):
    """`twinlink up` as bench/_server.py starts it, with more environment variables."""

    extra_env: dict[str, str] = field(default_factory=dict)

    def spawn(self) -> None:
        saved = {k: os.environ.get(k) for k in self.extra_env}
        os.environ.update(self.extra_env)
        try:
            super().spawn()  # the child's environment is copied from os.environ here
        finally:
            for k, v in saved.items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v
