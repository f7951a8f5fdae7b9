"""`twinlink cosim`: co-simulations of several FMUs (docs/cosim.md). `run` and `check` work
on this machine with no server (`run` sends its rows to a twin as a device when given a
device token: how a deployment's execute phase fills its twin's history); `create`, `start`,
`status`, `stop`, `results`, `list` and `rm` drive co-simulations on the server
(/api/v1/cosims)."""

from __future__ import annotations

import signal
import sys
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from types import FrameType
from typing import TYPE_CHECKING

import click

from twinlink.cli.client import DEFAULT_URL, saved_credentials
from twinlink.cli.common import HelpGroup
from twinlink.cli.cosimapi import FileError, api_commands
from twinlink.cosim.model import CosimFormatError
from twinlink.domain.errors import InvalidInputError

if TYPE_CHECKING:
    from twinlink.cli.cosimrun import Loaded
    from twinlink.cli.cosimsend import DeviceSender

# The co-simulation itself (numpy, FMPy, the master) is imported by the commands that run one,
# not by every `twinlink` command: it would add a third of a second to each start-up.

FILE = click.Path(path_type=Path, dir_okay=False)


@click.group(cls=HelpGroup)
def cosim() -> None:
    """Co-simulations of several FMUs: run or check a file here, or on the server."""


for _command in api_commands:
    cosim.add_command(_command)


@contextmanager
def _loaded(
    path: Path, settings: Path | None, end: float | None, step: float | None
) -> Iterator[Loaded]:
    from twinlink.cli.cosimrun import load

    try:
        with load(path, settings=settings, end=end, step=step) as loaded:
            yield loaded
    except CosimFormatError as err:
        raise FileError(str(err)) from err


@cosim.command("run")
@click.argument("file", type=FILE)
@click.option(
    "-o",
    "--output",
    type=click.Path(path_type=Path, dir_okay=False),
    help="Write the CSV (Maestro's outputs.csv) here [default: stdout].",
)
@click.option(
    "--realtime",
    type=click.FloatRange(min=0, min_open=True),
    metavar="FACTOR",
    help="Pace the run to the wall clock times FACTOR (1.0 real time, 2.0 twice "
    "as fast) [default: as fast as possible].",
)
@click.option("--end", type=float, metavar="T", help="End time (s), replacing the file's.")
@click.option("--step", type=float, metavar="H", help="Step size (s), replacing the file's.")
@click.option(
    "--settings",
    type=FILE,
    help="A Maestro co-simulation configuration (coe.json) beside the multi-model.",
)
@click.option(
    "--device-token",
    envvar="TWINLINK_DEVICE_TOKEN",
    metavar="TOKEN",
    help="Send the rows as this device's samples to its twin. Env: TWINLINK_DEVICE_TOKEN.",
)
@click.option(
    "--url", envvar="TWINLINK_URL", help="The server the samples go to. Env: TWINLINK_URL."
)
@click.option("--prefix", default="", help="Put this before each signal's name.")
@click.option("--stream", default="cosim", show_default=True, help="The stream the samples go to.")
@click.pass_context
def cosim_run(
    ctx: click.Context, file: Path, output: Path | None, realtime: float | None,
    end: float | None, step: float | None, settings: Path | None, device_token: str | None,
    url: str | None, prefix: str, stream: str,
) -> None:  # fmt: skip
    """Run the co-simulation FILE here: a Maestro multi-model (.json), twinlink's YAML form
    (.yaml) or an SSP archive (.ssp). The rows go to stdout (or -o) as CSV, progress to
    stderr. With --device-token they also go to the twin of that device, as signals
    "instance.variable" at the wall-clock time of the run's start plus the simulated time.
    Ctrl-C (or SIGTERM) stops it after the current step, keeping the rows so far."""
    from twinlink.cli.cosimrun import execute, signal_name
    from twinlink.cli.cosimsend import DeviceSender, SendError
    from twinlink.cosim.slaves import CosimRunError

    server = url or ctx.find_root().obj.get("url") or saved_credentials().get("url")
    server = server or DEFAULT_URL
    with _loaded(file, settings, end, step) as loaded, _stopper() as stop:

        def sender(columns: tuple[str, ...]) -> DeviceSender | None:
            if not device_token:
                return None
            names = [signal_name(c, prefix) for c in columns[1:]]
            return DeviceSender(server, device_token, names, t0=loaded.system.start_time,
                                stream=stream)  # fmt: skip

        out = output.open("w", newline="", encoding="utf-8") if output else sys.stdout
        try:
            outcome = execute(loaded, out, sender=sender, realtime=realtime, stop=stop,
                              say=_say(file))  # fmt: skip
        except CosimRunError as err:
            raise click.ClickException(str(err)) from err
        except SendError as err:
            raise click.ClickException(str(err)) from err
        except InvalidInputError as err:
            raise FileError(f"{file}: {err}" if str(file) not in str(err) else str(err)) from err
        finally:
            if output:
                out.close()
    ending = f"ended early ({outcome.ended})" if outcome.ended else "finished"
    done = (
        f"{ending}: {outcome.rows} rows to t = {outcome.last_time:g} s in {outcome.seconds:.3g} s"
    )
    if outcome.jitter:
        done += f" (lateness {outcome.jitter})"
    _say(file)(done)


@cosim.command("check")
@click.argument("file", type=FILE)
@click.option(
    "--settings",
    type=FILE,
    help="A Maestro co-simulation configuration (coe.json) beside the multi-model.",
)
def cosim_check(file: Path, settings: Path | None) -> None:
    """What the co-simulation FILE holds: its instances (and each FMU's kind), connections,
    algorithm and algebraic loops. Exits 1 when it has algebraic loops."""
    from twinlink.cli.cosimcheck import describe

    with _loaded(file, settings, None, None) as loaded:
        lines, loops = describe(loaded)
    for line in lines:
        click.echo(line)
    if loops:
        sys.exit(1)


def _say(file: Path) -> Callable[[str], None]:
    def say(text: str) -> None:
        click.echo(f"{file.name}: {text}", err=True)

    return say


@contextmanager
def _stopper() -> Iterator[threading.Event]:
    """An event set by Ctrl-C or SIGTERM (a deployment stopping its execute phase), so the
    run ends after its current step with what it has written and sent; the handlers before
    are put back after."""
    stop = threading.Event()

    def handler(signum: int, frame: FrameType | None) -> None:
        stop.set()

    if threading.current_thread() is not threading.main_thread():
        yield stop  # signals reach the main thread only (CliRunner in tests may not be it)
        return
    before = {s: signal.signal(s, handler) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield stop
    finally:
        for signum, previous in before.items():
            signal.signal(signum, previous)
