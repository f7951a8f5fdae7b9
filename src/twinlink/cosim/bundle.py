"""A received co-simulation made ready to run: its System read, each FMU it names resolved to a
file in its folder, every FMU inspected, and the view of the whole kept for the API.

An FMU reference resolves, in this order: `lib:...` to the library (resolved with the
caller's rights, pinned, its file linked into the folder); a path inside the uploaded folder;
a plain file name to an FMU uploaded to the co-simulation's twin (linked in as it is now, so
a later upload of that name changes no co-simulation made before). Files are hard links when
the file system allows, copies otherwise.

Errors name the document and the key (never the server's folders): a reference that
resolves nowhere, an FMU that is no usable FMU, a port naming a variable its FMU lacks.
"""

from __future__ import annotations

import asyncio
import difflib
import json
import os
import shutil
from collections.abc import Awaitable, Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import fmpy  # type: ignore[import-untyped]
import orjson

from twinlink.auth.rights import Principal
from twinlink.domain.errors import InvalidInputError, NotFoundError
from twinlink.domain.records import FmuRecord
from twinlink.library.service import LibraryService
from twinlink.processors.fmuinfo import FmuError, FmuInfo, inspect_fmu

from .graph import algebraic_loops, feedthrough_of
from .kinds import kind_of
from .maestro import _merge as merge_maestro
from .maestro import read_maestro
from .model import CosimFormatError, Instance, Port, System
from .ssp import read_ssp
from .upload import FILES, Received
from .yamlform import read_yaml

LIB = "lib:"
FMUS = "fmus"  # the linked FMUs' folder, in the co-simulation's folder


@dataclass(slots=True)
class Bundle:
    system: System
    fmus: dict[str, dict[str, str]]  # ref -> {"path": in the folder, "source": where from}
    view: dict[str, Any] = field(default_factory=dict)

    def paths(self, folder: Path) -> dict[str, Path]:
        return {ref: folder / fmu["path"] for ref, fmu in self.fmus.items()}


@dataclass(slots=True)
class Sources:
    """Where FMU references may resolve, for one caller: the library (if there is one), the
    uploaded FMUs of the co-simulation's twin (`twin_fmus`: its records and its folder)."""

    principal: Principal
    library: LibraryService | None
    twin: str | None = None
    twin_fmus: Callable[[], Awaitable[tuple[list[FmuRecord], Path]]] | None = None


def shown(text: str, folder: Path) -> str:
    """`text` without the server's folders: paths as the uploaded folder names them."""
    for prefix in (folder / FILES, folder):
        text = text.replace(f"{prefix}/", "").replace(str(prefix), ".")
    return text


def merge_settings(folder: Path, received: Received) -> Received:
    """A multi-model with a settings file of its own (coe.json) written as one, beside it (so
    its FMU paths stay as they are): the run reads one document (in a thread)."""
    if received.settings is None:
        return received
    path = folder / received.document
    model = json.loads(path.read_text(encoding="utf-8"))
    settings = json.loads((folder / received.settings).read_text(encoding="utf-8"))
    merged = path.with_name(f".{path.stem}.merged.json")
    merged.write_bytes(orjson.dumps(merge_maestro(model, settings)))
    return Received(merged.relative_to(folder).as_posix(), "maestro")


def read_system(folder: Path, received: Received) -> System:
    """The System of the received document (in a thread: it reads files)."""
    path = folder / received.document
    try:
        if received.format == "ssp":
            return read_ssp(path)
        if received.format == "yaml":
            return read_yaml(path)
        settings = folder / received.settings if received.settings else None
        return read_maestro(path, settings=settings)
    except CosimFormatError as err:
        raise CosimFormatError(shown(str(err), folder)) from None


async def resolve(folder: Path, received: Received, system: System, sources: Sources) -> Bundle:
    """Each FMU the system names as a file of the folder (linked in when it is not one of the
    upload's own); InvalidInputError naming the instance when one resolves nowhere."""
    base = folder / FILES if received.format == "ssp" else (folder / received.document).parent
    document = shown(str(folder / received.document), folder)
    fmus: dict[str, dict[str, str]] = {}
    for instance in system.instances:
        if instance.fmu not in fmus:
            where = f"{document}: instance {instance.name!r}: fmu {instance.fmu!r}"
            fmus[instance.fmu] = await _resolve_one(folder, base, instance.fmu, sources, where)
    return Bundle(system, fmus)


async def _resolve_one(
    folder: Path, base: Path, ref: str, sources: Sources, where: str
) -> dict[str, str]:
    links = folder / FMUS
    if ref.startswith(LIB):
        if sources.library is None:
            raise InvalidInputError(f"{where}: this server has no asset library")
        try:
            resolved = await sources.library.resolve(sources.principal, ref, kind="models")
            local = await sources.library.file_path(resolved)
        except NotFoundError as err:
            raise InvalidInputError(f"{where}: {err}") from err
        except InvalidInputError as err:
            raise InvalidInputError(f"{where}: {err}") from err
        name = f"lib-{len(list(links.glob('lib-*')))}-{Path(resolved.path or 'x.fmu').name}"
        await asyncio.to_thread(_link, local, links / name)
        return {"path": f"{FMUS}/{name}", "source": resolved.pinned}
    files = (folder / FILES).resolve()
    candidate = (base / ref).resolve()
    if candidate.is_relative_to(files) and candidate.is_file():
        return {"path": candidate.relative_to(folder.resolve()).as_posix(), "source": "upload"}
    if "/" not in ref and sources.twin_fmus is not None:
        records, twin_folder = await sources.twin_fmus()
        if any(r.name == ref for r in records):
            await asyncio.to_thread(_link, twin_folder / ref, links / f"twin-{ref}")
            return {"path": f"{FMUS}/twin-{ref}", "source": f"twin:{sources.twin}"}
        raise InvalidInputError(
            f"{where}: not in the uploaded files, nor an FMU uploaded to twin "
            f"{sources.twin!r} (upload it there, send it in a zip or tar with the document, "
            "or name a library model: lib:models/NAME#file.fmu)"
        )
    raise InvalidInputError(
        f"{where}: not in the uploaded files; send the FMUs with the document (a zip or tar "
        "of the folder), name a library model (lib:models/NAME#file.fmu), or give ?twin= "
        "and a file name of an FMU uploaded to that twin"
    )


def _link(source: Path, target: Path) -> None:
    target.parent.mkdir(parents=True, exist_ok=True)
    try:
        os.link(source, target)
    except OSError:  # another file system, or links refused: a copy
        shutil.copyfile(source, target)


# -- inspection and the view -------------------------------------------------------------------


def inspect(bundle: Bundle, folder: Path, document: str) -> None:
    """Inspect every FMU (in a thread: FMPy reads them), check the ports the system names
    exist, and make the view (`bundle.view`)."""
    system = bundle.system
    infos: dict[str, FmuInfo] = {}
    feedthrough: dict[str, dict[str, set[str]]] = {}
    paths = {ref: folder / fmu["path"] for ref, fmu in bundle.fmus.items()}
    for ref, path in paths.items():
        try:
            infos[ref] = inspect_fmu(path)
            feedthrough[ref] = feedthrough_of(fmpy.read_model_description(str(path)))
        except FmuError as err:
            raise InvalidInputError(f"{document}: fmu {ref!r}: {shown(str(err), folder)}") from err
    by_instance = {i.name: i for i in system.instances}
    _check_ports(system, by_instance, infos, document)
    loops = algebraic_loops(system, lambda name: feedthrough.get(by_instance[name].fmu))
    kinds: dict[str, str] = {i.name: kind_of(infos[i.fmu], paths[i.fmu]) for i in system.instances}
    bundle.view = view_of(system, kinds, loops)


def _check_ports(
    system: System, instances: dict[str, Instance], infos: dict[str, FmuInfo], document: str
) -> None:
    def check(port: Port, key: str) -> None:
        instance = instances.get(port.instance)
        if instance is None or "[" in port.variable:  # arrays: the FMU's own check
            return
        info = infos[instance.fmu]
        if info.variable(port.variable) is None:
            names = [v.name for v in info.variables]
            close = difflib.get_close_matches(port.variable, names, n=3, cutoff=0.5)
            hint = f" (did you mean {', '.join(close)}?)" if close else ""
            raise InvalidInputError(
                f"{document}: {key}: {port}: the FMU {instance.fmu!r} has no variable "
                f"{port.variable!r}{hint}"
            )

    for conn in system.connections:
        check(conn.source, "connections")
        check(conn.target, "connections")
    for port in system.parameters:
        check(port, "parameters")
    for name, variables in system.log_variables.items():
        for variable in variables:
            check(Port(name, variable), "log variables")


def _instance(instance: Instance, kind: str) -> dict[str, Any]:
    return {"name": instance.name, "fmu": instance.fmu, "kind": kind, "isolated": instance.isolated}


def view_of(system: System, kinds: dict[str, str], loops: list[list[Port]]) -> dict[str, Any]:
    algorithm = system.algorithm
    return {
        "source": system.source,
        "instances": [_instance(i, kinds.get(i.name, "co-simulation")) for i in system.instances],
        "connections": [
            {"source": str(c.source), "target": str(c.target)} for c in system.connections
        ],
        "algorithm": {
            "kind": algorithm.kind,
            "size": algorithm.size,
            "min_size": algorithm.min_size,
            "max_size": algorithm.max_size,
            "master": algorithm.master,
        },
        "start_time": system.start_time,
        "end_time": system.end_time,
        "loops": [[str(p) for p in loop] for loop in loops],
    }
