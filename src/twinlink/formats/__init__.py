"""Exchange formats for DT documents (docs/formats.md): W3C WoT Thing Description 1.1,
DTDL v3 and the Asset Administration Shell, exported from and imported into a document.

FORMATS names each export a twin's canonical URL serves (`/twins/{slug}?format=NAME`) with
its media type and its conversion; the AASX package, a file rather than a JSON document, has
its own route (`/twins/{slug}/export.aasx`, formats.aas.export_aasx)."""

from __future__ import annotations

import importlib
from collections.abc import Callable
from typing import Any

from twinlink.formats.context import ExportContext

Exporter = Callable[[dict[str, Any], ExportContext], dict[str, Any]]


def _on_use(module: str, function: str) -> Exporter:
    """`twinlink.formats.{module}.{function}`, imported at its first call: importing one
    format (or the package) does not load every format's libraries (the AAS SDK, the TD
    schema's validator)."""

    def export(document: dict[str, Any], ctx: ExportContext) -> dict[str, Any]:
        found: Exporter = getattr(importlib.import_module(f"{__name__}.{module}"), function)
        return found(document, ctx)

    export.__name__ = export.__qualname__ = function
    return export


FORMATS: dict[str, tuple[str, Exporter]] = {
    "wot-td": ("application/td+json", _on_use("wot", "export_wot")),  # registered by the TD spec
    "dtdl": ("application/ld+json", _on_use("dtdl", "export_dtdl")),  # DTDL is JSON-LD
    "aas-json": ("application/json", _on_use("aas", "export_aas")),  # as the AAS API serves it
}
