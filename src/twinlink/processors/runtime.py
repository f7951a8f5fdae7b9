"""Inside a worker: feeding one blueprint its inputs and collecting what it makes.

The runtime renames, scales and offsets source signals into the blueprint's inputs, applies the
rate limits (minimum input and output spacing), cuts large batches to `max_batch`, times each
`process` call, and gathers the events and commands the blueprint raised.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from twinlink.processors.blueprint import Batch, Blueprint
from twinlink.processors.spec import InputMap, Rates


class Runtime:
    def __init__(
        self, blueprint: Blueprint[Any], inputs: dict[str, InputMap], rates: Rates
    ) -> None:
        self.blueprint = blueprint
        self.maps = inputs
        self.rates = rates
        self.last_input_ns: int | None = None
        self.last_output_ns: int | None = None

    def feed(self, batch: Batch) -> tuple[dict[str, Any], Batch | None]:
        """Run one batch from the server: the reply (timings, events, commands), the outputs."""
        mapped = self._spaced(self._mapped(batch), self.rates.min_input_spacing_s, "input")
        outputs: list[Batch] = []
        timings: list[tuple[int, int]] = []
        step = self.rates.max_batch
        for start in range(0, len(mapped), step):
            chunk = mapped.take(slice(start, start + step)) if len(mapped) > step else mapped
            began = time.perf_counter_ns()
            made = self.blueprint.process(chunk)
            timings.append((time.perf_counter_ns() - began, len(chunk)))
            if made is not None and len(made):
                outputs.append(made)
            if self.blueprint.ctx.finished is not None:  # what comes after is not processed
                break
        out = Batch.concat(outputs) if outputs else None
        if out is not None:
            out = self._spaced(out, self.rates.min_output_spacing_s, "output")
        ctx = self.blueprint.ctx
        reply = {
            "n_in": len(batch),
            "timings": timings,
            "events": [[e.kind, e.message, e.time_ns, e.data] for e in ctx.events],
            "commands": [[c.name, c.params, c.device] for c in ctx.commands],
        }
        if ctx.finished is not None:
            reply["finished"] = [ctx.finished.message, ctx.finished.data]
        ctx.events.clear()
        ctx.commands.clear()
        return reply, out

    def _mapped(self, batch: Batch) -> Batch:
        wanted = self.blueprint.inputs()
        if not wanted:
            return batch
        columns: dict[str, np.ndarray] = {}
        for name in wanted:
            source = self.maps.get(name)
            column = batch.columns.get(source.signal if source else name)
            if column is None:
                continue
            if source is not None and (source.scale != 1.0 or source.offset != 0.0):
                column = column * source.scale + source.offset
            columns[name] = column
        return Batch(batch.times, columns)

    def _spaced(self, batch: Batch, spacing_s: float, which: str) -> Batch:
        """Keep samples at least `spacing_s` after the last one kept (greedy, in time order)."""
        if spacing_s <= 0 or not len(batch):
            return batch
        spacing = int(spacing_s * 1e9)
        attr = f"last_{which}_ns"
        last = getattr(self, attr)
        keep = []
        for i, t in enumerate(batch.times.tolist()):
            if last is None or t - last >= spacing:
                keep.append(i)
                last = t
        setattr(self, attr, last)
        return batch if len(keep) == len(batch) else batch.take(np.asarray(keep, dtype=np.int64))
