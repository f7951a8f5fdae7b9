"""The Python a processor's worker runs in, and the environment it starts with.

Most workers run in the server's own Python. A processor with python_requirements runs in
its own env (fmuenv.py), which may take minutes to build the first time: the supervisor
waits for it here, announcing the build as events, and a stop ends the wait at once.
"""

from __future__ import annotations

import asyncio
import os
import sys
import time
from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import Any

from twinlink.processors.fmuenv import EnvBuildError

# (kind, message, time_ns, data)
EventTuple = tuple[str, str, int, dict[str, Any]]
# Why a worker could not start or ended: (event kind, message, data)
Cause = tuple[str, str, dict[str, Any]]
# The interpreter of a processor's own Python env (fmuenv.py), built first if need be; it is
# told the env's key when a build starts.
Interpreter = Callable[[Callable[[str], None]], Awaitable[Path]]


def worker_environment() -> dict[str, str]:
    """The server's environment without its settings: a worker runs uploaded code, and the
    settings may hold the first admin's password and token."""
    return {k: v for k, v in os.environ.items() if not k.startswith("TWINLINK_")}


async def worker_python(
    interpreter: Interpreter | None,
    stop: asyncio.Event,
    on_events: Callable[[list[EventTuple]], None],
) -> str | Cause | None:
    """The Python the worker runs in; or why it cannot start ("env_failed"), or None when
    `stop` was set while its env was being built."""
    if interpreter is None:
        return sys.executable
    announced: list[str] = []

    def building(key: str) -> None:
        announced.append(key)
        message = f"building its Python environment {key} (python_requirements)"
        on_events([("env_building", message, time.time_ns(), {"env": key})])

    built = asyncio.ensure_future(interpreter(building))
    stopping = asyncio.ensure_future(stop.wait())
    await asyncio.wait((built, stopping), return_when=asyncio.FIRST_COMPLETED)
    stopping.cancel()
    if not built.done():
        built.cancel()
        await asyncio.gather(built, return_exceptions=True)
        return None
    try:
        python = built.result()
    except EnvBuildError as err:
        return "env_failed", f"its Python environment could not be built: {err}", {}
    if announced:
        on_events([("env_ready", "its Python environment is built", time.time_ns(),
                    {"env": announced[0]})])  # fmt: skip
    return str(python)
