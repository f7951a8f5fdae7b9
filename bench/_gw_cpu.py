"""CPU time of process trees, precise enough for one request.

psutil's cpu_times come in clock ticks (10 ms here), more than a sequential row of small
requests costs a proxy in all. The kernel's per-thread schedstat counts nanoseconds on the
CPU, so it is used when it is there; psutil otherwise.
"""

from __future__ import annotations

import contextlib
import os
import time
from collections.abc import Iterable
from pathlib import Path

import psutil


def tree(pid: int) -> list[int]:
    """`pid` and its children, recursively (nginx's master and workers; twinlink's workers)."""
    try:
        proc = psutil.Process(pid)
        return [pid, *(c.pid for c in proc.children(recursive=True))]
    except psutil.NoSuchProcess:
        return []


def cpu_ns(pids: Iterable[int]) -> int:
    """Nanoseconds on the CPU so far of the threads of these processes."""
    total = 0
    for pid in pids:
        total += _schedstat_ns(pid) if _HAS_SCHEDSTAT else _psutil_ns(pid)
    return total


def busy_ns() -> int:
    """Nanoseconds the machine's CPUs (all cores) ran processes, from /proc/stat. Interrupt
    time is left out: much of it is the loopback traffic of the benchmark itself, which no
    process is charged for, and steal is the hypervisor's."""
    t = psutil.cpu_times()
    return int((t.user + t.nice + t.system) * 1e9)


def _schedstat_ns(pid: int) -> int:
    total = 0
    with contextlib.suppress(OSError):
        for task in os.scandir(f"/proc/{pid}/task"):
            with contextlib.suppress(OSError, ValueError):
                total += int(Path(task.path, "schedstat").read_text().split()[0])
    return total


def _psutil_ns(pid: int) -> int:
    try:
        t = psutil.Process(pid).cpu_times()
    except psutil.NoSuchProcess:
        return 0
    return int((t.user + t.system) * 1e9)


_HAS_SCHEDSTAT = Path("/proc/self/schedstat").exists()


class CpuMeter:
    """CPU used by named groups of processes between start() and stop(), and by everything
    else on the machine ("other"), in nanoseconds."""

    def __init__(self, groups: dict[str, list[int]]) -> None:
        self.groups = groups
        self.before: dict[str, int] = {}
        self.busy_before = 0

    def start(self) -> None:
        self.before = {name: cpu_ns(pids) for name, pids in self.groups.items()}
        self.busy_before = busy_ns()

    def stop(self, extra_ns: int = 0) -> dict[str, int]:
        """ns per group, and `other`: the machine's busy time less the groups and `extra_ns`
        (CPU of a process measured another way, e.g. wrk's rusage)."""
        used = {name: cpu_ns(pids) - self.before[name] for name, pids in self.groups.items()}
        busy = busy_ns() - self.busy_before
        used["other"] = max(0, busy - sum(used.values()) - extra_ns)
        return used


def settle(
    pids: list[int], below: float = 0.05, window_s: float = 0.5, max_s: float = 20.0
) -> float:
    """Wait until the processes use less than `below` of a core over `window_s`; returns the
    seconds waited. A twinlink that has just started works in the background for a few
    seconds (it loads the blueprints' classes in a thread), which would count as the gateway's
    CPU and compete with the first requests."""
    start = time.perf_counter()
    while time.perf_counter() - start < max_s:
        before = cpu_ns(pids)
        time.sleep(window_s)
        if cpu_ns(pids) - before < below * window_s * 1e9:
            break
    return time.perf_counter() - start
