"""The DT document: the Aalto dt-document fields, Twinbase's, and our `interface` section.

Validation checks types and rules; the document itself stays the plain mapping it was read
as, so keys we do not know are kept and come back in their order on output. Other parts of the
platform read that mapping (ingest compares values with an interface's `min`), so a value
is accepted only in the type it will be used as: `min: "5"` is refused, not read as 5.

A Twinbase document is one with `dt-id` and no `version`: Twinbase publishes documents
without one, and its format is defined by its fields, which this model reads as they are.
"""

from __future__ import annotations

import math
import re
from typing import Annotated, Any, Literal

from pydantic import (
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    ValidationError,
    field_validator,
    model_validator,
)

from twinlink.domain.doctime import TimeRangeError, human_ns, machine_ns
from twinlink.domain.errors import DocumentError, Problem
from twinlink.domain.jsontext import fits_int64, int64_problem
from twinlink.domain.yamlsource import MAX_DEPTH, Path, SourceDocument

SUPPORTED_VERSION = re.compile(r"^(0|1)(\.\d+){0,2}$")
PRIVACY_LEVEL = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.:-]{0,63}$")
PLATFORM_KEYS = ("createdMachine", "createdHuman", "modifiedMachine", "modifiedHuman")
# Twinbase's template says `dt-id: autoassign|https://dtid.org` and `hosting-iri: autoassign`:
# values its publishing workflow fills in (the id under that base, the page's address).
AUTOASSIGN = "autoassign"


def is_placeholder(value: Any) -> bool:
    """Twinbase's `autoassign` (or `autoassign|BASE`), a value still to be filled in."""
    return isinstance(value, str) and value.split("|", 1)[0].strip() == AUTOASSIGN


def _number_to_text(value: Any) -> Any:
    # YAML reads `version: 1.0` as a float; the spec means the string "1.0".
    if isinstance(value, int | float) and not isinstance(value, bool):
        return str(value)
    return value


def _privacy(value: Any) -> Any:
    # "Public" and "PRIVATE" mean the fixed levels; group names keep their spelling.
    if isinstance(value, str) and value.lower() in ("public", "private"):
        return value.lower()
    return value


def _one_to_list(value: Any) -> Any:
    return [value] if isinstance(value, str) else value


Text = Annotated[str, BeforeValidator(_number_to_text)]
# A JSON number (an integer or a finite float), never a bool or a number written as text.
Number = Annotated[float, Field(strict=True, allow_inf_nan=False)]
Flag = Annotated[bool, Field(strict=True)]


class _Open(BaseModel):
    """Unknown keys are allowed everywhere: the spec lets any key-value pair be added."""

    model_config = ConfigDict(extra="allow", populate_by_name=True, strict=False)


class Party(_Open):
    name: Text | None = None
    email: Text | None = None
    website: Text | None = None


class Location(_Open):
    streetAddress: Text | None = None
    gpsCoordinates: Text | None = None


class Relation(_Open):
    relationType: Literal["parent", "child", "sibling"]
    id: Text | None = None
    dt_id: Text | None = Field(None, alias="dt-id")

    @model_validator(mode="after")
    def _has_target(self) -> Relation:
        if not (self.id or self.dt_id):
            raise ValueError("a relation needs the other twin's `id` (or `dt-id`)")
        return self

    @property
    def target(self) -> str:
        return str(self.id or self.dt_id)


class Feature(_Open):
    name: Text = Field(min_length=1)
    description: Text | None = None
    address: Text | None = None
    apiAddress: Text | None = None
    requirement: Text | None = None
    documentation: Text | None = None
    keywords: Annotated[list[Text], BeforeValidator(_one_to_list)] = Field(default_factory=list)


SignalType = Literal["number", "integer", "bool", "string"]


class Signal(_Open):
    name: Text = Field(min_length=1)
    unit: Text | None = None
    type: SignalType = "number"
    min: Number | None = None
    max: Number | None = None
    description: Text | None = None

    @model_validator(mode="after")
    def _range(self) -> Signal:
        if self.min is not None and self.max is not None and self.min > self.max:
            raise ValueError(f"min ({self.min}) is greater than max ({self.max})")
        return self


class Property(Signal):
    writable: Flag = False


class Parameter(Signal):
    required: Flag = False
    default: Any = None


class Command(_Open):
    name: Text = Field(min_length=1)
    description: Text | None = None
    parameters: list[Parameter] = Field(default_factory=list)


class Interface(_Open):
    signals: list[Signal] = Field(default_factory=list)
    properties: list[Property] = Field(default_factory=list)
    commands: list[Command] = Field(default_factory=list)
    # What ingest does with values the signals above do not describe (docs/protocol.md).
    unknown_signals: Literal["accept", "drop", "reject"] = "accept"
    out_of_range: Literal["accept", "reject"] = "reject"


class DocumentPart(_Open):
    """One document as written: a whole twin, or its part for one privacy level."""

    version: Text | None = None  # required unless the document is Twinbase's (`_rules`)
    privacy: Annotated[Text, BeforeValidator(_privacy)] = "private"
    id: Text | None = None
    dt_id: Text | None = Field(None, alias="dt-id")
    hosting_iri: Text | None = Field(None, alias="hosting-iri")
    name: Text | None = None
    description: Text | None = None
    owner: Text | Party | None = None
    contact: Party | None = None
    location: Location | None = None
    manufacturer: Text | Party | None = None
    apiGatewayAddress: Text | None = None
    relations: list[Relation] = Field(default_factory=list)
    features: list[Feature] = Field(default_factory=list)
    interface: Interface | None = None

    @field_validator("hosting_iri")
    @classmethod
    def _no_placeholder(cls, value: str | None) -> str | None:
        return None if is_placeholder(value) else value

    @property
    def global_id(self) -> str | None:
        if self.id:
            return self.id
        return None if is_placeholder(self.dt_id) else self.dt_id

    @property
    def id_base(self) -> str | None:
        """BASE of `dt-id: autoassign|BASE`: a new twin's id is BASE/{slug}, as Twinbase
        names it BASE/{folder}."""
        if self.id or not is_placeholder(self.dt_id):
            return None
        _, _, base = str(self.dt_id).partition("|")
        return base.strip().rstrip("/") or None


def validate_part(source: SourceDocument) -> tuple[DocumentPart, dict[str, Any]]:
    """Check one document; every problem is reported at once, with its line and column."""
    raw = source.data
    if not isinstance(raw, dict):
        kind = "empty" if raw is None else type(raw).__name__
        raise DocumentError(
            "A DT document must be a mapping of keys to values.",
            [source.problem(f"expected a mapping at the top level, found {kind}")],
        )
    problems: list[Problem] = []
    part: DocumentPart | None = None
    try:
        part = DocumentPart.model_validate(raw)
    except ValidationError as err:
        for e in err.errors(include_url=False):
            path = _data_path(raw, e["loc"], e["type"] == "missing")
            problems.append(source.problem(_message(e), path))
    problems.extend(_plain_data_problems(raw, (), source))
    problems.extend(_rules(raw, source))
    if problems:
        raise DocumentError("The DT document has problems; nothing was stored.", problems)
    assert part is not None
    return part, _normalised(raw, part)


def _rules(raw: dict[str, Any], source: SourceDocument) -> list[Problem]:
    """Checks beyond types, on the raw mapping so they run even when a type is wrong."""
    problems = []
    if "version" not in raw and "dt-id" not in raw:
        problems.append(
            source.problem(
                "required key `version` is missing (only a Twinbase document, one with `dt-id`, "
                'may leave it out); write the dt-document version, such as "1.0"',
                ("version",),
            )
        )
    elif "version" in raw and raw["version"] is None:
        problems.append(source.problem('version is empty; write one, such as "1.0"', ("version",)))
    version = _number_to_text(raw.get("version"))
    if isinstance(version, str) and not SUPPORTED_VERSION.match(version):
        problems.append(
            source.problem(
                f"unsupported version {version!r}: twinlink reads dt-document versions 0.x "
                'and 1.x ("1.0", "0.1"); quote the version',
                ("version",),
            )
        )
    privacy = raw.get("privacy")
    if isinstance(privacy, str) and not PRIVACY_LEVEL.match(privacy):
        problems.append(
            source.problem(
                "privacy must be public, private or a group name (letters, digits, . _ : -)",
                ("privacy",),
            )
        )
    ids = [raw.get("id"), raw.get("dt-id")]
    if all(isinstance(x, str) for x in ids) and ids[0] != ids[1] and not is_placeholder(ids[1]):
        problems.append(source.problem("`id` and `dt-id` name different twins", ("dt-id",)))
    problems.extend(_time_problems(raw, source))
    problems.extend(_duplicates(raw.get("features"), ("features",), "feature", source))
    interface = raw.get("interface")
    if isinstance(interface, dict):
        for section in ("signals", "properties", "commands"):
            path = ("interface", section)
            problems.extend(_duplicates(interface.get(section), path, section[:-1], source))
    return problems


def _time_problems(raw: dict[str, Any], source: SourceDocument) -> list[Problem]:
    """The platform's timestamps are replaced, but one a document brings may set a new twin's
    creation time, so each must be a time twinlink can hold (int64 nanoseconds)."""
    problems = []
    for key in PLATFORM_KEYS:
        read = machine_ns if key.endswith("Machine") else human_ns
        try:
            read(raw.get(key))
        except TimeRangeError as err:
            problems.append(source.problem(str(err), (key,)))
    return problems


def _duplicates(items: Any, path: Path, what: str, source: SourceDocument) -> list[Problem]:
    if not isinstance(items, list):
        return []
    problems = []
    seen: dict[str, int] = {}
    for i, item in enumerate(items):
        name = item.get("name") if isinstance(item, dict) else None
        if not isinstance(name, str):
            continue
        if name in seen:
            where = f"{path[-1]}[{seen[name]}]"
            problems.append(
                source.problem(
                    f"duplicate {what} name {name!r} (first at {where})", (*path, i, "name")
                )
            )
        seen.setdefault(name, i)
    return problems


def _plain_data_problems(value: Any, path: Path, source: SourceDocument) -> list[Problem]:
    """A DT document is plain data (JSON's types): text keys, no binary, dates or sets."""
    if len(path) > MAX_DEPTH:
        return [source.problem(f"nested more than {MAX_DEPTH} levels deep", path[:MAX_DEPTH])]
    if isinstance(value, dict):
        out = []
        for key, item in value.items():
            if not isinstance(key, str):
                out.append(
                    source.problem(f"key {key!r} must be text (quote it)", (*path, str(key)))
                )
            else:
                out.extend(_plain_data_problems(item, (*path, key), source))
        return out
    if isinstance(value, list):
        return [
            p
            for i, item in enumerate(value)
            for p in _plain_data_problems(item, (*path, i), source)
        ]
    if isinstance(value, int) and not isinstance(value, bool) and not fits_int64(value):
        return [source.problem(int64_problem(value), path)]
    if isinstance(value, float) and not math.isfinite(value):
        return [source.problem("not-a-number and infinite values are not allowed", path)]
    if value is None or isinstance(value, str | int | float | bool):
        return []
    return [source.problem(f"values of type {type(value).__name__} are not allowed here", path)]


def _normalised(raw: dict[str, Any], part: DocumentPart) -> dict[str, Any]:
    """The document as stored: the input mapping with text fields made text."""
    out = dict(raw)
    if part.version is not None:
        out["version"] = part.version
    out["privacy"] = part.privacy
    for key in PLATFORM_KEYS:
        out.pop(key, None)
    if is_placeholder(out.get("hosting-iri")):
        del out["hosting-iri"]  # the twin's address here, which the reader's document shows
    return out


_ALIASES = {"dt_id": "dt-id", "hosting_iri": "hosting-iri"}


def _has(node: Any, key: str | int) -> bool:
    if isinstance(node, dict):
        return key in node
    return isinstance(node, list) and isinstance(key, int) and 0 <= key < len(node)


def _data_path(raw: Any, loc: tuple[int | str, ...], missing: bool) -> Path:
    """Pydantic locations also name union members (`str`, `Party`); keep only real keys.
    For a missing key, the path ends with its name so the message can point at the parent."""
    path: list[str | int] = []
    node = raw
    for i, part in enumerate(loc):
        key = _ALIASES.get(part, part) if isinstance(part, str) else part
        if _has(node, key):
            node = node[key]
            path.append(key)
        elif missing and i == len(loc) - 1:
            path.append(key)
    return tuple(path)


def _message(e: Any) -> str:
    kind = e["type"]
    if kind == "missing":
        return f"required key `{e['loc'][-1]}` is missing"
    if kind == "literal_error":
        return str(e["msg"]).replace("Input should be", "must be")
    msg = str(e["msg"])
    if msg.startswith("Value error, "):
        msg = msg[len("Value error, ") :]
    got = e.get("input")
    if kind == "float_type" and isinstance(got, str) and _reads_as_number(got):
        # YAML 1.1 reads `1e3` as text: its floats need a dot (and a sign in the exponent).
        return f"{msg} (got the text {got!r}; write a number without quotes, such as 1.0e+3)"
    if kind.endswith("_type") and not isinstance(got, dict | list):
        return f"{msg} (got {got!r})"
    return msg


def _reads_as_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True
