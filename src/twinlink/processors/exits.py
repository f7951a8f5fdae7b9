"""How a worker's process ends: asked to stop (then terminated, then killed), and why it
ended, told as the event its supervisor reports (a crash, a signal, its memory limit, a hung
batch)."""

from __future__ import annotations

import asyncio
import contextlib
import signal
from typing import Any

from twinlink.processors.wire import frame
from twinlink.processors.workerenv import Cause

STOP_GRACE_S = 5.0


async def ask_to_stop(
    proc: asyncio.subprocess.Process | None, writer: asyncio.StreamWriter | None
) -> None:
    """Ask the worker to stop (its blueprint's `stop` runs), then terminate it, then kill it."""
    if proc is None or proc.returncode is not None:
        return
    if writer is not None:
        with contextlib.suppress(ConnectionError, RuntimeError):
            writer.write(frame({"t": "stop"}))
    for action in (None, proc.terminate, proc.kill):
        if action is not None:
            with contextlib.suppress(ProcessLookupError):
                action()
        with contextlib.suppress(TimeoutError):
            await asyncio.wait_for(proc.wait(), STOP_GRACE_S if action is None else 2.0)
            return


def exit_cause(
    code: int | None,
    log_tail: list[str],
    memory_limit_bytes: int,
    over_memory: int | None,
    hung: float | None,
    failure: str | None,
) -> Cause:
    """Why a worker that was not asked to end did: its memory limit, a batch it hung on, a
    failure it reported, or a crash (`code`: its exit status, negative for a signal)."""
    data: dict[str, Any] = {"exit_code": code, "log_tail": log_tail}
    if over_memory is not None:
        limit_mb = memory_limit_bytes / 2**20
        message = f"over its memory limit: RSS {over_memory / 2**20:.0f} MB > {limit_mb:.0f} MB"
        return "memory_limit", message, {**data, "rss_bytes": over_memory}
    if hung is not None:
        return "hung", f"stuck on one batch for {hung:.0f} s (batch_timeout_s)", data
    if failure is not None:
        return "failed", failure, data
    if code is not None and code < 0:
        name = signal.Signals(-code).name
        described = signal.strsignal(-code) or name
        return "crashed", f"killed by signal {name} ({described})", data
    return "crashed", f"exited with status {code}", data
