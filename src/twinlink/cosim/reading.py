"""One entry point for a co-simulation file: `read_system(path)` chooses the reader.

By extension: `.ssp` an SSP archive (ssp.py), `.yaml`/`.yml` twinlink's YAML form
(yamlform.py), `.json` a Maestro file (maestro.py). Another extension is told by its content:
a zip holding SystemStructure.ssd is SSP, text opening with `{` Maestro JSON, other text
YAML.

A Maestro JSON is either a multi-model (it has `fmus`; Maestro 2's single file holds its
settings too) or the INTO-CPS app's settings file, coe.json (no `fmus`, a
`multimodel_path`). A multi-model without an `algorithm` takes its settings from a coe.json
beside it; a coe.json finds its multi-model at `multimodel_path` relative to its own folder
or to one above it up to `root` (the app writes it relative to the project folder), or by
its name alone in one of those folders. Nothing outside `root` (by default the file's own
folder) is read.

Maestro's var-step `constraints` are read into the algorithm and applied (constraints.py).
What a Maestro file asks that is not done is its stabilisation (`stabalizationEnabled`, with
`global_absolute_tolerance` and `global_relative_tolerance`: iterating each step until the
coupled values settle): reading such a file logs a warning saying so, and
`unapplied(path)` lists it for a caller to show.
"""

from __future__ import annotations

import json
import logging
import zipfile
from pathlib import Path
from typing import Any

from .maestro import read_maestro
from .model import CosimFormatError, System
from .ssp import SSD_NAME, read_ssp
from .yamlform import read_yaml

_log = logging.getLogger("twinlink.cosim")
SETTINGS_NAME = "coe.json"  # the INTO-CPS app's name for a multi-model's settings


def read_system(
    path: Path | str, *, step_size: float | None = None, root: Path | None = None
) -> System:
    """The System the file at `path` describes. `step_size`: an SSP archive's fixed step
    (SSP has none of its own; its DefaultExperiment gives the span). `root`: the folder a
    coe.json's multi-model is looked for in (the file's own by default). Raises
    CosimFormatError naming the file and what is wrong."""
    path = Path(path)
    kind = format_of(path)
    if kind == "ssp":
        return read_ssp(path, step_size)
    if kind == "yaml":
        return read_yaml(path)
    data = _json(path)
    for note in _unapplied(data):
        _log.warning("%s: %s", path.name, note)
    if "fmus" in data:
        sibling = path.parent / SETTINGS_NAME
        if "algorithm" not in data and sibling.is_file() and sibling != path:
            return read_maestro(path, settings=sibling)
        return read_maestro(path)
    return read_maestro(_multimodel_of(path, data, root), settings=path.resolve())


def format_of(path: Path) -> str:
    """ "ssp", "yaml" or "maestro": by extension, else by content."""
    suffix = path.suffix.lower()
    if suffix == ".ssp":
        return "ssp"
    if suffix in (".yaml", ".yml"):
        return "yaml"
    if suffix == ".json":
        return "maestro"
    try:
        if zipfile.is_zipfile(path):
            with zipfile.ZipFile(path) as archive:
                if SSD_NAME in archive.namelist():
                    return "ssp"
            raise CosimFormatError(f"{path.name}: a zip archive without {SSD_NAME} at its root")
        with path.open("rb") as file:
            head = file.read(4096).lstrip()
    except OSError as err:
        raise CosimFormatError(f"{path.name}: cannot be read: {err.strerror or err}") from err
    return "maestro" if head.startswith(b"{") else "yaml"


def unapplied(path: Path | str) -> list[str]:
    """What a Maestro file asks that the masters do not do (stabilisation), each as a
    sentence; [] for other formats."""
    path = Path(path)
    if format_of(path) != "maestro":
        return []
    data = _json(path)
    if "fmus" in data and "algorithm" not in data and (path.parent / SETTINGS_NAME).is_file():
        data = _json(path.parent / SETTINGS_NAME)
    return _unapplied(data)


def _json(path: Path) -> dict[str, Any]:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except OSError as err:
        raise CosimFormatError(f"{path.name}: cannot be read: {err.strerror or err}") from err
    except UnicodeDecodeError as err:
        raise CosimFormatError(f"{path.name}: is not UTF-8 text: {err.reason}") from err
    except json.JSONDecodeError as err:
        raise CosimFormatError(
            f"{path.name}: line {err.lineno}, column {err.colno}: {err.msg}"
        ) from err
    if not isinstance(data, dict):
        raise CosimFormatError(f"{path.name}: is not a JSON object")
    return data


def _multimodel_of(path: Path, settings: dict[str, Any], root: Path | None) -> Path:
    """The multi-model a coe.json names, inside `root`."""
    named = settings.get("multimodel_path")
    if not isinstance(named, str) or not named:
        raise CosimFormatError(
            f'{path.name}: neither a multi-model (no "fmus") nor settings naming one '
            '(no "multimodel_path")'
        )
    relative = Path(named)
    if relative.is_absolute() or ".." in relative.parts:
        raise CosimFormatError(f"{path.name}: multimodel_path {named!r} leaves the folder")
    folder = path.resolve().parent
    top = (root or folder).resolve()
    bases = [base for base in (folder, *folder.parents) if base.is_relative_to(top)]
    candidates = [base / relative for base in bases]
    candidates += [base / relative.name for base in bases]
    for candidate in candidates:
        if candidate.is_file():
            return candidate
    raise CosimFormatError(
        f"{path.name}: multimodel_path {named!r} is not found from this folder or one above "
        f"it up to {top} (the folder the multi-model is looked for in)"
    )


def _unapplied(data: dict[str, Any]) -> list[str]:
    if data.get("stabalizationEnabled") is not True:  # Maestro's spelling
        return []
    tolerances = ", ".join(
        f"{key} {data[key]}"
        for key in ("global_absolute_tolerance", "global_relative_tolerance")
        if key in data
    )
    return [
        "stabalizationEnabled is not applied: the masters step each FMU once per step and do "
        "not iterate until the coupled values settle"
        + (f" (its {tolerances} are not used)" if tolerances else "")
    ]
