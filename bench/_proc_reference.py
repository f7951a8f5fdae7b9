"""The ceilings, in this process and without the platform: FMPy's own FMU2Slave stepping the
Tingen FMU one call at a time, and the `fmu` blueprint alone on batches (what a worker runs,
without the server, the bus, the channel or the live clients)."""

from __future__ import annotations

import logging
import math
import shutil
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

from _live_report import Row, per_s
from _proc_setup import FMU_NAME, ProcBench

STEP_NS = 1_000_000  # 1 kHz, as the rig samples
T0_NS = 1_700_000_000_000_000_000


def forces(n: int, offset: int = 0) -> np.ndarray:
    """The force a device of the live benchmark sends (_live_client.value_pool), in N."""
    k = np.arange(offset, offset + n) % 997
    return np.round(np.sin(0.01 * k + 1) * 2, 6)


def raw_fmpy(fmu: Path, steps: int) -> dict[str, Any]:
    """FMU2Slave: setReal / doStep / getReal per step, as an FMPy script would."""
    import fmpy  # type: ignore[import-untyped]
    from fmpy.fmi2 import FMU2Slave  # type: ignore[import-untyped]

    md = fmpy.read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    unzipped = tempfile.mkdtemp(prefix="twinlink-bench-fmpy-")
    slave = FMU2Slave(
        guid=md.guid,
        unzipDirectory=fmpy.extract(str(fmu), unzipped),
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="reference",
    )
    try:
        slave.instantiate()
        slave.setupExperiment(startTime=0.0)
        slave.enterInitializationMode()
        slave.exitInitializationMode()
        inputs, outputs = [vr["F"]], [vr["theta"], vr["sigma"]]
        values = forces(steps).tolist()
        h = STEP_NS * 1e-9
        began = time.perf_counter()
        for k, force in enumerate(values):
            slave.setReal(inputs, [force])
            slave.doStep(k * h, h)
            last = slave.getReal(outputs)
        seconds = time.perf_counter() - began
        slave.terminate()
        slave.freeInstance()
    finally:
        shutil.rmtree(unzipped, ignore_errors=True)
    rate = steps / seconds
    return {"steps": steps, "seconds": round(seconds, 3), "steps_per_s": rate, "last": last[0]}


def blueprint_alone(fmu: Path, steps: int, batch: int) -> dict[str, Any]:
    """FmuBlueprint.process() on batches of `batch` samples, 1 ms apart, as a worker calls it."""
    from twinlink.processors.blueprint import Batch, Context
    from twinlink.processors.blueprints.fmu import FmuBlueprint, FmuParams

    folder = Path(tempfile.mkdtemp(prefix="twinlink-bench-blueprint-"))
    (folder / "files").mkdir()
    (folder / "work").mkdir()
    shutil.copy(fmu, folder / "files" / FMU_NAME)
    log = logging.getLogger("bench.blueprint")
    ctx = Context("reference", "bench", folder / "files", folder / "work", log=log)
    blueprint = FmuBlueprint(FmuParams(fmu=FMU_NAME, outputs=["theta", "sigma"]), ctx)
    cuts = [(i, min(steps, i + batch)) for i in range(0, steps, batch)]
    batches = [Batch.of(T0_NS + np.arange(a, b) * STEP_NS, F=forces(b - a, a)) for a, b in cuts]
    try:
        blueprint.start()
        began = time.perf_counter()
        made = sum(len(blueprint.process(b) or ()) for b in batches)
        seconds = time.perf_counter() - began
        blueprint.stop()
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    if made != steps:
        raise RuntimeError(f"the blueprint made {made} outputs from {steps} samples")
    rate = steps / seconds
    return {"steps": steps, "batch": batch, "seconds": round(seconds, 3), "steps_per_s": rate}


async def reference(bench: ProcBench) -> list[Row]:
    """Both references, before any processor runs (the server is idle meanwhile)."""
    opts = bench.opts
    raw = raw_fmpy(bench.fmu, opts.reference_steps)
    alone = blueprint_alone(bench.fmu, opts.reference_steps, opts.reference_batch)
    if not math.isfinite(raw["last"]):
        raise RuntimeError(f"raw FMPy gave theta = {raw['last']}")
    return [
        Row(
            "reference: raw FMPy, in-process",
            measured=per_s(raw["steps_per_s"], "steps"),
            value=raw["steps_per_s"],
            details=raw,
            note=f"FMU2Slave setReal/doStep/getReal per step, {raw['steps']} steps in "
            f"{raw['seconds']:.2f} s ({1e6 / raw['steps_per_s']:.1f} us a step)",
        ),
        Row(
            "reference: fmu blueprint alone, in-process",
            measured=per_s(alone["steps_per_s"], "steps"),
            value=alone["steps_per_s"],
            details=alone,
            note=f"process() on batches of {alone['batch']}: {1e6 / alone['steps_per_s']:.1f} "
            f"us a step ({alone['steps_per_s'] / raw['steps_per_s']:.1f}x raw FMPy: the "
            "blueprint calls the FMI functions on preallocated arrays)",
        ),
    ]
