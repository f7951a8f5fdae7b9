"""`python -m ilmatar_crane`: run the crane's example services until SIGINT or SIGTERM."""

from __future__ import annotations

import argparse
import asyncio
import dataclasses
import json
import logging
import signal
import sys
from collections.abc import Sequence
from pathlib import Path

from ilmatar_crane._http import can_listen
from ilmatar_crane.runner import start_crane
from ilmatar_crane.settings import CranePorts, CraneSettings

# Scripts wait for this line on stderr; keep its wording stable.
READY = "crane services ready"


def parse_args(argv: Sequence[str] | None = None) -> argparse.Namespace:
    defaults = CranePorts()
    parser = argparse.ArgumentParser(
        prog="python -m ilmatar_crane",
        description="The Ilmatar crane's example services (demo credentials: docs/crane.md).",
    )
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--opcua-port", type=int, default=defaults.opcua)
    parser.add_argument("--historian-port", type=int, default=defaults.historian)
    parser.add_argument("--bridge-port", type=int, default=defaults.bridge)
    parser.add_argument("--cad-port", type=int, default=defaults.cad)
    parser.add_argument("--sensors-port", type=int, default=defaults.sensors)
    parser.add_argument(
        "--token-ttl", type=float, default=300.0, help="historian and sensor token lifetime, s"
    )
    parser.add_argument("--cad-dir", type=Path, help="serve this folder instead of the models")
    parser.add_argument(
        "--no-autopilot", action="store_true", help="keep the crane still until commanded"
    )
    return parser.parse_args(argv)


def ports_of(args: argparse.Namespace) -> CranePorts:
    return CranePorts(
        opcua=args.opcua_port,
        historian=args.historian_port,
        bridge=args.bridge_port,
        cad=args.cad_port,
        sensors=args.sensors_port,
    )


async def serve(args: argparse.Namespace) -> None:
    ports = ports_of(args)
    settings = CraneSettings(
        token_ttl_s=args.token_ttl, cad_dir=args.cad_dir, autopilot=not args.no_autopilot
    )
    stop = asyncio.Event()
    loop = asyncio.get_running_loop()
    for sig in (signal.SIGINT, signal.SIGTERM):
        loop.add_signal_handler(sig, stop.set)
    crane = await start_crane(args.host, ports, settings)
    try:
        print(f"{READY} {json.dumps(crane.urls)}", file=sys.stderr, flush=True)
        await stop.wait()
    finally:
        await crane.stop()


def taken(host: str, ports: CranePorts) -> str | None:
    """A line naming the ports something else listens on, with the option to change each."""
    busy = [
        f"{port} (--{name}-port)"
        for name, port in dataclasses.asdict(ports).items()
        if not can_listen(host, port)
    ]
    if not busy:
        return None
    return (
        f"port{'s' if len(busy) > 1 else ''} {', '.join(busy)} on {host} "
        f"{'are' if len(busy) > 1 else 'is'} in use; choose another, or 0 for any free one"
    )


def main(argv: Sequence[str] | None = None) -> int:
    args = parse_args(argv)
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    # asyncua reports routine session events (clients that drop, sessions that lapse) as
    # warnings; its errors still show.
    logging.getLogger("asyncua").setLevel(logging.ERROR)
    # Checked first: asyncua would log a traceback for a taken OPC UA port before failing.
    problem = taken(args.host, ports_of(args))
    if problem is not None:
        print(f"crane services could not start: {problem}", file=sys.stderr)
        return 1
    try:
        asyncio.run(serve(args))
    except OSError as err:
        print(f"crane services could not start: {err}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
