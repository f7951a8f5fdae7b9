"""The rules a processor's settings must follow before it is stored or run."""

from __future__ import annotations

from typing import Any

from pydantic import ValidationError

from twinlink.domain.errors import ConflictError, InvalidInputError
from twinlink.domain.records import ProcessorRecord
from twinlink.processors.blueprint import BlueprintError
from twinlink.processors.catalog import Entry
from twinlink.processors.fmurules import enumeration_value
from twinlink.processors.libref import LibraryFmus, check_variables, checkable, lib_ref
from twinlink.processors.spec import ProcessorSpec
from twinlink.store.base import MetadataStore

FMU_BLUEPRINT = "fmu"


def checked_spec(body: dict[str, Any], catalog: dict[str, Entry]) -> ProcessorSpec:
    """The processor `body` describes; InvalidInputError says what is wrong with it."""
    try:
        spec = ProcessorSpec.model_validate(body)
    except ValidationError as err:
        raise InvalidInputError(first_errors(err)) from err
    entry = catalog.get(spec.blueprint)
    if entry is None:
        raise InvalidInputError(f"no blueprint {spec.blueprint!r}; see /api/v1/blueprints")
    if entry.cls is None:
        raise InvalidInputError(f"blueprint {spec.blueprint!r} is broken: {entry.error}")
    try:
        entry.cls.check(entry.cls.Params.model_validate(checkable(spec.params)))
    except ValidationError as err:
        raise InvalidInputError("params: " + first_errors(err)) from err
    except BlueprintError as err:
        raise InvalidInputError(f"params: {err}") from err
    if spec.output_stream == spec.source:
        raise InvalidInputError("a processor cannot write the stream it reads")
    return spec


async def check_fmu(
    spec: ProcessorSpec,
    twin_id: int,
    slug: str,
    store: MetadataStore,
    lib: LibraryFmus,
    catalog: dict[str, Entry] | None = None,
) -> None:
    """Refuse an `fmu` processor its FMU cannot run (422 naming the variable and why), from
    the description kept at upload or library push, so it is not made to crash-loop later.
    Enumeration parameters given by item name are stored as the item's value. Another
    blueprint's uploaded FMUs (Blueprint.uploads) must be there, with the variables named,
    when it is to run: a stopped processor can always be changed and stopped."""
    if catalog is not None and spec.enabled and spec.blueprint != FMU_BLUEPRINT:
        await check_uploads(spec, catalog, twin_id, slug, store)
    if spec.blueprint != FMU_BLUEPRINT or not isinstance(spec.params.get("fmu"), str):
        return
    name = spec.params["fmu"]
    if lib_ref(spec.params) is not None:
        info, where = await lib.described(name)
    else:
        record = next((f for f in await store.list_fmus(twin_id) if f.name == name), None)
        if record is None:
            raise InvalidInputError(
                f"params.fmu: twin {slug!r} has no FMU {name!r}; upload it first "
                f"(PUT /api/v1/twins/{slug}/fmus/{name})"
            )
        info, where = record.info, name
    check_variables(spec.params, info, where, list(spec.inputs))
    parameters = spec.params.get("parameters")
    if parameters:
        by_name = {v.get("name"): v for v in info.get("variables", [])}
        for key, value in parameters.items():
            if by_name[key].get("type") == "Enumeration":
                parameters[key] = enumeration_value(by_name[key], value)


def uploads_of(
    catalog: dict[str, Entry], blueprint: str, params: dict[str, Any]
) -> dict[str, dict[str, str]]:
    """The uploaded FMUs a processor of `blueprint` with `params` uses (Blueprint.uploads),
    with the variables it names in each; {} for params its blueprint refuses."""
    entry = catalog.get(blueprint)
    cls = entry.cls if entry is not None else None
    if cls is None:
        return {}
    try:
        return cls.uploads(cls.Params.model_validate(params))
    except (ValidationError, BlueprintError):  # checked_spec refuses these
        return {}


async def check_uploads(
    spec: ProcessorSpec, catalog: dict[str, Entry], twin_id: int, slug: str, store: MetadataStore
) -> None:
    """Refuse a processor naming an FMU the twin has not uploaded, or a variable that FMU
    does not have (from the description kept at upload), naming the parameter."""
    wanted = uploads_of(catalog, spec.blueprint, spec.params)
    records = {f.name: f for f in await store.list_fmus(twin_id)} if wanted else {}
    for name, variables in wanted.items():
        record = records.get(name)
        if record is None:
            raise InvalidInputError(
                f"params: twin {slug!r} has no FMU {name!r}; upload it first "
                f"(PUT /api/v1/twins/{slug}/fmus/{name})"
            )
        known = {v.get("name") for v in record.info.get("variables", [])}
        for variable, key in variables.items():
            if variable not in known:
                raise InvalidInputError(f"params: {key}: {name} has no variable {variable!r}")


def spec_of(record: ProcessorRecord) -> ProcessorSpec:
    return ProcessorSpec.model_validate(
        {
            **record.spec,
            "name": record.name,
            "blueprint": record.blueprint,
            "enabled": record.enabled,
        }
    )


def check_chain(spec: ProcessorSpec, others: list[ProcessorRecord]) -> None:
    """Refuse a processor whose output would come back to its own input through others."""
    edges: dict[str, set[str]] = {}
    for record in others:
        other = spec_of(record)
        edges.setdefault(other.source, set()).add(other.output_stream)
        if other.output_stream == spec.output_stream:
            raise ConflictError(f"processor {record.name!r} already writes {spec.output_stream!r}")
    edges.setdefault(spec.source, set()).add(spec.output_stream)
    seen, todo = set(), [spec.output_stream]
    while todo:
        stream = todo.pop()
        if stream == spec.source:
            raise InvalidInputError(
                f"{spec.source!r} -> {spec.output_stream!r} would make a loop of processors"
            )
        if stream not in seen:
            seen.add(stream)
            todo.extend(edges.get(stream, ()))


def first_errors(err: ValidationError) -> str:
    return "; ".join(
        f"{'.'.join(str(p) for p in e['loc']) or 'body'}: {e['msg']}" for e in err.errors()[:5]
    )
