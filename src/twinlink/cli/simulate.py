"""`twinlink simulate`: run a simulated device against a server."""

from __future__ import annotations

import asyncio
import signal
from collections.abc import Awaitable, Callable

import click

from twinlink.cli.common import HelpGroup, client_for

_DEVICE_HELP = (
    "Device token to send with. Env: TWINLINK_DEVICE_TOKEN. Without one, the device "
    "`simulator` of the twin is created (or its token renewed) with your API token."
)


@click.group(cls=HelpGroup)
def simulate() -> None:
    """Run a simulated device that streams to a twin and obeys its commands."""


def _device_token(ctx: click.Context, twin: str, device_token: str | None) -> str:
    if device_token:
        return device_token
    client = client_for(ctx)
    devices = client.json("GET", f"/api/v1/twins/{twin}/devices")["devices"]
    if any(d["name"] == "simulator" for d in devices):
        answer = client.json("POST", f"/api/v1/twins/{twin}/devices/simulator/token")
    else:
        answer = client.json(
            "POST",
            f"/api/v1/twins/{twin}/devices",
            json={"name": "simulator", "description": "twinlink simulate"},
        )
    return str(answer["token"])


def _run(main: Callable[[asyncio.Event], Awaitable[int]], duration: float | None) -> int:
    async def runner() -> int:
        stop = asyncio.Event()
        loop = asyncio.get_running_loop()
        for sig in (signal.SIGINT, signal.SIGTERM):
            loop.add_signal_handler(sig, stop.set)
        if duration is not None:
            loop.call_later(duration, stop.set)
        return await main(stop)

    return asyncio.run(runner())


@simulate.command()
@click.option("--twin", default="tingen", show_default=True, help="Slug of the twin.")
@click.option("--device-token", envvar="TWINLINK_DEVICE_TOKEN", help=_DEVICE_HELP)
@click.option("--rate", default=100.0, show_default=True, help="Samples per second (1-100).")
@click.option("-k", "k", default=0.85, show_default=True, help="Filter weight K (eq. 4.2).")
@click.option("--duration", type=float, help="Stop after this many seconds [default: never].")
@click.pass_context
def tingen(
    ctx: click.Context,
    twin: str,
    device_token: str | None,
    rate: float,
    k: float,
    duration: float | None,
) -> None:
    """The thesis's cantilever rig: a damped swing sensed by an IMU, smoothed by the
    complementary filter; obeys pause, start and set_sample_rate."""
    from twinlink_edge.simulate.runner import run_tingen

    if not 1 <= rate <= 100 or not 0 <= k <= 1:
        raise click.BadParameter("--rate must be 1-100 and -k 0-1")
    token = _device_token(ctx, twin, device_token)
    url = client_for(ctx).url
    click.echo(f"streaming to {url}/twins/{twin} at {rate:g} Hz; Ctrl-C stops", err=True)
    sent = _run(lambda stop: run_tingen(url, token, stop, rate, k), duration)
    click.echo(f"sent {sent} samples", err=True)


@simulate.command()
@click.option("--twin", required=True, help="Slug of the twin.")
@click.option("--device-token", envvar="TWINLINK_DEVICE_TOKEN", help=_DEVICE_HELP)
@click.option("--rate", default=10.0, show_default=True, help="Samples per second.")
@click.option("--signals", default=4, show_default=True, help="Number of signals.")
@click.option(
    "--shape",
    type=click.Choice(["mixed", "sine", "step", "noise", "walk"]),
    default="mixed",
    show_default=True,
    help="Signal shape; mixed cycles through the others.",
)
@click.option("--duration", type=float, help="Stop after this many seconds [default: never].")
@click.pass_context
def generic(
    ctx: click.Context,
    twin: str,
    device_token: str | None,
    rate: float,
    signals: int,
    shape: str,
    duration: float | None,
) -> None:
    """A generic source: sine, step, noise and random-walk signals at any rate."""
    from twinlink_edge.simulate.runner import run_generic

    if rate <= 0 or not 1 <= signals <= 1000:
        raise click.BadParameter("--rate must be positive and --signals 1-1000")
    token = _device_token(ctx, twin, device_token)
    url = client_for(ctx).url
    click.echo(f"streaming {signals} signals to {url}/twins/{twin} at {rate:g} Hz", err=True)
    sent = _run(
        lambda stop: run_generic(url, token, stop, rate_hz=rate, signals=signals, shape=shape),
        duration,
    )
    click.echo(f"sent {sent} samples", err=True)
