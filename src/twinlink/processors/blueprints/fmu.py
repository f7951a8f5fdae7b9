"""The `fmu` blueprint: runs an uploaded FMU (FMI 2.0 or 3.0) on the processor's input signals.

Time 0 of the FMU is the first sample's timestamp. In "samples" mode every sample sets the
inputs and steps the FMU to the sample's time, giving one output sample per input sample;
in "fixed" mode the FMU steps on a grid of `step_size_s`, holding the latest inputs, giving
one output sample per step.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import fmpy  # type: ignore[import-untyped]
import numpy as np
from pydantic import Field, field_validator, model_validator

from ..blueprint import MAX_SPAN_S, Batch, Blueprint, BlueprintError, Context, Params
from ..fmuinfo import FLOAT_TYPES, INT_TYPES, FmuError, FmuInfo, FmuVariable, Scalar, inspect_fmu
from ..fmurules import STREAMED_TYPES
from ._fmu_cs import CoSimulation, Engine
from ._fmu_fmi import ERROR, FATAL, FmuLog, Terminated, initialize, instantiate, value_for
from ._fmu_io import InputGuard, OutputReader
from ._fmu_loop import run_fixed, run_samples
from ._fmu_me import ModelExchange

OUTPUT_TYPES = FLOAT_TYPES | INT_TYPES | {"Boolean"}


class FmuParams(Params):
    fmu: str = Field(description="File name of an uploaded FMU (no folders).")
    inputs: list[str] | None = Field(
        None, description="FMU inputs to feed (numbers, Boolean, Enumeration); default: all."
    )
    outputs: list[str] | None = Field(
        None, description="FMU variables to output; default: all numeric outputs."
    )
    parameters: dict[str, Scalar] = Field(
        default_factory=dict,
        description="Values set before initialisation: parameters and start values.",
    )
    step: Literal["samples", "fixed"] = Field(
        "samples", description="Step to each input sample's time, or on a fixed grid."
    )
    step_size_s: float | None = Field(
        None,
        gt=0,
        le=MAX_SPAN_S,
        description="The grid step in seconds (required for step = fixed).",
    )
    out_of_range: Literal["clamp", "reject"] = Field(
        "clamp", description="Inputs outside their declared min/max: clamp, or skip the sample."
    )
    fmi_type: Literal["auto", "CoSimulation", "ModelExchange"] = Field(
        "auto", description="Which kind of FMU to run; auto: co-simulation if available."
    )
    solver: Literal["CVode", "Euler"] = Field("CVode", description="Model exchange solver.")
    solver_step_s: float | None = Field(
        None,
        gt=0,
        le=MAX_SPAN_S,
        description="Euler step; default: the FMU's default step or 1 ms.",
    )
    log_level: Literal["off", "errors", "all"] = Field(
        "errors", description="FMU log messages passed on to the processor log."
    )

    @field_validator("fmu")
    @classmethod
    def _plain_name(cls, name: str) -> str:
        if not name or any(c in name for c in "/\\\0") or ".." in name:
            raise ValueError("must be a plain file name (no folders, no '..')")
        return name

    @model_validator(mode="after")
    def _step_size(self) -> FmuParams:
        if self.step == "fixed" and self.step_size_s is None:
            raise ValueError("step = fixed needs step_size_s")
        return self


@dataclass(slots=True)
class _Run:
    """A started FMU instance and everything the hot loop needs."""

    fmu: Any
    log: FmuLog
    kind: str
    engine: Engine | None = None
    guard: InputGuard | None = None
    reader: OutputReader | None = None
    inputs: list[str] = field(default_factory=list)
    t0_ns: int | None = None
    steps: int = 0


class FmuBlueprint(Blueprint[FmuParams]):
    """Runs an FMU (FMI 2.0 or 3.0, co-simulation or model exchange) on the input signals."""

    name = "fmu"
    title = "FMU"
    Params = FmuParams
    keeps_state = True  # tunable parameters and out_of_range change in place

    def __init__(self, params: FmuParams, ctx: Context) -> None:
        super().__init__(params, ctx)
        self._info: FmuInfo | None = None
        self._by_name: dict[str, FmuVariable] = {}
        self._run: _Run | None = None

    # what the FMU offers ------------------------------------------------------------------

    def _path(self) -> Path:
        return Path(self.ctx.files) / self.params.fmu

    def info(self) -> FmuInfo:
        if self._info is None:
            try:
                self._info = inspect_fmu(self._path())
            except FmuError as err:
                raise BlueprintError(str(err)) from err
            self._by_name = {v.name: v for v in self._info.variables}
        return self._info

    def _variables(self, names: list[str], what: str) -> list[FmuVariable]:
        self.info()
        unknown = [n for n in names if n not in self._by_name]
        if unknown:
            names = list(self._by_name)
            valid = ", ".join(names[:20]) + (f", ... ({len(names)} in all)" if names[20:] else "")
            raise BlueprintError(f"unknown FMU {what}: {', '.join(unknown)} (valid: {valid})")
        return [self._by_name[n] for n in dict.fromkeys(names)]

    def _input_vars(self) -> list[FmuVariable]:
        if self.params.inputs is None:
            return [v for v in self.info().variables if _is_input(v)]
        chosen = self._variables(self.params.inputs, "inputs")
        wrong = [f"{v.name} ({v.causality} {v.type})" for v in chosen if not _is_input(v)]
        if wrong:
            raise BlueprintError(f"not scalar inputs of a number type: {', '.join(wrong)}")
        return chosen

    def _output_vars(self) -> list[FmuVariable]:
        if self.params.outputs is None:
            variables = self.info().variables
            return [v for v in variables if v.causality == "output" and _is_number(v)]
        chosen = self._variables(self.params.outputs, "outputs")
        wrong = [f"{v.name} ({v.type})" for v in chosen if not _is_number(v)]
        if wrong:
            raise BlueprintError(
                f"only numeric scalar variables can be outputs: {', '.join(wrong)}"
            )
        return chosen

    def _kind(self) -> str:
        info, wanted = self.info(), self.params.fmi_type
        kinds = [i.kind for i in info.interfaces if i.has_binary]
        if wanted == "auto" and kinds:
            return "CoSimulation" if "CoSimulation" in kinds else kinds[0]
        if wanted not in kinds:
            can = ", ".join(kinds) or "nothing"
            raise BlueprintError(f"the FMU cannot run as {wanted} here (it can run: {can})")
        return wanted

    def inputs(self) -> list[str]:
        return [v.name for v in self._input_vars()]

    def outputs(self) -> list[str]:
        return [v.name for v in self._output_vars()]

    def describe(self) -> dict[str, Any]:
        p = self.params
        d = self.info().as_dict()
        d |= {"inputs": self.inputs(), "outputs": self.outputs()}
        mode: dict[str, Any] = {"fmi_type": self._kind(), "step": p.step}
        mode |= {"step_size_s": p.step_size_s, "out_of_range": p.out_of_range}
        if mode["fmi_type"] == "ModelExchange":
            mode |= {"solver": p.solver, "solver_step_s": self._solver_step()}
        d["mode"] = mode
        run = self._run
        if run is not None and run.engine is not None and run.guard is not None:
            counts = dict(zip(run.guard.names, run.guard.counts, strict=True))
            d["state"] = {
                "time_s": run.engine.time,
                "clamped" if p.out_of_range == "clamp" else "rejected": counts,
                "skipped_samples": run.guard.skipped,
                "log": list(run.log.messages),
            }
        return d

    def _solver_step(self) -> float:
        return self.params.solver_step_s or self.info().default_experiment.step or 1e-3

    def _start_values(self) -> tuple[list[tuple[FmuVariable, Scalar]], ...]:
        """The `parameters` to set when instantiated, and in initialization mode."""
        pairs = list(
            zip(
                self._variables(list(self.params.parameters), "parameters"),
                self.params.parameters.values(),
                strict=True,
            )
        )
        before, during, refused = [], [], []
        for var, value in pairs:
            item = (var, value_for(var, value))
            if var.causality == "input" or (
                var.variability != "constant" and var.initial in {"exact", "approx"}
            ):
                before.append(item)
            elif var.causality != "parameter" and var.variability == "tunable":
                during.append(item)
            else:
                refused.append(f"{var.name} ({var.causality}, {var.variability})")
        if refused:
            raise BlueprintError(f"these variables cannot be set: {', '.join(refused)}")
        return before, during

    # running ------------------------------------------------------------------------------

    def start(self) -> None:
        self._info = None  # check the file again: it may have been replaced
        p, info = self.params, self.info()
        kind, inputs, outputs = self._kind(), self._input_vars(), self._output_vars()
        before, during = self._start_values()
        unzipdir = Path(self.ctx.workdir) / "fmu"
        try:
            fmpy.extract(str(self._path()), str(unzipdir))
        except Exception as err:  # FMPy raises plain Exception
            raise BlueprintError(f"cannot extract {p.fmu}: {err}") from err
        interface = info.interface(kind)
        if p.step == "samples" and interface and not interface.can_handle_variable_step:
            self.ctx.log.warning(
                "%s does not declare canHandleVariableCommunicationStepSize; "
                "irregular samples may need step = fixed",
                p.fmu,
            )
        log = FmuLog(p.log_level, self.ctx.log)
        fmu, api = instantiate(info, kind, unzipdir, log, self.ctx.processor or info.model_name)
        run = self._run = _Run(fmu=fmu, log=log, kind=kind, inputs=[v.name for v in inputs])
        try:
            initialize(fmu, api.fmi3, before, during, info.default_experiment.tolerance, log)
            if kind == "CoSimulation":
                run.engine = CoSimulation(fmu, api, log, inputs)
            else:
                tolerance = info.default_experiment.tolerance or 1e-5
                run.engine = ModelExchange(
                    fmu, api, log, inputs, info, p.solver, self._solver_step(), tolerance
                )
            run.engine.begin()
            run.reader = OutputReader(api, outputs, log)
        except BaseException:
            self.stop()
            raise
        held = {var.name: float(value) for var, value in before if var in inputs}
        start = [held.get(v.name, _number(v.start)) for v in inputs]
        run.guard = InputGuard(inputs, start, p.out_of_range, self.ctx, api.fmi3)

    def process(self, batch: Batch) -> Batch | None:
        run = self._run
        if run is None or run.engine is None or run.guard is None or run.reader is None:
            raise BlueprintError("the FMU is not started")
        if run.log.failed:
            raise BlueprintError(f"the FMU failed ({run.log.failure}); it must be restarted")
        columns = [batch.columns.get(name) for name in run.inputs]
        times, u = run.guard.condition(batch.times, columns)
        if len(times) == 0:
            return None
        run.engine.setter.bind(u)  # inputs other than Real/Float64, converted once a batch
        if run.t0_ns is None:
            run.t0_ns = int(times[0])
        t = (times - run.t0_ns) * 1e-9
        try:
            if self.params.step == "samples":
                run_samples(run.engine, run.reader, t, u)
            else:
                h = float(self.params.step_size_s or 0.0)
                steps = run_fixed(run.engine, run.reader, h, run.steps, t, u)
                run.steps += len(steps)
                times = run.t0_ns + np.rint(steps * (h * 1e9)).astype(np.int64)
        except Terminated as end:  # not a failure: what it made up to its end is kept
            return self._finished(run, end, times)
        except BlueprintError as err:  # a half-done batch: this instance cannot go on
            run.log.failed = max(run.log.failed, ERROR)
            run.log.failure = run.log.failure or str(err)
            raise
        return Batch(times, run.reader.columns()) if len(times) else None

    def _finished(self, run: _Run, end: Terminated, times: np.ndarray) -> Batch | None:
        """The FMU ended the simulation: the rows up to its end, the last at its end time;
        the worker then stops (terminating the FMU) and the processor is finished."""
        assert run.t0_ns is not None and run.reader is not None
        self.ctx.finish(f"the FMU finished: it asked to terminate at t = {end.time:g} s",
                        fmu_time_s=end.time)  # fmt: skip
        if self.params.step != "samples":
            h = float(self.params.step_size_s or 0.0)
            steps = np.arange(run.steps + 1, run.steps + end.rows + 1, dtype=np.int64)
            run.steps += end.rows
            times = run.t0_ns + np.rint(steps * (h * 1e9)).astype(np.int64)
        times = np.array(times[: end.rows], dtype=np.int64)
        if not len(times):
            return None
        times[-1] = run.t0_ns + round(end.time * 1e9)
        return Batch(times, run.reader.columns(end.rows))

    def reconfigure(self, params: FmuParams) -> bool:
        """In place if only tunable `parameters` values or `out_of_range` change."""
        run, old = self._run, self.params
        keep = {"parameters", "out_of_range"}
        if run is None or run.engine is None or run.guard is None or run.log.failed:
            return False
        if old.model_dump(exclude=keep) != params.model_dump(exclude=keep):
            return False
        if set(old.parameters) - set(params.parameters):
            return False
        changed = {k: v for k, v in params.parameters.items() if old.parameters.get(k) != v}
        variables = [self._by_name.get(name) for name in changed]
        tunable = [v for v in variables if v and v.causality == "parameter"]
        if len(tunable) != len(changed) or any(v.variability != "tunable" for v in tunable):
            return False
        try:
            values = [(v, value_for(v, changed[v.name])) for v in tunable]
            if values:
                run.engine.retune(values)
        except BlueprintError as err:
            self.ctx.log.warning("cannot retune the FMU, restarting it: %s", err)
            return False
        run.guard.mode = params.out_of_range
        self.params = params
        return True

    def stop(self) -> None:
        run, self._run = self._run, None
        if run is None:
            return
        if run.engine is not None:
            run.engine.close()
        steps = [] if run.log.failed else [("terminate", run.fmu.terminate)]
        if run.log.failed < FATAL:  # after fatal, no call is allowed: leave the instance
            steps.append(("freeInstance", run.fmu.freeInstance))
        for name, call in steps:
            try:
                call()
            except Exception as err:  # stop must not raise
                self.ctx.log.warning("FMU %s failed: %s (%s)", name, err, run.log.tail())


def _is_input(v: FmuVariable) -> bool:
    return v.causality == "input" and v.type in STREAMED_TYPES and not v.shape


def _number(start: Scalar | None) -> float:
    """An input's start value as the float its signal holds until a sample comes."""
    return float(start) if isinstance(start, int | float) else 0.0


def _is_number(v: FmuVariable) -> bool:
    return v.type in OUTPUT_TYPES and not v.shape
