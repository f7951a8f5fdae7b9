"""Finding blueprints: installed packages (entry points) and the blueprints folder.

The built-in blueprints are ordinary entry points of the `twinlink.blueprints` group, found the
same way as a third-party package's, and as connector kinds and credential methods are
(`twinlink.plugins`, docs/plugins.md). In the folder, a `name.py` file or a `name/` package may
define Blueprint subclasses, or a Tvilling digital style `class P` (run through the adapter
under the module's name). A module that fails to import is listed with its error.

A blueprint is named by a reference (`ref`) that a worker process can load on its own:
`{"entry": "package.module:Class"}` or `{"path": "/abs/file.py", "class": "Class"}` or
`{"path": "/abs/folder", "tvilling": "name"}`.
"""

from __future__ import annotations

import importlib
import inspect
import logging
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from twinlink.plugins import BLUEPRINTS, registered
from twinlink.processors.blueprint import Blueprint, describe_blueprint
from twinlink.processors.blueprints.tvilling import tvilling_blueprint
from twinlink.processors.fileimport import load_module

log = logging.getLogger("twinlink.processors")
GROUP = BLUEPRINTS

BlueprintClass = type[Blueprint[Any]]


@dataclass(slots=True)
class Entry:
    """A blueprint found; an installed one is imported only when first needed (its
    dependencies, SciPy or FMPy, are heavy), so starting the server stays fast."""

    name: str
    ref: dict[str, str]
    source: str  # "installed" or "folder"
    _cls: BlueprintClass | None = None
    error: str | None = None

    @property
    def cls(self) -> BlueprintClass | None:
        if self._cls is None and self.error is None:
            try:
                self._cls = load_ref(self.ref)
            except Exception as err:  # a broken plug-in is listed, never fatal
                self.error = f"{type(err).__name__}: {err}"
        return self._cls

    def view(self) -> dict[str, Any]:
        if self.cls is None:
            return {"name": self.name, "source": self.source, "error": self.error}
        return {**describe_blueprint(self.cls), "name": self.name, "source": self.source}


def load_ref(ref: dict[str, str]) -> BlueprintClass:
    """The blueprint class a reference names (in the server or in a worker)."""
    if "entry" in ref:
        module_name, _, attr = ref["entry"].partition(":")
        cls = getattr(importlib.import_module(module_name), attr)
    else:
        module = load_module(Path(ref["path"]))
        if "tvilling" in ref:
            cls = tvilling_blueprint(ref["tvilling"], module.P)
        else:
            cls = getattr(module, ref["class"])
    if not (inspect.isclass(cls) and issubclass(cls, Blueprint)):
        raise TypeError(f"{ref} is not a Blueprint subclass")
    return cls


def discover(folder: Path | None) -> dict[str, Entry]:
    """Every blueprint, installed ones first; a folder blueprint may not shadow one of them."""
    found: dict[str, Entry] = {}
    for name, ep in registered(GROUP).items():  # a name claimed twice: twinlink's wins
        found[name] = Entry(name, {"entry": ep.target}, "installed")
    if folder is not None and folder.is_dir():
        for entry in _folder_entries(folder):
            if entry.name in found:
                log.warning(
                    "blueprint %r in %s is shadowed by an installed one", entry.name, folder
                )
                continue
            found[entry.name] = entry
    return found


def _folder_entries(folder: Path) -> list[Entry]:
    entries: list[Entry] = []
    for path in sorted(folder.iterdir()):
        if path.name.startswith(("_", ".")):
            continue
        if not (path.suffix == ".py" or (path / "__init__.py").is_file()):
            continue
        try:
            entries.extend(_module_entries(path))
        except Exception as err:  # a syntax error in one file must not hide the others
            entries.append(Entry(path.stem, {}, "folder", error=f"{type(err).__name__}: {err}"))
    return entries


def _module_entries(path: Path) -> list[Entry]:
    module = load_module(path)
    entries = []
    for attr, value in vars(module).items():
        if (
            inspect.isclass(value)
            and issubclass(value, Blueprint)
            and value.__module__ == module.__name__
            and value.name
        ):
            ref = {"path": str(path.resolve()), "class": attr}
            entries.append(Entry(value.name, ref, "folder", _cls=value))
    if not entries and inspect.isclass(getattr(module, "P", None)):
        ref = {"path": str(path.resolve()), "tvilling": path.stem}
        entries.append(Entry(path.stem, ref, "folder", _cls=load_ref(ref)))
    return entries
