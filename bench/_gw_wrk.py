"""Throughput of small GETs with wrk, and the CPU each request costs the proxy.

wrk is a C load generator (one thread here, epoll): it needs far less CPU a request than any
Python client, which matters when it shares 2 CPUs with the proxy and the test API.
"""

from __future__ import annotations

import re
import resource
import shutil
import subprocess
import time
from typing import Any

from _gw_cpu import CpuMeter

_UNITS = {"us": 0.001, "ms": 1.0, "s": 1000.0, "m": 60_000.0}
_TIME = r"([\d.]+)(us|ms|s|m)"


def wrk_binary() -> str | None:
    return shutil.which("wrk")


def wrk_version() -> str | None:
    exe = wrk_binary()
    if exe is None:
        return None
    out = subprocess.run([exe, "--version"], capture_output=True, text=True, check=False)
    return (out.stdout or out.stderr).splitlines()[0].split(" Copyright")[0].strip() or None


def run_wrk(
    url: str,
    connections: int,
    seconds: float,
    token: str,
    groups: dict[str, list[int]],
) -> dict[str, Any]:
    """One wrk run: requests/s, latency percentiles (ms), errors, and the CPU of each group
    of processes per request (us), of wrk, and of everything else (% of one core)."""
    exe = wrk_binary()
    assert exe is not None
    cmd = [
        exe,
        "-t1",
        f"-c{connections}",
        f"-d{seconds:g}s",
        "--latency",
        "-H",
        f"Authorization: Bearer {token}",
        url,
    ]
    meter = CpuMeter(groups)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    meter.start()
    start = time.perf_counter()
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=seconds + 60, check=False)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    wrk_ns = int((after.ru_utime - children.ru_utime + after.ru_stime - children.ru_stime) * 1e9)
    used = meter.stop(extra_ns=wrk_ns)
    if out.returncode != 0:
        raise RuntimeError(f"wrk failed ({out.returncode}): {out.stderr.strip() or out.stdout}")
    result = parse(out.stdout)
    n = max(1, result["requests"])
    result["cpu_us_per_request"] = {name: round(used[name] / n / 1000, 1) for name in groups}
    result["wrk_cpu_pct"] = round(100 * wrk_ns / 1e9 / wall, 1)
    result["other_cpu_pct"] = round(100 * used["other"] / 1e9 / wall, 1)
    return result


def parse(text: str) -> dict[str, Any]:
    """The figures of wrk's report (its default output with --latency)."""
    done = re.search(r"(\d+) requests in " + _TIME, text)
    rps = re.search(r"Requests/sec:\s+([\d.]+)", text)
    if done is None or rps is None:
        raise RuntimeError(f"could not read wrk's output:\n{text}")
    percentiles = {
        f"p{p}_ms": _ms(value, unit)
        for p, value, unit in re.findall(r"^\s+(\d+)%\s+" + _TIME, text, re.MULTILINE)
    }
    mean = re.search(r"Latency\s+" + _TIME, text)
    non_2xx = re.search(r"Non-2xx or 3xx responses: (\d+)", text)
    sockets = re.search(
        r"Socket errors: connect (\d+), read (\d+), write (\d+), timeout (\d+)", text
    )
    return {
        "requests": int(done.group(1)),
        "seconds": _ms(done.group(2), done.group(3)) / 1000,
        "rps": float(rps.group(1)),
        "mean_ms": _ms(mean.group(1), mean.group(2)) if mean else None,
        **percentiles,
        "non_2xx": int(non_2xx.group(1)) if non_2xx else 0,
        "socket_errors": sum(int(x) for x in sockets.groups()) if sockets else 0,
    }


def _ms(value: str, unit: str) -> float:
    return round(float(value) * _UNITS[unit], 4)
