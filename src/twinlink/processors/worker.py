"""A processor's worker process: `python -m twinlink.processors.worker FD`.

It reads frames from the socket FD (see `wire`), runs one blueprint, and answers each data frame
with one `out` frame. Anything the blueprint prints goes to stderr, which the supervisor keeps as
the processor's log. When the server goes away the channel closes and the worker exits; an
exception from the blueprint is reported in a `failed` frame and the worker exits with status 3,
so the supervisor restarts it from a clean state (a native FMU in an unknown state is never
reused). A blueprint that finished (`Context.finish`, an FMU that ended its simulation) has its
last `out` frame say so; the worker then stops the blueprint and exits with status 0.
"""

from __future__ import annotations

import contextlib
import logging
import os
import shutil
import signal
import socket
import sys
import traceback
from pathlib import Path
from typing import Any

from twinlink.processors.blueprint import Blueprint, Context
from twinlink.processors.catalog import load_ref
from twinlink.processors.runtime import Runtime
from twinlink.processors.spec import InputMap, Rates
from twinlink.processors.wire import BlockingChannel, ChannelClosed, pack_batch, unpack_batch

EXIT_FAILED = 3
log = logging.getLogger("twinlink.worker")


def build(init: dict[str, Any]) -> tuple[Runtime, type[Blueprint[Any]]]:
    cls = load_ref(init["ref"])
    # Absolute: FMUs are given their resources as a file URI, which a relative path is not.
    workdir = Path(init["workdir"]).resolve()
    shutil.rmtree(workdir, ignore_errors=True)
    workdir.mkdir(parents=True)
    rates = Rates.model_validate(init["rates"])
    ctx = Context(
        processor=init["processor"],
        twin=init["twin"],
        files=Path(init["files"]).resolve(),
        workdir=workdir,
        step_spacing_s=rates.min_step_spacing_s,
        log=logging.getLogger(f"twinlink.blueprint.{init['processor']}"),
    )
    blueprint = cls(cls.Params.model_validate(init["params"]), ctx)
    blueprint.start()
    maps = {k: InputMap.model_validate(v) for k, v in init["inputs"].items()}
    return Runtime(blueprint, maps, rates), cls


def serve(channel: BlockingChannel) -> int:
    init = channel.receive()
    try:
        runtime, cls = build(init)
    except Exception as err:
        return _fail(channel, "start", err)
    blueprint = runtime.blueprint
    channel.send({"t": "ready", "pid": os.getpid(), **_described(blueprint)})
    while True:
        message = channel.receive()
        kind = message["t"]
        if kind == "data":
            try:
                reply, out = runtime.feed(unpack_batch(message))
            except Exception as err:
                return _fail(channel, "process", err)
            reply.update(t="out", id=message["id"])
            if out is not None:
                reply.update(pack_batch(out))
            channel.send(reply)
            if "finished" in reply:  # done for good: end normally, the blueprint stopped
                blueprint.stop()
                return 0
        elif kind == "configure":
            try:
                params = cls.Params.model_validate(message["params"])
                kept = blueprint.reconfigure(params)
            except Exception as err:
                return _fail(channel, "reconfigure", err)
            # New parameters may change the inputs and outputs of a blueprint that kept state.
            channel.send({"t": "configured", "kept_state": kept, **_described(blueprint)})
        elif kind == "stop":
            try:
                blueprint.stop()
            finally:
                channel.send({"t": "stopped"})
            return 0


def _described(blueprint: Blueprint[Any]) -> dict[str, Any]:
    return {
        "inputs": blueprint.inputs(),
        "outputs": blueprint.outputs(),
        "describe": blueprint.describe(),
    }


def _fail(channel: BlockingChannel, where: str, err: Exception) -> int:
    message = f"{type(err).__name__}: {err}" if str(err) else type(err).__name__
    log.error("%s failed: %s\n%s", where, message, traceback.format_exc())
    with contextlib.suppress(OSError):
        channel.send({"t": "failed", "where": where, "error": message[:4000]})
    return EXIT_FAILED


def main(argv: list[str]) -> int:
    # The terminal's Ctrl-C is for the server, which stops workers gracefully itself.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    logging.basicConfig(
        stream=sys.stderr, level=logging.INFO, format="%(levelname)s %(name)s: %(message)s"
    )
    channel = BlockingChannel(socket.socket(fileno=int(argv[1])))
    try:
        return serve(channel)
    except ChannelClosed:
        return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
