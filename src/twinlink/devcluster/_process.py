"""What the launchers share: children that die with their parent, free ports, stopping."""

from __future__ import annotations

import contextlib
import ctypes
import signal
import socket
import subprocess
from collections.abc import Callable

_PR_SET_PDEATHSIG = 1


def dying_with_parent(sig: signal.Signals = signal.SIGKILL) -> Callable[[], None]:
    """A `preexec_fn` for Popen: in the child before exec, ask the kernel to send it `sig`
    when its parent dies, even by SIGKILL, so an interrupted cluster or test run leaves no
    server behind. The kernel watches the *thread* that started the child: start servers
    from a thread that lives as long as they should (the main thread)."""

    def _set() -> None:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(_PR_SET_PDEATHSIG, sig)

    return _set


def free_ports(n: int) -> list[int]:
    """n different free loopback ports (asking for one n times may give the same one twice).
    Another process may take one before its server binds it: callers retry on that."""
    with contextlib.ExitStack() as held:
        sockets = [held.enter_context(socket.socket()) for _ in range(n)]
        for s in sockets:
            s.bind(("127.0.0.1", 0))
        return [int(s.getsockname()[1]) for s in sockets]


def port_free(port: int) -> bool:
    """Whether a server could bind 127.0.0.1:`port` now."""
    with socket.socket() as s:
        try:
            s.bind(("127.0.0.1", port))
        except OSError:
            return False
        return True


def listening(host: str, port: int) -> bool:
    """Whether something accepts TCP connections on host:port."""
    try:
        with socket.create_connection((host, port), timeout=1):
            return True
    except OSError:
        return False


def stop_process(process: subprocess.Popen[bytes], sig: signal.Signals, timeout_s: float) -> None:
    """Send `sig` (the program's own clean shutdown), wait up to `timeout_s`, then kill."""
    if process.poll() is None:
        process.send_signal(sig)
        try:
            process.wait(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            process.kill()
    process.wait()
