"""Running tasks side by side until the first one ends (a socket's reader and writer)."""

from __future__ import annotations

import asyncio
from collections.abc import Sequence
from typing import Any


async def until_first_done(tasks: Sequence[asyncio.Task[Any]]) -> BaseException | None:
    """Wait until one of `tasks` ends, cancel the others and wait for them all; the exception
    that ended one, if any."""
    try:
        await asyncio.wait(tasks, return_when=asyncio.FIRST_COMPLETED)
    finally:
        for task in tasks:
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)
    for task in tasks:
        if not task.cancelled() and task.exception() is not None:
            return task.exception()
    return None
