"""Run a simulated device against a server through the edge SDK, like a real rig would.

The Tingen rig obeys the thesis's `pause` and `start` commands, `set_sample_rate`, and the
desired properties `sample_rate` and `filter_k`, and reports `paused`, `sample_rate`,
`filter_k` and `device_id`. The generic source only streams.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ..aio import AsyncDevice
from .generic import GenericModel
from .tingen import TingenModel

log = logging.getLogger("twinlink_edge.simulate")

TICK_S = 0.01  # the pacing loop wakes at most this often and makes every sample that is due


@dataclass
class Pace:
    rate_hz: float
    paused: bool = False
    # When sending last resumed: the ticks the loop catches up on after a start may be older,
    # from while it was paused, and are not sent.
    resumed_ns: int = 0


async def run_paced(
    device: AsyncDevice,
    pace: Pace,
    step: Callable[[float], dict[str, Any]],
    stop: asyncio.Event,
) -> int:
    """Make samples at `pace.rate_hz` (timestamps exactly 1/rate apart) until `stop` is set.
    The model keeps running while paused; only sending stops. Returns samples sent."""
    sent = 0
    next_ns = time.time_ns()
    while not stop.is_set():
        now = time.time_ns()
        period_ns = round(1e9 / pace.rate_hz)
        while next_ns <= now:
            values = step(period_ns / 1e9)
            if not pace.paused and next_ns >= pace.resumed_ns:
                await device.send(values, time_ns=next_ns)
                sent += 1
            next_ns += period_ns
        if now - next_ns > 1_000_000_000:  # far behind (machine suspended): skip ahead
            next_ns = now
        wait_s = max(0.0, min(TICK_S, (next_ns - time.time_ns()) / 1e9))
        with contextlib.suppress(asyncio.TimeoutError):
            await asyncio.wait_for(stop.wait(), wait_s)
    return sent


def device_for(url: str, token: str, rate_hz: float, close_timeout_s: float = 10.0) -> AsyncDevice:
    # Send at most every 20 ms (or every sample at low rates): the live view stays close to
    # real time while a fast source still travels in large batches.
    return AsyncDevice(
        url,
        token,
        flush_interval=min(0.02, 1 / rate_hz),
        batch_size=5000,
        close_timeout=close_timeout_s,
    )


async def run_tingen(
    url: str,
    token: str,
    stop: asyncio.Event,
    rate_hz: float = 100.0,
    k: float = 0.85,
    close_timeout_s: float = 10.0,
) -> int:
    """Run the simulated rig until `stop`; then wait up to `close_timeout_s` for the server to
    acknowledge what was sent."""
    model = TingenModel(k=k)
    pace = Pace(rate_hz)
    async with device_for(url, token, rate_hz, close_timeout_s) as device:
        _tingen_handlers(device, model, pace)
        await device.wait_connected(timeout=30)
        await _report(device, model, pace)
        sent = await run_paced(device, pace, model.step, stop)
        await device.flush(timeout=close_timeout_s)
    return sent


def _tingen_handlers(device: AsyncDevice, model: TingenModel, pace: Pace) -> None:
    @device.on_command("pause")
    async def pause(args: dict[str, Any]) -> dict[str, Any]:
        pace.paused = True
        await _report(device, model, pace)
        return {"paused": True}

    @device.on_command("start")
    async def start(args: dict[str, Any]) -> dict[str, Any]:
        if pace.paused:
            pace.paused, pace.resumed_ns = False, time.time_ns()
        await _report(device, model, pace)
        return {"paused": False}

    @device.on_command("set_sample_rate")
    async def set_sample_rate(args: dict[str, Any]) -> dict[str, Any]:
        pace.rate_hz = _rate(args.get("value"))
        await _report(device, model, pace)
        return {"sample_rate": pace.rate_hz}

    @device.on_desired
    async def desired(changed: dict[str, Any]) -> None:
        if "sample_rate" in changed:
            pace.rate_hz = _rate(changed["sample_rate"])
        if "filter_k" in changed:
            model.k = min(1.0, max(0.0, float(changed["filter_k"])))
        await _report(device, model, pace)


def _rate(value: Any) -> float:
    if not isinstance(value, (int, float)) or isinstance(value, bool) or not 1 <= value <= 100:
        raise ValueError("sample_rate must be a number from 1 to 100 (Hz)")
    return float(value)


async def _report(device: AsyncDevice, model: TingenModel, pace: Pace) -> None:
    state = {
        "paused": pace.paused,
        "sample_rate": pace.rate_hz,
        "filter_k": model.k,
        "device_id": device.device_name or "tingenSAP",
    }
    try:
        await device.report(state, wait=False)
    except Exception:  # reporting is best effort; the stream goes on
        log.warning("reporting properties failed", exc_info=True)


async def run_generic(
    url: str,
    token: str,
    stop: asyncio.Event,
    *,
    rate_hz: float = 10.0,
    signals: int = 4,
    shape: str = "mixed",
) -> int:
    model = GenericModel(signals=signals, shape=shape)  # type: ignore[arg-type]
    async with device_for(url, token, rate_hz) as device:
        await device.wait_connected(timeout=30)
        sent = await run_paced(device, Pace(rate_hz), model.step, stop)
        await device.flush(timeout=10)
    return sent
