"""Importing a blueprint's `.py` file or package folder by its path: the catalog finds folder
blueprints this way, and the Tvilling digital adapter (blueprints/tvilling.py) loads its
blueprints so. A module of its own, so that a blueprint needs nothing of the catalog."""

from __future__ import annotations

import hashlib
import importlib.util
import sys
from pathlib import Path
from types import ModuleType


def load_module(path: Path) -> ModuleType:
    """Import a `.py` file or a package folder by its path (once; the same module after)."""
    init = path / "__init__.py" if path.is_dir() else path
    digest = hashlib.sha1(str(path.resolve()).encode()).hexdigest()[:12]
    name = f"twinlink_blueprint_{path.stem}_{digest}"
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(
        name, init, submodule_search_locations=[str(path)] if path.is_dir() else None
    )
    if spec is None or spec.loader is None:
        raise ImportError(f"cannot load {path}")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[name]
        raise
    return module
