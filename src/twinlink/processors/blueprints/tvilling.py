"""Runs blueprints written for NTNU's "Tvilling digital" platform as twinlink blueprints.

Such a blueprint is a module defining `class P`: `P(**init_params)`; its inputs and outputs as
`input_names` / `output_names` tuples (the value reference is the index) or as `inputs` /
`outputs` lists of objects with `.name` and `.valueReference`; `set_inputs(refs, values)`,
`step(t)` and `get_outputs(refs)` (None: nothing now); optionally `start(start_time,
**start_params)`, `stop()` and `get_time()`. Times are seconds since the first sample. The
original's input proportions and input / output spacing are the runtime's input scale and
rate limits; its step spacing is `Context.step_spacing_s`.
`tvilling_blueprint(name, P)` makes the Blueprint class; `load_tvilling(path)` loads a folder
with `__init__.py` or a single `.py` file and does the same.
"""

from __future__ import annotations

import inspect
import re
import sys
import typing
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
from pydantic import BaseModel, Field, TypeAdapter, create_model

from twinlink.processors.blueprint import Batch, Blueprint, BlueprintError, Context, Params
from twinlink.processors.fileimport import load_module

RESERVED = ("start_params", "outputs")


@dataclass(frozen=True, slots=True)
class Variable:
    valueReference: int  # the original's name
    name: str


def variables(instance: Any, listed: str, named: str) -> list[Variable]:
    """A P's inputs or outputs: from `inputs` / `outputs` objects, else from the name tuples."""
    if hasattr(instance, listed):
        return [Variable(int(v.valueReference), str(v.name)) for v in getattr(instance, listed)]
    return [Variable(i, str(name)) for i, name in enumerate(getattr(instance, named, ()))]


def param_docs(doc: str | None) -> dict[str, str]:
    """`:param name: text` lines of a docstring."""
    found = re.findall(r"^\s*:param\s+(\w+):\s*(.*?)\s*$", doc or "", flags=re.MULTILINE)
    return {name: text for name, text in found}


def guess_type(default: Any, annotation: Any) -> Any:
    """The annotation when pydantic can use it, else a type guessed from the default."""
    if annotation is not inspect.Parameter.empty:
        try:
            TypeAdapter(annotation).json_schema()
            return annotation
        except Exception:  # an annotation pydantic cannot handle: fall back to the default
            pass
    if isinstance(default, bool):
        return bool
    if isinstance(default, int):
        return int | float  # the original passed numbers through as given: 10 may mean 10.5
    if isinstance(default, float):
        return float
    if isinstance(default, str):
        return str
    if isinstance(default, list | tuple):
        return list[Any]
    if isinstance(default, dict):
        return dict[str, Any]
    return Any


def params_model(name: str, p_class: type) -> type[BaseModel]:
    """The Params model of a P: `P.__init__`'s parameters plus the adapter's own."""
    init = p_class.__init__  # type: ignore[misc]
    try:
        hints = typing.get_type_hints(init)
    except Exception:  # unresolvable annotations: guess from the defaults
        hints = {}
    docs = param_docs(inspect.getdoc(init))
    fields: dict[str, Any] = {}
    for pname, param in list(inspect.signature(init).parameters.items())[1:]:
        if param.kind in (param.VAR_POSITIONAL, param.VAR_KEYWORD):
            continue
        if pname in RESERVED:
            raise BlueprintError(f"{name}: P's parameter {pname!r} clashes with the adapter's")
        default = ... if param.default is param.empty else param.default
        kind = guess_type(param.default, hints.get(pname, param.empty))
        safe = pname if not (pname.startswith("_") or hasattr(BaseModel, pname)) else f"p{pname}"
        alias = pname if safe != pname else None
        fields[safe] = (kind, Field(default, description=docs.get(pname, pname), alias=alias))
    fields["start_params"] = (
        dict[str, Any],
        Field(default_factory=dict, description="Keyword arguments of P.start."),
    )
    fields["outputs"] = (
        list[str] | None,
        Field(None, description="The outputs to use, by name; empty: all of them."),
    )
    model_name = "".join(w.capitalize() for w in re.split(r"\W|_", name)) + "Params"
    return create_model(model_name, __base__=Params, **fields)


class TvillingBlueprint(Blueprint[Any]):
    """The adapter: runs a P sample by sample with the original platform's rules."""

    p_class: ClassVar[type] = object

    def __init__(self, params: Any, ctx: Context) -> None:
        super().__init__(params, ctx)
        values = params.model_dump(by_alias=True, exclude=set(RESERVED))
        self._p = self._call(f"{self.name}: P", self.p_class, **values)
        self._in = self._call("inputs", variables, self._p, "inputs", "input_names")
        available = self._call("outputs", variables, self._p, "outputs", "output_names")
        by_name = {v.name: v for v in available}
        wanted = params.outputs if params.outputs is not None else list(by_name)
        if unknown := [o for o in wanted if o not in by_name]:
            raise BlueprintError(f"{self.name}: no output {unknown[0]!r}; it has {list(by_name)}")
        self._out = [by_name[o] for o in wanted]
        self._available = available
        self._start_ns: int | None = None
        self._next_step = 0

    def inputs(self) -> list[str]:
        return [v.name for v in self._in]

    def outputs(self) -> list[str]:
        return [v.name for v in self._out]

    def describe(self) -> dict[str, Any]:
        def listed(vs: list[Variable]) -> list[dict[str, Any]]:
            return [{"name": v.name, "valueReference": v.valueReference} for v in vs]

        return {
            "inputs": listed(self._in),
            "outputs": listed(self._out),
            "available_outputs": listed(self._available),
        }

    def start(self) -> None:
        if hasattr(self._p, "start"):
            self._call("start", self._p.start, start_time=0.0, **self.params.start_params)

    def stop(self) -> None:
        if hasattr(self._p, "stop"):
            self._call("stop", self._p.stop)

    def _call(self, what: str, fn: Callable[..., Any], *args: Any, **kwargs: Any) -> Any:
        try:
            return fn(*args, **kwargs)
        except BlueprintError:
            raise
        except Exception as e:
            raise BlueprintError(f"{what}: {e}") from e

    def process(self, batch: Batch) -> Batch | None:
        if len(batch) == 0:
            return None
        if self._start_ns is None:
            self._start_ns = int(batch.times[0])
        columns = [batch.columns.get(v.name) for v in self._in]
        present = [c for c in columns if c is not None]
        values = np.zeros((len(batch), len(self._in)))
        if len(present) == len(columns):
            for j, c in enumerate(present):
                values[:, j] = c
            ready = np.asarray(np.isfinite(values).all(axis=1))
        else:
            ready = np.zeros(len(batch), dtype=bool)
        times, rows = self._run(batch.times.tolist(), values.tolist(), ready.tolist())
        if not times:
            return None
        table = np.array(rows, dtype=np.float64).reshape(len(times), len(self._out))
        return Batch(
            np.array(times, dtype=np.int64),
            {v.name: table[:, j] for j, v in enumerate(self._out)},
        )

    def _run(
        self, times: list[int], values: list[list[float]], ready: list[bool]
    ) -> tuple[list[int], list[list[float]]]:
        """The original's loop: set_inputs, step (if the step spacing allows), get_outputs."""
        p, start = self._p, self._start_ns or 0
        in_refs = [v.valueReference for v in self._in]
        out_refs = [v.valueReference for v in self._out]
        spacing = round(self.ctx.step_spacing_s * 1e9)
        get_time = getattr(p, "get_time", None)
        out_times: list[int] = []
        rows: list[list[float]] = []
        what = "set_inputs"
        try:
            for i, t_ns in enumerate(times):
                if ready[i]:
                    what = "set_inputs"
                    p.set_inputs(in_refs, values[i])
                if t_ns >= self._next_step:
                    what = "step"
                    p.step((t_ns - start) / 1e9)
                    self._next_step = t_ns + spacing
                what = "get_outputs"
                result = p.get_outputs(out_refs)
                if result is not None:
                    rows.append(self._numbers(result))
                    what = "get_time"
                    out_times.append(start + round(get_time() * 1e9) if get_time else t_ns)
        except BlueprintError:
            raise
        except Exception as e:
            raise BlueprintError(f"{what}: {e}") from e
        return out_times, rows

    def _numbers(self, result: Any) -> list[float]:
        try:
            row = [float(x) for x in result]
        except (TypeError, ValueError) as e:
            raise BlueprintError(f"get_outputs gave something that is not numbers: {e}") from e
        if len(row) != len(self._out):
            raise BlueprintError(f"get_outputs gave {len(row)} values for {len(self._out)} outputs")
        return row


def slug(name: str) -> str:
    return re.sub(r"\W", "_", name)


def tvilling_blueprint(name: str, p_class: type) -> type[Blueprint[Any]]:
    """A Blueprint class running the Tvilling digital blueprint `p_class` (its class P)."""
    module = sys.modules.get(p_class.__module__)
    doc = inspect.cleandoc(getattr(module, "__doc__", None) or p_class.__doc__ or name)
    attributes = {
        "__doc__": f"{doc}\n\n(A blueprint of the Tvilling digital platform, run by an adapter.)",
        "__module__": __name__,
        "name": name,
        "Params": params_model(name, p_class),
        "p_class": p_class,
    }
    return type(f"Tvilling_{slug(name)}", (TvillingBlueprint,), attributes)


def load_tvilling(path: Path, name: str | None = None) -> type[Blueprint[Any]]:
    """Loads a Tvilling digital blueprint (a folder with `__init__.py`, or a `.py` file)."""
    folder = path.is_dir()
    name = name or (path.name if folder else path.stem)
    if not (path / "__init__.py" if folder else path).is_file():
        raise BlueprintError(f"{path}: not a Python module")
    try:
        module = load_module(path)
    except Exception as e:
        raise BlueprintError(f"{path}: cannot be imported: {e}") from e
    p_class = getattr(module, "P", None)
    if not isinstance(p_class, type):
        raise BlueprintError(f"{path}: defines no class P")
    return tvilling_blueprint(name, p_class)
