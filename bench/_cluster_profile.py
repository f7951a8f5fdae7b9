"""Where a node's time goes: `py-spy record` of one node for a few seconds while the devices
post, summarised from its collapsed stacks (`--format raw`: one line per distinct stack,
`frame;frame;...;frame count`, the innermost frame last).

Two views: the functions the samples were in (self time), and each sample put in the first
area its stack passes through, innermost first (the PostgreSQL driver, the Kafka client, JSON,
HTTP, twinlink's own modules...), which says what the time is spent on.
"""

from __future__ import annotations

import asyncio
import re
import signal
import sys
from collections import Counter
from pathlib import Path
from typing import Any

# Areas a frame's file belongs to, tried in order (the innermost frame that matches names
# the sample's area). Frames of the standard library and the event loop fall through to the
# next frame out.
AREAS: list[tuple[str, str]] = [
    ("asyncpg", "PostgreSQL driver (asyncpg)"),
    ("aiokafka", "Kafka client (aiokafka)"),
    ("kafka/", "Kafka client (aiokafka)"),
    ("orjson", "JSON"),
    ("json/", "JSON"),
    ("pydantic", "validation (pydantic)"),
    ("uvicorn", "HTTP server (uvicorn, httptools)"),
    ("httptools", "HTTP server (uvicorn, httptools)"),
    ("starlette", "routing (starlette, fastapi)"),
    ("fastapi", "routing (starlette, fastapi)"),
    ("websockets", "WebSockets"),
    ("sqlite3", "SQLite"),
]
# A thread blocked in one of these (the GIL released) is waiting, not working; py-spy's idle
# detection does not always see that.
WAITING = ("wait", "acquire", "select", "poll", "_worker", "get")
# The event loop's own frame as the innermost one: uvloop's C code (its I/O, its callbacks)
LOOP = ("Runner.run", "run", "run_until_complete", "run_forever")


def _waiting(frame: tuple[str, str]) -> bool:
    return frame[0].split(".")[-1] in WAITING


RATE = 100  # samples a second
FRAME = re.compile(r"^(?P<func>.*?) \((?P<file>[^:()]*)(?::\d+)?\)$")


class NodeProfile:
    """py-spy on `pid` for `seconds`, started `delay_s` into the load (so the warm-up is not
    in it); writes the raw stacks to `path`."""

    def __init__(self, pid: int, path: Path, seconds: float, delay_s: float) -> None:
        self.exe = Path(sys.executable).with_name("py-spy")
        self.pid, self.path, self.seconds, self.delay_s = pid, path, seconds, delay_s
        self.task: asyncio.Task[str | None] | None = None

    @property
    def available(self) -> bool:
        return self.exe.exists()

    def start(self) -> None:
        if self.available:
            self.task = asyncio.create_task(self._record())

    async def _record(self) -> str | None:
        """None, or why there is no profile."""
        await asyncio.sleep(self.delay_s)
        proc = await asyncio.create_subprocess_exec(
            str(self.exe), "record", "--pid", str(self.pid), "--rate", str(RATE),
            "--duration", str(int(self.seconds)), "--format", "raw", "--nonblocking",
            "--full-filenames",
            "-o", str(self.path),
            stdout=asyncio.subprocess.DEVNULL, stderr=asyncio.subprocess.PIPE,
        )  # fmt: skip
        try:
            _, err = await asyncio.wait_for(proc.communicate(), self.seconds + 60)
        except TimeoutError:
            proc.send_signal(signal.SIGINT)
            await proc.wait()
            return "py-spy did not finish"
        return None if proc.returncode == 0 else err.decode(errors="replace")[-300:]

    async def summary(self, top: int = 12) -> dict[str, Any]:
        if self.task is None:
            return {"status": "py-spy not found beside the interpreter (pip install py-spy)"}
        why = await self.task
        if why is not None or not self.path.exists():
            return {"status": f"no profile: {why}"}
        found = summarise(self.path.read_text(), top)
        # py-spy samples a thread only while it runs (no --idle): samples over those possible
        # is roughly the share of a core the node's Python threads used
        possible = RATE * self.seconds
        return {
            "status": "ok",
            "file": str(self.path),
            "busy_pct": round(100 * found["samples"] / possible),
            **found,
        }


def summarise(raw: str, top: int) -> dict[str, Any]:
    own: Counter[str] = Counter()
    areas: Counter[str] = Counter()
    total = 0
    for line in raw.splitlines():
        stack, _, count = line.rpartition(" ")
        if not count.isdigit():
            continue
        n = int(count)
        total += n
        frames = [_frame(f) for f in stack.split(";") if f]
        if frames and not _waiting(frames[-1]):
            own[_name(frames[-1])] += n
        areas[_area(frames)] += n
    if not total:
        return {"samples": 0, "self": [], "areas": []}
    return {
        "samples": total,
        "self": [
            {"function": f, "pct": round(100 * n / total, 1)} for f, n in own.most_common(top)
        ],
        "areas": [{"area": a, "pct": round(100 * n / total, 1)} for a, n in areas.most_common()],
    }


def _frame(text: str) -> tuple[str, str]:
    m = FRAME.match(text.strip())
    return (m["func"], m["file"]) if m else (text.strip(), "")


def _name(frame: tuple[str, str]) -> str:
    func, file = frame
    short = "/".join(Path(file).parts[-2:]) if file else "?"
    return f"{func} ({short})"


def _area(frames: list[tuple[str, str]]) -> str:
    if frames and _waiting(frames[-1]):
        return "waiting (threads, event loop)"
    if frames and frames[-1][0] in LOOP:
        return "event loop and socket I/O (uvloop, in C)"
    for _func, file in reversed(frames):
        for needle, area in AREAS:
            if needle in file:
                return area
        if "/twinlink/" in file:  # twinlink's own modules: by package, store/postgres, ingest...
            parts = file.split("/twinlink/", 1)[1].split("/")[:-1]
            return "twinlink " + ("/".join(parts[:2]) or "(top level)")
    return "other (standard library, event loop)"
