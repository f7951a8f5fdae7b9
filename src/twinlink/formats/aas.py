"""The Asset Administration Shell (IDTA / IEC 63278): a twin exported as an AAS environment,
in JSON and as an AASX package, and an environment imported into a document fragment
(docs/formats.md "Asset Administration Shell").

Everything goes through the Eclipse BaSyx Python SDK: its model builds the shell (checking
the metamodel's constraints as each object is made), its writers serialise it, and its
readers check what comes in. Our own code only decides what goes where (_aas_export.py,
_aas_import.py).
"""

from __future__ import annotations

import io
import json
import logging
import threading
from datetime import UTC, datetime
from typing import Any

from basyx.aas import model
from basyx.aas.adapter import aasx
from basyx.aas.adapter.json import json_deserialization, json_serialization
from pyecma376_2.core_properties import OPCCoreProperties

from twinlink.domain.document import validate_part
from twinlink.domain.errors import DocumentError, InvalidInputError
from twinlink.domain.yamlsource import SourceDocument
from twinlink.formats import _aas_export, _aas_import
from twinlink.formats._aas_model import Store
from twinlink.formats.context import ExportContext

MEDIA_TYPE = "application/json"
# AAS Part 2 names the package so (the /serialization operation's answer).
AASX_MEDIA_TYPE = "application/asset-administration-shell-package+xml"
_TOP_LEVEL = ("assetAdministrationShells", "submodels", "conceptDescriptions")


def export_aas(document: dict[str, Any], ctx: ExportContext) -> dict[str, Any]:
    """The twin as an AAS environment in the JSON serialisation (AAS Part 2)."""
    text = json_serialization.object_store_to_json(_build(document, ctx))
    environment: dict[str, Any] = json.loads(text)
    return environment


def export_aasx(document: dict[str, Any], ctx: ExportContext) -> bytes:
    """The twin as an AASX package (AAS Part 5). The environment is in it as JSON
    (/aasx/data.json), the same serialisation as export_aas: Part 5 allows either, and the
    IDTA's JSON schema checks it (the XML schema the compliance tool ships is AAS 3.0's,
    older than the SDK's 3.1 XML)."""
    store = _build(document, ctx)
    shell_id = _aas_export.twin_id(document, ctx)
    buffer = io.BytesIO()
    with aasx.AASXWriter(buffer, failsafe=False) as writer:
        writer.write_aas(shell_id, store, _files(), write_json=True)
        properties = OPCCoreProperties()  # type: ignore[no-untyped-call]
        properties.creator = "twinlink"
        properties.title = str(document.get("name") or ctx.slug)
        properties.created = datetime.now(UTC)
        writer.write_core_properties(properties)
    return buffer.getvalue()


def import_aas(data: dict[str, Any]) -> dict[str, Any]:
    """A DT document fragment (id, name, description, manufacturer, owner, contact,
    interface) from an AAS environment in JSON, read as far as it can be: an object the SDK
    cannot make is left out (validate_aas names each; run it first to refuse such a file)."""
    return _checked(_aas_import.fragment(read_json(data, strict=False)))


def import_aasx(package: bytes) -> dict[str, Any]:
    """As import_aas, from an AASX package."""
    return _checked(_aas_import.fragment(read_aasx(package)))


def _checked(fragment: dict[str, Any]) -> dict[str, Any]:
    """The fragment, once twinlink's document checks accept it: another tool's shell may
    say what ours never would (a range whose min is above its max, two names alike)."""
    try:
        validate_part(SourceDocument({"version": "1.0", **fragment}))
    except DocumentError as err:
        listed = "; ".join(str(p) for p in err.problems)
        raise InvalidInputError(
            f"The AAS environment describes a twin twinlink cannot use: {listed}"
        ) from err
    return fragment


def validate_aas(data: Any) -> list[str]:
    """Problems of an AAS environment in JSON, empty when the SDK reads it whole: every
    object the SDK's reader had to skip (a constraint broken, a key missing, a wrong type),
    and submodel references the environment does not hold."""
    if not isinstance(data, dict):
        return ["an AAS environment is a JSON object (with assetAdministrationShells, submodels)"]
    problems = [
        f"unknown top-level key {key!r} (an environment has {', '.join(_TOP_LEVEL)})"
        for key in data
        if key not in _TOP_LEVEL
    ]
    with _SdkProblems() as logged:
        try:
            store = json_deserialization.read_aas_json_file(
                io.StringIO(json.dumps(data)), failsafe=True
            )
        except (ValueError, TypeError, KeyError, model.AASConstraintViolation) as err:
            return [*problems, *logged.messages, _first_line(str(err))]
    problems += logged.messages
    for shell in (x for x in store if isinstance(x, model.AssetAdministrationShell)):
        for ref in shell.submodel:
            try:
                ref.resolve(store)
            except (KeyError, model.UnexpectedTypeError):
                target = ref.key[-1].value if ref.key else "?"
                problems.append(
                    f"shell {shell.id!r} refers to submodel {target!r}, not in the file"
                )
    if not problems and not any(isinstance(x, model.AssetAdministrationShell) for x in store):
        problems.append("the environment has no assetAdministrationShells")
    return problems


def read_json(data: dict[str, Any], strict: bool = True) -> Store:
    """The SDK's objects from an environment in JSON. Strict, the first problem raises
    InvalidInputError; else objects the SDK cannot make are skipped (and logged by it)."""
    try:
        return json_deserialization.read_aas_json_file(
            io.StringIO(json.dumps(data)), failsafe=not strict
        )
    except (ValueError, TypeError, KeyError, model.AASConstraintViolation) as err:
        raise InvalidInputError(_refusal([_first_line(str(err))])) from err


def read_aasx(package: bytes) -> Store:
    """The SDK's objects from an AASX package, read strictly."""
    store: Store = Store()
    try:
        with aasx.AASXReader(io.BytesIO(package), failsafe=False) as reader:
            reader.read_into(store, _files())
    except (ValueError, TypeError, KeyError, OSError, model.AASConstraintViolation) as err:
        raise InvalidInputError(
            f"The file is not an AASX package twinlink can read: {_first_line(str(err))}"
        ) from err
    return store


def _files() -> aasx.DictSupplementaryFileContainer:
    # Supplementary files (documents, images) a package may carry; twins have none to add.
    return aasx.DictSupplementaryFileContainer()  # type: ignore[no-untyped-call]


def _build(document: dict[str, Any], ctx: ExportContext) -> Store:
    try:
        return _aas_export.build(document, ctx)
    except (ValueError, TypeError, KeyError, model.AASConstraintViolation) as err:
        # A value the metamodel cannot hold (an id over 2000 characters, say): the document
        # is valid for twinlink, so say what the shell refused.
        raise InvalidInputError(
            f"The twin cannot be written as an Asset Administration Shell: {_first_line(str(err))}"
        ) from err


def _refusal(problems: list[str]) -> str:
    more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
    return f"The AAS environment cannot be read: {problems[0]}{more}"


def _first_line(message: str) -> str:
    # The SDK's messages end with the whole offending JSON object after ">>>".
    return message.split(" >>> ", 1)[0].splitlines()[0] if message else "unknown error"


class _SdkProblems(logging.Handler):
    """Collects what the SDK's failsafe reader logs (warnings and errors) in this thread,
    for the duration of a `with` block: its reader reports skipped objects only there."""

    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.messages: list[str] = []
        self._thread = threading.get_ident()
        # The reader's own logger, not "basyx": a caller may have stopped it propagating
        # (the AAS compliance tool does).
        self._logger = logging.getLogger(json_deserialization.__name__)

    def emit(self, record: logging.LogRecord) -> None:
        if record.thread == self._thread:
            self.messages.append(_first_line(record.getMessage()))

    def __enter__(self) -> _SdkProblems:
        self._logger.addHandler(self)
        return self

    def __exit__(self, *exc: object) -> None:
        self._logger.removeHandler(self)
