"""Library benchmark: push and pull a 100 MB asset through the API of a real server.

Starts `twinlink up` on a random loopback port with a temporary data folder, writes an asset of
random (incompressible) bytes in a few files, packs it once as a tar and once as a zip, then
for each repetition pushes it (POST .../versions, a fresh asset each time, so every blob is new)
and pulls it back as tar, zip and tgz (GET .../archive), with curl as the client (C, streaming:
the client's share of the time is small; the same curl for every case). Measured per case: MB/s
(the asset's bytes over the request's wall time), the server's CPU time, and its peak RSS over
the RSS it had settled at before (sampled every 10 ms): the goal is >= 100 MB/s each way with
constant memory. The references, on the same bytes in the same run: `cp` of the tar (what a
push must at least do: write it once) and `cat` of it to /dev/null (a pull's read). A pulled
tar is checked file by file against the asset once, outside the timing.

    .venv/bin/python bench/library.py              # 100 MB, 3 repetitions, about 1 minute
    .venv/bin/python bench/library.py --size-mb 20 --reps 1   # a smoke run
    .venv/bin/python bench/library.py --direct     # archive.receive/send in this process, no HTTP

Prints a table and writes JSON to bench/results/library-<UTC timestamp>.json (or --json PATH).
Exits 1 if a request failed or a pulled file differed, 2 if the server could not be started.
"""

from __future__ import annotations

import argparse
import hashlib
import os
import shutil
import statistics
import subprocess
import sys
import tarfile
import tempfile
import threading
import time
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import psutil

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _report import machine_info, write_json
from _server import Twinlink

MB = 1 << 20
GOAL_MB_S = 100.0
PULL_FORMATS = ("tar", "zip", "tgz")


@dataclass
class Case:
    name: str
    mb_s: list[float] = field(default_factory=list)
    cpu_s: list[float] = field(default_factory=list)
    rss_growth_mb: list[float] = field(default_factory=list)
    errors: list[str] = field(default_factory=list)

    def summary(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "mb_s_median": round(statistics.median(self.mb_s), 1) if self.mb_s else None,
            "mb_s_best": round(max(self.mb_s), 1) if self.mb_s else None,
            "mb_s": [round(x, 1) for x in self.mb_s],
            "server_cpu_s": [round(x, 2) for x in self.cpu_s],
            "rss_growth_mb_max": round(max(self.rss_growth_mb), 1) if self.rss_growth_mb else None,
            "errors": self.errors,
        }


class PeakRss:
    """The highest RSS of a process (with its children) while the block runs, sampled every
    10 ms in a thread; `cpu_s` its CPU time over the block."""

    def __init__(self, pid: int) -> None:
        self.proc = psutil.Process(pid)
        self.peak = 0
        self.cpu_s = 0.0
        self._stop = threading.Event()

    def _rss(self) -> int:
        total = self.proc.memory_info().rss
        for child in self.proc.children(recursive=True):
            try:
                total += child.memory_info().rss
            except psutil.NoSuchProcess:
                continue
        return total

    def _sample(self) -> None:
        while not self._stop.wait(0.01):
            self.peak = max(self.peak, self._rss())

    def __enter__(self) -> PeakRss:
        self.peak = self._rss()
        self._cpu0 = sum(self.proc.cpu_times()[:2])
        self._thread = threading.Thread(target=self._sample, daemon=True)
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._thread.join()
        self.peak = max(self.peak, self._rss())
        self.cpu_s = sum(self.proc.cpu_times()[:2]) - self._cpu0


# -- the asset ---------------------------------------------------------------------------------


def write_asset(folder: Path, size: int, files: int) -> dict[str, str]:
    """`files` files of random bytes adding up to `size`, one of them executable; returns
    path -> sha256."""
    digests = {}
    each = size // files
    for n in range(files):
        path = folder / ("bin/run.sh" if n == 0 else f"data/part-{n}.bin")
        path.parent.mkdir(parents=True, exist_ok=True)
        digest = hashlib.sha256()
        with path.open("wb") as out:
            left = each if n < files - 1 else size - each * (files - 1)
            while left:
                chunk = os.urandom(min(left, 4 * MB))
                digest.update(chunk)
                out.write(chunk)
                left -= len(chunk)
        if n == 0:
            path.chmod(0o755)
        digests[str(path.relative_to(folder))] = digest.hexdigest()
    return digests


def pack(folder: Path, tar_path: Path, zip_path: Path) -> None:
    files = sorted(p for p in folder.rglob("*") if p.is_file())
    with tarfile.open(tar_path, "w") as tar:
        for p in files:
            tar.add(p, arcname=str(p.relative_to(folder)))
    with zipfile.ZipFile(zip_path, "w", zipfile.ZIP_STORED) as archive:
        for p in files:
            archive.write(p, arcname=str(p.relative_to(folder)))


def check_tar(path: Path, digests: dict[str, str]) -> list[str]:
    """What differs between a pulled tar and the asset (nothing: an empty list)."""
    found = {}
    with tarfile.open(path, "r|") as tar:
        for member in tar:
            source = tar.extractfile(member)
            if source is None:
                continue
            digest = hashlib.sha256()
            while data := source.read(MB):
                digest.update(data)
            found[member.name] = digest.hexdigest()
    return [] if found == digests else [f"pulled tar differs: {sorted(found)} != {sorted(digests)}"]


# -- the cases ---------------------------------------------------------------------------------


def curl(args: list[str]) -> tuple[int, float, str]:
    """Run curl; (HTTP status, seconds, body when not saved)."""
    out = subprocess.run(
        ["curl", "-sS", "--noproxy", "*", "-w", "\n%{http_code} %{time_total}", *args],
        capture_output=True,
        text=True,
        check=False,
    )
    if out.returncode != 0:
        return 0, 0.0, out.stderr.strip()
    body, _, last = out.stdout.rpartition("\n")
    code, seconds = last.split()
    return int(code), float(seconds), body


def quiet(pid: int, timeout_s: float = 60) -> None:
    """Wait until the server is idle (under 5 % of a core over 0.5 s): after its start it
    loads the processors' blueprints in the background (scipy), which the first push would
    pay for."""
    proc = psutil.Process(pid)
    deadline = time.perf_counter() + timeout_s
    while time.perf_counter() < deadline:
        before = sum(proc.cpu_times()[:2])
        time.sleep(0.5)
        if sum(proc.cpu_times()[:2]) - before < 0.025:
            return


def timed(command: list[str]) -> float:
    start = time.perf_counter()
    subprocess.run(command, check=True, shell=False)
    return time.perf_counter() - start


def references(tar_path: Path, tmp: Path, size: int, reps: int) -> list[Case]:
    """`cp` of the tar (in the data folder's file system) and `cat` of it to /dev/null."""
    cp, cat = Case("reference: cp (write)"), Case("reference: cat > /dev/null (read)")
    for _ in range(reps):
        copy = tmp / "copy.tar"
        cp.mb_s.append(size / MB / timed(["cp", str(tar_path), str(copy)]))
        copy.unlink()
        start = time.perf_counter()
        with tar_path.open("rb") as source:
            subprocess.run(["cat"], stdin=source, stdout=subprocess.DEVNULL, check=True)
        cat.mb_s.append(size / MB / (time.perf_counter() - start))
    return [cp, cat]


def http_cases(
    server: Twinlink, tmp: Path, size: int, reps: int, digests: dict[str, str]
) -> list[Case]:
    auth = ["-H", f"Authorization: Bearer {server.admin_token}"]
    base = f"{server.url}/api/v1/library/common/data"
    pushes = {fmt: Case(f"push {fmt}") for fmt in ("tar", "zip")}
    pulls = {fmt: Case(f"pull {fmt}") for fmt in PULL_FORMATS}
    for rep in range(reps):
        if rep:  # fresh bytes each time: every blob of the push is new
            write_asset(tmp / "asset", size, len(digests))
            pack(tmp / "asset", tmp / "asset.tar", tmp / "asset.zip")
        for fmt, case in pushes.items():
            url = f"{base}/bench-{rep}-{fmt}/versions?format={fmt}&tag=latest"
            body = tmp / f"asset.{fmt}"
            settled = server.settled_rss(settle_s=0.3)
            with PeakRss(server.pid) as watch:
                code, seconds, text = curl([*auth, "-X", "POST", "-T", str(body), url])
            _record(case, code, 201, seconds, size, watch, settled, text)
        for fmt, case in pulls.items():
            url = f"{base}/bench-{rep}-tar/versions/latest/archive?format={fmt}"
            out = tmp / f"pulled.{fmt}"
            settled = server.settled_rss(settle_s=0.3)
            with PeakRss(server.pid) as watch:
                code, seconds, text = curl([*auth, "-o", str(out), url])
            _record(case, code, 200, seconds, size, watch, settled, text)
            if fmt == "tar" and code == 200 and rep == 0:
                case.errors += check_tar(out, digests)
            out.unlink(missing_ok=True)
    return [*pushes.values(), *pulls.values()]


def _record(
    case: Case,
    code: int,
    want: int,
    seconds: float,
    size: int,
    watch: PeakRss,
    settled: int,
    text: str,
) -> None:
    if code != want:
        case.errors.append(f"HTTP {code}: {text[:300]}")
        return
    case.mb_s.append(size / MB / seconds)
    case.cpu_s.append(watch.cpu_s)
    case.rss_growth_mb.append((watch.peak - settled) / MB)


def direct_cases(tmp: Path, size: int, reps: int) -> list[Case]:
    """archive.receive and archive.send in this process (no HTTP): the library's own share."""
    import asyncio

    from twinlink.library.archive import Limits, receive, send
    from twinlink.library.blobs import FileBlobStore

    async def body(path: Path) -> Any:
        with path.open("rb") as source:
            while data := await asyncio.to_thread(source.read, MB):
                yield data

    async def one(rep: int, push: Case, pull: Case) -> None:
        blobs = FileBlobStore(tmp / f"blobs-{rep}")
        with PeakRss(os.getpid()) as watch:
            start = time.perf_counter()
            files = await receive(body(tmp / "asset.tar"), "tar", blobs, Limits(2 * size))
            seconds = time.perf_counter() - start
        push.mb_s.append(size / MB / seconds)
        push.cpu_s.append(watch.cpu_s)
        with PeakRss(os.getpid()) as watch:
            start = time.perf_counter()
            async for _ in send(files, blobs, "tar"):
                pass
            seconds = time.perf_counter() - start
        pull.mb_s.append(size / MB / seconds)
        pull.cpu_s.append(watch.cpu_s)
        shutil.rmtree(tmp / f"blobs-{rep}")

    push, pull = Case("receive tar (in process)"), Case("send tar (in process)")
    for rep in range(reps):
        asyncio.run(one(rep, push, pull))
    return [push, pull]


# -- the run -----------------------------------------------------------------------------------


def render(report: dict[str, Any]) -> str:
    m = report["machine"]
    lines = [
        f"library benchmark, {report['config']['size_mb']} MB in {report['config']['files']} "
        f"files, {report['config']['reps']} repetitions; {m['nproc']} CPUs ({m['cpu_model']}), "
        f"git {m['git']}; load average {report['loadavg']['before']} before, "
        f"{report['loadavg'].get('after', '-')} after (1 min)",
        "",
        f"{'case':<36}{'MB/s median':>12}{'best':>8}{'srv CPU s':>11}{'MB/CPU s':>10}"
        f"{'RSS growth MB':>15}",
    ]
    size = report["config"]["size_mb"]
    for c in report["cases"]:
        cpu = statistics.median(c["server_cpu_s"]) if c["server_cpu_s"] else None
        lines.append(
            f"{c['name']:<36}{_f(c['mb_s_median']):>12}{_f(c['mb_s_best']):>8}"
            f"{_f(cpu, 2):>11}{_f(size / cpu if cpu else None, 0):>10}"
            f"{_f(c['rss_growth_mb_max']):>15}"
            + (f"   ERRORS: {c['errors']}" if c["errors"] else "")
        )
    for label, ratio in report.get("ratios", {}).items():
        lines.append(f"{label}: {ratio}")
    return "\n".join(lines)


def _f(x: float | None, digits: int = 1) -> str:
    return "-" if x is None else f"{x:.{digits}f}"


def ratios(cases: list[dict[str, Any]]) -> dict[str, str]:
    by = {c["name"]: c["mb_s_median"] for c in cases}
    out = {}
    for case, ref in (
        ("push tar", "reference: cp (write)"),
        ("pull tar", "reference: cat > /dev/null (read)"),
    ):
        if by.get(case) and by.get(ref):
            out[f"{case} / {ref}"] = f"{by[case] / by[ref]:.2f}"
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--size-mb", type=int, default=100, help="the asset's size (default 100)")
    p.add_argument("--files", type=int, default=4, help="files in the asset (default 4)")
    p.add_argument("--reps", type=int, default=3, help="repetitions of each case (default 3)")
    p.add_argument("--direct", action="store_true", help="receive/send in process, no server")
    p.add_argument("--json", type=Path, help="default bench/results/library-<timestamp>.json")
    a = p.parse_args(argv)
    size = a.size_mb * MB
    tmp = Path(tempfile.mkdtemp(prefix="twinlink-bench-lib-"))
    report: dict[str, Any] = {
        "machine": machine_info(),
        "config": {"size_mb": a.size_mb, "files": a.files, "reps": a.reps, "direct": a.direct},
        "goal_mb_s": GOAL_MB_S,
        "loadavg": {"before": round(os.getloadavg()[0], 2)},
    }
    server = Twinlink(tmp / "data")
    status = 0
    try:
        print(f"writing a {a.size_mb} MB asset of random bytes ...", flush=True)
        digests = write_asset(tmp / "asset", size, a.files)
        pack(tmp / "asset", tmp / "asset.tar", tmp / "asset.zip")
        cases = references(tmp / "asset.tar", tmp, size, a.reps)
        if a.direct:
            cases += direct_cases(tmp, size, a.reps)
        else:
            print("starting twinlink ...", flush=True)
            try:
                server.start()
            except RuntimeError as err:
                print(f"error: {err}", file=sys.stderr)
                return 2
            quiet(server.pid)
            report["rss_mb_idle"] = round(server.settled_rss() / MB, 1)
            cases += http_cases(server, tmp, size, a.reps, digests)
            report["rss_mb_after"] = round(server.settled_rss() / MB, 1)
        report["loadavg"]["after"] = round(os.getloadavg()[0], 2)
        report["cases"] = [c.summary() for c in cases]
        report["ratios"] = ratios(report["cases"])
        status = 1 if any(c.errors for c in cases) else 0
    finally:
        server.stop()
        shutil.rmtree(tmp, ignore_errors=True)
    print(render(report))
    print(f"\nresults: {write_json(report, a.json, 'library')}")
    return status


if __name__ == "__main__":
    sys.exit(main())
