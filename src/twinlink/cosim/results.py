"""The results of a batch co-simulation: one row per communication point, a `time` column
then one column per recorded variable, and the CSV Maestro writes (its `outputs.csv`).

The rows live in one float64 array filled in place by the master, so recording a step is a
few numpy assignments, not Python work per value; the columns are views of it.
"""

from __future__ import annotations

import csv
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import IO

import numpy as np
import numpy.typing as npt

from .model import Port, System


def column_name(system: System, port: Port) -> str:
    """The CSV column of a recorded port: Maestro's `{fmu}.instance.var` for a Maestro
    multi-model (its instance "fmu.instance" gets its key's braces back), else
    `instance.var`."""
    if system.source == "maestro" and "." in port.instance:
        key, instance = port.instance.split(".", 1)
        return f"{{{key}}}.{instance}.{port.variable}"
    return str(port)


@dataclass(frozen=True, slots=True)
class Result:
    """The recorded rows. `ended` says why a run ended before `end_time` ("" if it did not):
    a stop asked for, or an FMU that asked to terminate (named)."""

    columns: tuple[str, ...]  # "time" first
    values: npt.NDArray[np.float64]  # rows x columns
    ended: str = ""

    @property
    def arrays(self) -> Mapping[str, npt.NDArray[np.float64]]:
        """Each column's values by name (views of `values`, not copies)."""
        return {name: self.values[:, i] for i, name in enumerate(self.columns)}

    def column(self, name: str) -> npt.NDArray[np.float64]:
        try:
            return self.values[:, self.columns.index(name)]
        except ValueError:
            raise KeyError(f"no recorded column {name!r}; the columns: {self.columns}") from None

    def write_csv(self, out: Path | IO[str]) -> None:
        """Write the rows as CSV: a header, then each value in its shortest exact form
        (Python's repr), so a value read back is the value computed."""
        if isinstance(out, Path):
            with out.open("w", newline="", encoding="utf-8") as file:
                self._write(file)
        else:
            self._write(out)

    def _write(self, file: IO[str]) -> None:
        writer = csv.writer(file, lineterminator="\n")
        writer.writerow(self.columns)
        writer.writerows([repr(v) for v in row] for row in self.values.tolist())
