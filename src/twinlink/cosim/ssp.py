"""An SSP archive (System Structure and Parameterization 1.0, a `.ssp` zip) read into a
System, and its files unpacked safely.

Read: SystemStructure.ssd's ssd:System with its ssd:Elements/ssd:Component (`source` the
FMU inside the archive, "resources/x.fmu"), ssd:Connections, ssd:ParameterBindings (inline
ssv:ParameterSet or an .ssv file of the archive; ssv:Real, Integer, Boolean, String and
Enumeration values) on the components and on the system (names "component.variable" there),
and ssd:DefaultExperiment's startTime and stopTime.

A connection through one of the system's own connectors (a component's output to the
system's connector, the connector to other components' inputs) is joined into direct
connections; a system input nothing feeds is refused, as its value would come from outside
the file; a system output nothing reads only shows a value, and is dropped. Nested systems,
parameter mappings and connection transformations are refused with a message saying so. SSP has no
step size: `step_size` gives it, or a 500th of the experiment (FMPy's output interval).

The XML is parsed with a DTD or an entity declaration refused (billion laughs, external
entities), as defusedxml does, with the standard library's expat (defusedxml is not one of
twinlink's dependencies).

FMUs stay inside the archive: Instance.fmu is their path there, and `extract`
unpacks the archive into a folder, refusing any member that would land outside it.
"""

from __future__ import annotations

import math
import zipfile
from collections.abc import Iterable
from pathlib import Path, PurePosixPath
from typing import NoReturn
from xml.etree.ElementTree import Element, TreeBuilder
from xml.parsers import expat

from twinlink.cosim.model import Algorithm, Connection, CosimFormatError, Instance, Port, System

SSD = "{http://ssp-standard.org/SSP1/SystemStructureDescription}"
SSV = "{http://ssp-standard.org/SSP1/SystemStructureParameterValues}"
SSD_NAME = "SystemStructure.ssd"
# An archive's unpacked size is bounded: a zip bomb fills no disk.
MAX_UNPACKED_BYTES = 2 * 1024**3
DEFAULT_STEPS = 500

Scalar = float | int | bool | str


def _member(name: str, where: str) -> str:
    """`name` as a path inside the archive, refused if it could leave it."""
    path = PurePosixPath(name.replace("\\", "/"))
    if path.is_absolute() or ".." in path.parts or ":" in name.split("/")[0]:
        raise CosimFormatError(f"{where}: {name!r} is not a path inside the archive")
    return str(path)


class _Refused(Exception):
    """A DTD or an entity met while parsing (control flow inside this module, answered as a
    CosimFormatError naming the file)."""


def _refuse(*_args: object) -> NoReturn:
    raise _Refused


def _name(raw: str) -> str:
    # expat writes "namespace}local" with "}" as the separator; ElementTree's "{ns}local"
    return "{" + raw if "}" in raw else raw


def parse_xml(text: bytes) -> Element:
    """`text` parsed into an Element tree, refusing any DOCTYPE or entity declaration."""
    builder = TreeBuilder()
    parser = expat.ParserCreate(namespace_separator="}")
    parser.StartDoctypeDeclHandler = _refuse
    parser.EntityDeclHandler = _refuse
    parser.ExternalEntityRefHandler = _refuse
    parser.StartElementHandler = lambda tag, attrs: builder.start(
        _name(tag), {_name(k): v for k, v in attrs.items()}
    )
    parser.EndElementHandler = lambda tag: builder.end(_name(tag))
    parser.CharacterDataHandler = builder.data
    parser.Parse(text, True)
    root: Element = builder.close()
    return root


def _xml(archive: zipfile.ZipFile, name: str, where: str) -> Element:
    try:
        text = archive.read(name)
    except KeyError:
        raise CosimFormatError(f"{where}: the archive has no {name}") from None
    try:
        return parse_xml(text)
    except _Refused:
        raise CosimFormatError(
            f"{where}: {name} declares a DTD or an entity, refused for safety"
        ) from None
    except expat.ExpatError as err:
        raise CosimFormatError(
            f"{where}: {name} is not well-formed XML: {expat.ErrorString(err.code)} "
            f"at line {err.lineno}, column {err.offset + 1}"
        ) from None


def read_ssp(path: Path | str, step_size: float | None = None) -> System:
    """The System of the SSP archive at `path`; `step_size` the master's fixed step."""
    path = Path(path)
    try:
        archive = zipfile.ZipFile(path)
    except (OSError, zipfile.BadZipFile) as err:
        raise CosimFormatError(f"{path}: is not an SSP archive (a zip file): {err}") from err
    with archive:
        root = _xml(archive, SSD_NAME, str(path))
        return _Reader(archive, str(path)).system(root, step_size)


class _Reader:
    def __init__(self, archive: zipfile.ZipFile, name: str) -> None:
        self.archive = archive
        self.name = name
        self.members = set(archive.namelist())
        self.names: list[str] = []

    def fail(self, where: str, problem: str) -> CosimFormatError:
        return CosimFormatError(f"{self.name}: {SSD_NAME}: {where}: {problem}")

    def system(self, root: Element, step_size: float | None) -> System:
        if root.tag != f"{SSD}SystemStructureDescription":
            raise self.fail(root.tag, "is not an ssd:SystemStructureDescription")
        system = root.find(f"{SSD}System")
        if system is None:
            raise self.fail("ssd:SystemStructureDescription", "has no ssd:System")
        instances = self._components(system)
        self.names = [i.name for i in instances]
        parameters: dict[Port, Scalar] = {}
        for comp in system.iterfind(f"{SSD}Elements/{SSD}Component"):
            self._bindings(comp, comp.get("name", ""), parameters)
        self._bindings(system, None, parameters)
        start, end = self._experiment(root)
        if step_size is None:
            step_size = (end - start) / DEFAULT_STEPS if end is not None else 1e-3
        if not (math.isfinite(step_size) and step_size > 0):
            raise CosimFormatError(f"{self.name}: step size {step_size} is not above 0")
        return System(
            instances=instances,
            connections=self._connections(system, {i.name for i in instances}),
            parameters=parameters,
            log_variables={},
            algorithm=Algorithm("fixed-step", step_size),
            start_time=start,
            end_time=end,
            source="ssp",
        )

    def _components(self, system: Element) -> tuple[Instance, ...]:
        elements = system.find(f"{SSD}Elements")
        if elements is not None and elements.find(f"{SSD}System") is not None:
            raise self.fail("ssd:Elements", "holds a nested ssd:System, not supported yet")
        out: list[Instance] = []
        for comp in system.iterfind(f"{SSD}Elements/{SSD}Component"):
            name, source = comp.get("name"), comp.get("source")
            where = f"ssd:Component {name!r}"
            if not name or not source:
                raise self.fail(where, "needs a name and a source")
            kind = comp.get("type", "application/x-fmu-sharedlibrary")
            if kind != "application/x-fmu-sharedlibrary":
                raise self.fail(where, f"type {kind!r} is not an FMU")
            member = _member(source, f"{self.name}: {where}")
            if member not in self.members:
                raise self.fail(where, f"its source {source} is not in the archive")
            if any(i.name == name for i in out):
                raise self.fail(where, "is named twice")
            out.append(Instance(name=name, fmu=member))
        if not out:
            raise self.fail("ssd:Elements", "has no ssd:Component")
        return tuple(out)

    def _connections(self, system: Element, names: set[str]) -> tuple[Connection, ...]:
        direct: list[Connection] = []
        into: dict[str, list[Port]] = {}  # a system connector -> the outputs feeding it
        out_of: dict[str, list[Port]] = {}  # a system connector -> the inputs it feeds
        for conn in system.iterfind(f"{SSD}Connections/{SSD}Connection"):
            if (
                conn.find(f"{SSD}LinearTransformation") is not None
                or conn.find(f"{SSD}MappingTransformation") is not None
            ):
                raise self.fail("ssd:Connection", "transformations are not supported yet")
            start, start_c = conn.get("startElement"), conn.get("startConnector")
            end, end_c = conn.get("endElement"), conn.get("endConnector")
            where = f"ssd:Connection {start or ''}.{start_c} -> {end or ''}.{end_c}"
            if not start_c or not end_c:
                raise self.fail(where, "needs startConnector and endConnector")
            for element in (start, end):
                if element is not None and element not in names:
                    raise self.fail(where, f"{element!r} is not a component of the system")
            if start is not None and end is not None:
                direct.append(Connection(Port(start, start_c), Port(end, end_c)))
            elif start is not None:
                into.setdefault(end_c, []).append(Port(start, start_c))
            elif end is not None:
                out_of.setdefault(start_c, []).append(Port(end, end_c))
            else:
                raise self.fail(where, "joins two of the system's own connectors")
        for connector, inputs in out_of.items():
            sources = into.get(connector, [])
            if len(sources) != 1:
                problem = "nothing in the system feeds it" if not sources else "several feed it"
                raise self.fail(
                    f"the system connector {connector!r}",
                    f"{problem}; connect the inputs it feeds to a component's output",
                )
            direct.extend(Connection(sources[0], target) for target in inputs)
        return tuple(direct)

    def _bindings(self, owner: Element, component: str | None, out: dict[Port, Scalar]) -> None:
        for binding in owner.iterfind(f"{SSD}ParameterBindings/{SSD}ParameterBinding"):
            where = f"ssd:ParameterBinding of {component or 'the system'}"
            if binding.find(f"{SSD}ParameterMapping") is not None:
                raise self.fail(where, "ssd:ParameterMapping is not supported yet")
            source = binding.get("source")
            if source is not None:
                member = _member(source, f"{self.name}: {where}")
                values = _xml(self.archive, member, f"{self.name}: {where}")
            else:
                inline = binding.find(f"{SSD}ParameterValues/{SSV}ParameterSet")
                if inline is None:
                    raise self.fail(where, "has neither a source nor ssd:ParameterValues")
                values = inline
            prefix = binding.get("prefix", "")
            for name, value in _parameters(values, f"{self.name}: {where}"):
                # the standard: the prefix is prepended to the set's names ("msd2." puts
                # a component's set at the system level)
                out[self._port(prefix + name, component, where)] = value

    def _port(self, name: str, component: str | None, where: str) -> Port:
        if component is not None:
            return Port(component, name)
        # on the system: "component.variable", the component's name possibly holding dots
        for comp in sorted(self.names, key=len, reverse=True):
            if name.startswith(comp + "."):
                return Port(comp, name[len(comp) + 1 :])
        raise self.fail(where, f"the parameter {name!r} names no component's variable")

    def _experiment(self, root: Element) -> tuple[float, float | None]:
        exp = root.find(f"{SSD}DefaultExperiment")
        if exp is None:
            return 0.0, None
        start = self._float(exp.get("startTime", "0"), "ssd:DefaultExperiment startTime")
        stop = exp.get("stopTime")
        end = None if stop is None else self._float(stop, "ssd:DefaultExperiment stopTime")
        if end is not None and end <= start:
            raise self.fail("ssd:DefaultExperiment", f"stopTime {end} is not after {start}")
        return start, end

    def _float(self, text: str, where: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise self.fail(where, f"{text!r} is not a number") from None
        if not math.isfinite(value):
            raise self.fail(where, f"{text!r} is not a finite number")
        return value


def _parameters(root: Element, where: str) -> Iterable[tuple[str, Scalar]]:
    """The (name, value) pairs of an ssv:ParameterSet."""
    if root.tag != f"{SSV}ParameterSet":
        raise CosimFormatError(f"{where}: {root.tag} is not an ssv:ParameterSet")
    for param in root.iterfind(f"{SSV}Parameters/{SSV}Parameter"):
        name = param.get("name")
        if not name or len(param) != 1:
            raise CosimFormatError(f"{where}: an ssv:Parameter needs a name and one value")
        yield name, _value(param[0], f"{where}: ssv:Parameter {name!r}")


def _value(elem: Element, where: str) -> Scalar:
    kind = elem.tag.removeprefix(SSV)
    text = elem.get("value")
    if text is None:
        raise CosimFormatError(f"{where}: ssv:{kind} has no value")
    try:
        if kind in ("Real", "Float64", "Float32"):
            value = float(text)
            if not math.isfinite(value):
                raise ValueError(text)
            return value
        if kind in ("Integer", "Int8", "Int16", "Int32", "Int64"):
            return int(text)
        if kind in ("UInt8", "UInt16", "UInt32", "UInt64"):
            return int(text)
        if kind == "Boolean":
            if text not in ("true", "false", "1", "0"):
                raise ValueError(text)
            return text in ("true", "1")
        if kind in ("String", "Enumeration"):
            return text
    except ValueError:
        raise CosimFormatError(f"{where}: {text!r} is not an ssv:{kind} value") from None
    raise CosimFormatError(f"{where}: ssv:{kind} values are not supported")


def extract(path: Path | str, dest: Path | str) -> list[Path]:
    """Unpack the archive at `path` into `dest`; the files written. A member that would land
    outside `dest` (an absolute path, "..", a drive), a link, or an archive unpacking past
    MAX_UNPACKED_BYTES is refused before anything is written."""
    dest = Path(dest).resolve()
    try:
        archive = zipfile.ZipFile(path)
    except (OSError, zipfile.BadZipFile) as err:
        raise CosimFormatError(f"{path}: is not an SSP archive (a zip file): {err}") from err
    with archive:
        infos = archive.infolist()
        total = 0
        plan: list[tuple[zipfile.ZipInfo, Path]] = []
        for info in infos:
            member = _member(info.filename, f"{path}")
            target = (dest / member).resolve()
            if not target.is_relative_to(dest):
                raise CosimFormatError(f"{path}: {info.filename!r} would land outside {dest}")
            if (info.external_attr >> 16) & 0o170000 == 0o120000:
                raise CosimFormatError(f"{path}: {info.filename!r} is a link, refused")
            total += info.file_size
            if total > MAX_UNPACKED_BYTES:
                raise CosimFormatError(
                    f"{path}: unpacks to over {MAX_UNPACKED_BYTES} bytes, refused"
                )
            plan.append((info, target))
        written: list[Path] = []
        for info, target in plan:
            if info.is_dir():
                target.mkdir(parents=True, exist_ok=True)
                continue
            target.parent.mkdir(parents=True, exist_ok=True)
            with archive.open(info) as src, target.open("wb") as out:
                while chunk := src.read(1 << 20):
                    out.write(chunk)
            written.append(target)
        return written
