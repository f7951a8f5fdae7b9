"""Check an uploaded FMU file and describe it (FMI 2.0 and 3.0), without running it.

`inspect_fmu` looks at the archive first (size, paths), then lets FMPy validate and read the
modelDescription.xml, and reports whether a binary for this platform is present. Anything
wrong with the file becomes an `FmuError` with a message meant for the person who uploaded it.
"""

from __future__ import annotations

import math
import zipfile
from dataclasses import asdict, dataclass, field
from pathlib import Path, PurePosixPath
from typing import Any, Literal

import fmpy  # type: ignore[import-untyped]
from fmpy.model_description import ValidationError  # type: ignore[import-untyped]
from fmpy.validation import validate_fmu  # type: ignore[import-untyped]
from lxml import etree  # type: ignore[import-untyped]

from twinlink.domain.errors import TwinlinkError

GiB = 1 << 30
FLOAT_TYPES = frozenset({"Real", "Float64", "Float32"})
INT_TYPES = frozenset(
    {"Integer", "Enumeration", "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64"}
    | {"UInt64"}
)
Scalar = float | int | bool | str
Kind = Literal["CoSimulation", "ModelExchange"]


class FmuError(TwinlinkError):
    """The file is not an FMU this platform can run; the message says why."""


@dataclass(frozen=True, slots=True)
class FmuVariable:
    """One model variable, with its declared type's unit and range filled in."""

    name: str
    value_reference: int
    causality: str
    variability: str
    type: str  # Real/Integer/Boolean/String/Enumeration (FMI 2), Float64/Int32/... (FMI 3)
    initial: str | None = None
    unit: str | None = None
    start: Scalar | None = None
    min: float | None = None
    max: float | None = None
    description: str | None = None
    shape: tuple[int, ...] = ()  # FMI 3 arrays; () for scalars
    items: tuple[tuple[str, int], ...] = ()  # an Enumeration's declared items (name, value)

    def as_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["shape"] = list(self.shape)
        d["items"] = [{"name": name, "value": value} for name, value in self.items]
        return d


@dataclass(frozen=True, slots=True)
class FmuInterface:
    """A kind of FMU the file implements."""

    kind: Kind
    model_identifier: str
    has_binary: bool  # binaries/<this platform>/<model_identifier>.so is in the archive
    needs_completed_integrator_step: bool = False  # model exchange only
    can_handle_variable_step: bool = True  # co-simulation: canHandleVariableCommunicationStepSize

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True, slots=True)
class DefaultExperiment:
    start: float | None = None
    stop: float | None = None
    step: float | None = None
    tolerance: float | None = None

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True, slots=True)
class FmuInfo:
    fmi_version: str  # "2.0" or "3.0"
    model_name: str
    guid: str  # the GUID (FMI 2) or instantiationToken (FMI 3)
    description: str | None
    generation_tool: str | None
    platform: str  # the binaries folder this platform uses
    interfaces: tuple[FmuInterface, ...]
    default_experiment: DefaultExperiment = field(default_factory=DefaultExperiment)
    number_of_continuous_states: int = 0
    number_of_event_indicators: int = 0
    variables: tuple[FmuVariable, ...] = ()

    @property
    def co_simulation(self) -> bool:
        return self.interface("CoSimulation") is not None

    @property
    def model_exchange(self) -> bool:
        return self.interface("ModelExchange") is not None

    @property
    def has_binary(self) -> bool:
        return any(i.has_binary for i in self.interfaces)

    def interface(self, kind: str) -> FmuInterface | None:
        return next((i for i in self.interfaces if i.kind == kind), None)

    def variable(self, name: str) -> FmuVariable | None:
        return next((v for v in self.variables if v.name == name), None)

    def as_dict(self) -> dict[str, Any]:
        return {
            "fmi_version": self.fmi_version,
            "model_name": self.model_name,
            "guid": self.guid,
            "description": self.description,
            "generation_tool": self.generation_tool,
            "platform": self.platform,
            "co_simulation": self.co_simulation,
            "model_exchange": self.model_exchange,
            "has_binary": self.has_binary,
            "interfaces": [i.as_dict() for i in self.interfaces],
            "default_experiment": self.default_experiment.as_dict(),
            "number_of_continuous_states": self.number_of_continuous_states,
            "number_of_event_indicators": self.number_of_event_indicators,
            "variables": [v.as_dict() for v in self.variables],
        }


def inspect_fmu(path: Path, *, max_unpacked: int = GiB, require_binary: bool = True) -> FmuInfo:
    """Validate the FMU at `path` and describe it; raise FmuError if it cannot be used.

    The archive is refused if it would unpack to more than `max_unpacked` bytes or has paths
    that leave the folder it is extracted to; with `require_binary`, it must also contain a
    shared library for this platform.
    """
    names = check_archive(path, max_unpacked)
    _check_version(path)
    problems = validate_fmu(str(path))
    if problems:
        raise FmuError(f"{path.name} is not a valid FMU:\n" + "\n".join(f"- {p}" for p in problems))
    try:
        md = fmpy.read_model_description(str(path), validate=True)
    except ValidationError as err:
        lines = "\n".join(f"- {p}" for p in err.problems)
        raise FmuError(f"{path.name} is not a valid FMU:\n{lines}") from err
    except Exception as err:  # FMPy raises plain Exception, lxml and zipfile their own
        raise FmuError(f"cannot read the modelDescription.xml of {path.name}: {err}") from err
    try:
        info = _describe(md, names)
    except (AttributeError, KeyError, TypeError, ValueError) as err:
        raise FmuError(f"cannot read the modelDescription.xml of {path.name}: {err}") from err
    if not info.interfaces:
        raise FmuError(f"{path.name} implements neither co-simulation nor model exchange")
    if require_binary and not info.has_binary:
        found = sorted({n.split("/")[1] for n in names if n.startswith("binaries/") and n[9:]})
        raise FmuError(
            f"{path.name} has no binary for this platform ({info.platform}); "
            f"it has binaries for: {', '.join(found) or 'none'}"
        )
    return info


def check_archive(path: Path, max_unpacked: int) -> set[str]:
    """The file names in the FMU archive, after checking its size and paths (nothing extracted)."""
    try:
        with zipfile.ZipFile(path) as zf:
            infos = zf.infolist()
    except FileNotFoundError as err:
        raise FmuError(f"no FMU file {path.name}") from err
    except (zipfile.BadZipFile, OSError, ValueError, EOFError) as err:
        raise FmuError(f"{path.name} is not an FMU: it is not a ZIP archive ({err})") from err
    total = 0
    for info in infos:
        name = info.filename
        parts = PurePosixPath(name).parts
        if name.startswith("/") or "\\" in name or ":" in name or ".." in parts:
            raise FmuError(f"{path.name} is refused: the archive path {name!r} is not allowed")
        total += info.file_size
    if total > max_unpacked:
        raise FmuError(
            f"{path.name} is refused: it unpacks to {total} bytes, more than {max_unpacked}"
        )
    names = {i.filename for i in infos}
    if "modelDescription.xml" not in names:
        raise FmuError(f"{path.name} is not an FMU: it has no modelDescription.xml")
    return names


def _check_version(path: Path) -> None:
    """Refuse what FMPy would explain badly: no XML, no fmiVersion, FMI 1.0."""
    try:
        with zipfile.ZipFile(path) as zf, zf.open("modelDescription.xml") as xml:
            events = etree.iterparse(xml, events=("start", "end"))
            version = next(events)[1].get("fmiVersion")
            for _, element in events:  # the rest only needs to be well-formed
                element.clear()
    except Exception as err:  # lxml, zlib, zipfile (encrypted, unknown compression...) errors
        raise FmuError(f"{path.name}: cannot read modelDescription.xml: {err}") from err
    if version is None:
        raise FmuError(f"{path.name}: modelDescription.xml has no fmiVersion")
    if not version.startswith(("2.", "3.")):
        raise FmuError(f"{path.name} is an FMI {version} FMU; only FMI 2.0 and 3.0 are supported")


def _describe(md: Any, names: set[str]) -> FmuInfo:
    fmi3 = str(md.fmiVersion).startswith("3.")
    platform = str(fmpy.platform_tuple if fmi3 else fmpy.platform)
    interfaces = []
    kinds: tuple[tuple[Kind, Any], ...] = (
        ("CoSimulation", md.coSimulation),
        ("ModelExchange", md.modelExchange),
    )
    for kind, spec in kinds:
        if spec is None or not spec.modelIdentifier:
            continue
        library = f"binaries/{platform}/{spec.modelIdentifier}{fmpy.sharedLibraryExtension}"
        interfaces.append(
            FmuInterface(
                kind=kind,
                model_identifier=str(spec.modelIdentifier),
                has_binary=library in names,
                needs_completed_integrator_step=bool(
                    getattr(spec, "needsCompletedIntegratorStep", False)
                )
                and not bool(getattr(spec, "completedIntegratorStepNotNeeded", False)),
                can_handle_variable_step=kind == "ModelExchange"
                or bool(getattr(spec, "canHandleVariableCommunicationStepSize", False)),
            )
        )
    de = md.defaultExperiment
    return FmuInfo(
        fmi_version="3.0" if fmi3 else "2.0",
        model_name=str(md.modelName),
        guid=str(md.guid),
        description=md.description,
        generation_tool=md.generationTool,
        platform=platform,
        interfaces=tuple(interfaces),
        default_experiment=DefaultExperiment(
            start=_float(getattr(de, "startTime", None)),
            stop=_float(getattr(de, "stopTime", None)),
            step=_float(getattr(de, "stepSize", None)),
            tolerance=_float(getattr(de, "tolerance", None)),
        ),
        number_of_continuous_states=int(md.numberOfContinuousStates),
        number_of_event_indicators=int(md.numberOfEventIndicators),
        variables=tuple(_variable(v) for v in md.modelVariables),
    )


def _variable(v: Any) -> FmuVariable:
    declared = v.declaredType
    shape = tuple(int(n) for n in (v.shape or ()))
    return FmuVariable(
        name=str(v.name),
        value_reference=int(v.valueReference),
        causality=str(v.causality),
        variability=str(v.variability),
        type=str(v.type),
        initial=v.initial,
        unit=v.unit or (declared.unit if declared is not None else None),
        start=_start(str(v.type), v.start) if not shape else v.start,
        min=_float(v.min if v.min is not None else getattr(declared, "min", None)),
        max=_float(v.max if v.max is not None else getattr(declared, "max", None)),
        description=v.description,
        shape=shape,
        items=tuple((str(i.name), int(i.value)) for i in getattr(declared, "items", None) or ()),
    )


def _float(text: str | float | None) -> float | None:
    """A finite float, or None (JSON has no NaN or infinity)."""
    if text is None:
        return None
    value = float(text)
    return value if math.isfinite(value) else None


def _start(type_: str, text: str | None) -> Scalar | None:
    if text is None:
        return None
    if type_ in FLOAT_TYPES:
        return _float(text)
    if type_ in INT_TYPES:
        return int(text)
    if type_ == "Boolean":
        return text.strip().lower() in {"true", "1"}
    return str(text)
