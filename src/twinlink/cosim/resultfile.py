"""A run's outputs.csv read back for a chart: its columns, and at most `max_points` rows
picked evenly (the first and the last always among them), column by column (uPlot's shape).

A running co-simulation's file is read as far as it is written: a last line without its
end is left for the next read.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path
from typing import Any

import numpy as np


def read_columns(path: Path, max_points: int) -> dict[str, Any]:
    """{"columns": [...], "data": [[values of a column]...]} of the CSV at `path`."""
    try:
        text = path.read_bytes()
    except FileNotFoundError:
        return {"columns": [], "data": []}
    lines = text[: text.rfind(b"\n") + 1].splitlines()
    if not lines:
        return {"columns": [], "data": []}
    columns = next(csv.reader([lines[0].decode("utf-8", "replace")]))
    body = lines[1:]
    if len(body) > max_points:
        picked = np.unique(np.linspace(0, len(body) - 1, max_points).round().astype(np.int64))
        body = [body[i] for i in picked.tolist()]
    if not body:
        return {"columns": columns, "data": [[] for _ in columns]}
    values = np.loadtxt(io.BytesIO(b"\n".join(body)), delimiter=",", ndmin=2, dtype=np.float64)
    data = [[None if v != v else v for v in column] for column in values.T.tolist()]
    return {"columns": columns, "data": data}
