"""The simulated Tingen rig, run as a tool: streams to a twin as one of its devices until it is
stopped (SIGTERM or SIGINT, which a deployment's stop sends), then waits for its last batches
to be acknowledged.

    python3 tingen_sim.py [--rate HZ] [--duration S]

Where to and as whom come from the environment a lifecycle run gets: TWINLINK_URL (the
server) and TWINLINK_DEVICE_TOKEN_TINGENSAP (the token of the deployment's device
tingenSAP). It needs the twinlink edge SDK (`pip install twinlink-edge`, or `edge/` of the
twinlink repository); nothing of the server.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import signal
import sys

TOKEN_VARIABLE = "TWINLINK_DEVICE_TOKEN_TINGENSAP"


def main() -> int:
    parser = argparse.ArgumentParser(description="Run the simulated Tingen rig.")
    parser.add_argument("--rate", type=float, default=100.0, help="samples per second (1-100)")
    parser.add_argument("--duration", type=float, help="stop after this many seconds")
    args = parser.parse_args()
    url, token = os.environ.get("TWINLINK_URL"), os.environ.get(TOKEN_VARIABLE)
    if not url or not token:
        print(f"tingen-sim: set TWINLINK_URL and {TOKEN_VARIABLE}", file=sys.stderr)
        return 2
    try:
        from twinlink_edge.simulate.runner import run_tingen
    except ImportError:
        print(
            f"tingen-sim: the twinlink edge SDK is not installed for {sys.executable}: "
            "pip install twinlink-edge (or the edge/ folder of twinlink)",
            file=sys.stderr,
        )
        return 3

    async def run() -> int:
        stop = asyncio.Event()
        loop = asyncio.get_running_loop()
        for sig in (signal.SIGINT, signal.SIGTERM):
            loop.add_signal_handler(sig, stop.set)
        if args.duration is not None:
            loop.call_later(args.duration, stop.set)
        return await run_tingen(url, token, stop, rate_hz=args.rate, close_timeout_s=3.0)

    print(f"tingen-sim: streaming to {url} at {args.rate:g} Hz", flush=True)
    sent = asyncio.run(run())
    print(f"tingen-sim: sent {sent} samples", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
