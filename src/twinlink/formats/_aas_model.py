"""The Asset Administration Shell vocabulary twinlink writes and reads: the semantic ids of
the IDTA submodel templates it follows, its own for the operational data, and small builders
over the BaSyx SDK's model that keep every value within the metamodel's limits.

Semantic ids are the templates' own (admin-shell-io/submodel-templates, published/):
Digital Nameplate 3.0 (IDTA 02006-3-0), Contact Information 1.0 (IDTA 02002-1-0) and the
Generic Frame for Technical Data 1.2 (IDTA 02003-1-2). The operational data submodel has no
IDTA template; its ids are twinlink's URNs.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from typing import Any

from basyx.aas import model

# Digital Nameplate 3.0 (IDTA 02006-3-0).
NAMEPLATE = "https://admin-shell.io/idta/nameplate/3/0/Nameplate"
URI_OF_THE_PRODUCT = "0112/2///61987#ABN590#002"
MANUFACTURER_NAME = "0112/2///61987#ABA565#009"
MANUFACTURER_PRODUCT_DESIGNATION = "0112/2///61987#ABA567#009"
ADDRESS_INFORMATION = (
    "https://admin-shell.io/zvei/nameplate/1/0/ContactInformations/AddressInformation"
)
# Contact Information 1.0 (IDTA 02002-1-0), also the drop-in AddressInformation uses.
CONTACT_INFORMATIONS = "https://admin-shell.io/zvei/nameplate/1/0/ContactInformations"
CONTACT_INFORMATION = (
    "https://admin-shell.io/zvei/nameplate/1/0/ContactInformations/ContactInformation"
)
ROLE_OF_CONTACT_PERSON = "0173-1#02-AAO204#003"
ROLE_OTHER_CONTACT = "0173-1#07-AAS929#001"  # the template's "other contact"
OWNER = "owner"  # the owner's role: ECLASS has no code for it, the template takes text
COMPANY = "0173-1#02-AAW001#001"
NAME_OF_CONTACT = "0173-1#02-AAO205#002"
EMAIL = "0173-1#02-AAQ836#005"
EMAIL_ADDRESS = "0173-1#02-AAO198#002"
ADDRESS_OF_ADDITIONAL_LINK = "0173-1#02-AAQ326#002"
# Generic Frame for Technical Data 1.2 (IDTA 02003-1-2).
TECHNICAL_DATA = "https://admin-shell.io/ZVEI/TechnicalData/Submodel/1/2"
GENERAL_INFORMATION = "https://admin-shell.io/ZVEI/TechnicalData/GeneralInformation/1/1"
TD_MANUFACTURER_NAME = "0173-1#02-AAO677#002"
TD_PRODUCT_DESIGNATION = "0173-1#02-AAW338#001"
PRODUCT_CLASSIFICATIONS = "https://admin-shell.io/ZVEI/TechnicalData/ProductClassifications/1/1"
TECHNICAL_PROPERTIES = "https://admin-shell.io/ZVEI/TechnicalData/TechnicalProperties/1/1"
FURTHER_INFORMATION = "https://admin-shell.io/ZVEI/TechnicalData/FurtherInformation/1/1"
TEXT_STATEMENT = "https://admin-shell.io/ZVEI/TechnicalData/TextStatement/1/1"
VALID_DATE = "https://admin-shell.io/ZVEI/TechnicalData/ValidDate/1/1"
# twinlink's own: the interface as operational data, and the twin's endpoints.
OPERATIONAL_DATA = "urn:twinlink:aas:OperationalData:1:0"
SIGNAL = "urn:twinlink:aas:OperationalData:1:0:Signal"
PROPERTY = "urn:twinlink:aas:OperationalData:1:0:Property"
COMMAND = "urn:twinlink:aas:OperationalData:1:0:Command"
ENDPOINTS = "urn:twinlink:aas:OperationalData:1:0:Endpoints"
IEC61360 = "https://admin-shell.io/DataSpecificationTemplates/DataSpecificationIEC61360/3/1"

# Qualifier types on operational data elements: what the interface says beyond name,
# value type and unit (the unit is in the element's IEC 61360 data specification).
Q_NAME = "twinlink:name"  # the interface name, when it is not a valid idShort
Q_MIN = "twinlink:min"
Q_MAX = "twinlink:max"
Q_WRITABLE = "twinlink:writable"
Q_REQUIRED = "twinlink:required"
Q_DEFAULT = "twinlink:default"
# Their values are JSON text (xs:string): `1`, `0.5`, `true`, a default of any type.

# The SDK's object store, holding shells and submodels by id.
Store = model.DictIdentifiableStore[model.Identifiable]

VALUE_TYPES: dict[str, type] = {
    "number": model.datatypes.Double,
    "integer": model.datatypes.Long,
    "bool": model.datatypes.Boolean,
    "string": model.datatypes.String,
}
# Read back: every XSD numeric type a third-party shell may use maps to ours.
TYPE_OF_VALUE: dict[type, str] = {
    model.datatypes.Double: "number",
    model.datatypes.Float: "number",
    model.datatypes.Decimal: "number",
    model.datatypes.Boolean: "bool",
    model.datatypes.String: "string",
}

# Limits of the metamodel's string types (AAS Part 1, 3.1).
_NAME_MAX = 64  # MultiLanguageNameType, NameType... idShort is 128
_ID_SHORT_MAX = 128
_TEXT_MAX = 1023  # MultiLanguageTextType
_PREFERRED_NAME_MAX = 255
_ID_SHORT = re.compile(r"^[a-zA-Z][a-zA-Z0-9_-]*[a-zA-Z0-9_]$")


def external(value: str) -> model.ExternalReference:
    """A semantic id: a global reference to a concept outside the package."""
    return model.ExternalReference((model.Key(model.KeyTypes.GLOBAL_REFERENCE, value),))


def clip(text: str, limit: int) -> str:
    return text if len(text) <= limit else text[: limit - 1] + "…"


def text(value: str) -> model.MultiLanguageTextType:
    return model.MultiLanguageTextType({"en": clip(value, _TEXT_MAX)})


def id_short(name: str, taken: set[str]) -> str:
    """A valid idShort for `name`, unique among `taken` (which it joins): letters, digits,
    `_` and `-`, starting with a letter. Names that are not are rewritten, and the exporter
    keeps the original beside it (Q_NAME) so an import gives it back."""
    out = re.sub(r"[^a-zA-Z0-9_-]", "_", name)[:_ID_SHORT_MAX]
    if not out or not out[0].isalpha():
        out = ("x" + out)[:_ID_SHORT_MAX]
    if not _ID_SHORT.match(out):
        out = out.rstrip("-") + "_" if len(out) > 1 else out + "_"
    base, n = out, 2
    while out.lower() in taken:  # idShorts are compared case-insensitively in a namespace
        suffix = f"_{n}"
        out, n = base[: _ID_SHORT_MAX - len(suffix)] + suffix, n + 1
    taken.add(out.lower())
    return out


def qualifier(type_: str, value: str) -> model.Qualifier:
    return model.Qualifier(
        type_, model.datatypes.String, value, kind=model.QualifierKind.VALUE_QUALIFIER
    )


def prop(
    short: str, value: Any, semantic: str | None = None, value_type: type = model.datatypes.String
) -> model.Property:
    return model.Property(
        short, value_type, value, semantic_id=external(semantic) if semantic else None
    )


def mlp(short: str, value: str, semantic: str) -> model.MultiLanguageProperty:
    return model.MultiLanguageProperty(
        short,
        model.MultiLanguageTextType({"en": clip(value, _TEXT_MAX)}),
        semantic_id=external(semantic),
    )


def collection(
    short: str, elements: Iterable[model.SubmodelElement], semantic: str | None = None
) -> model.SubmodelElementCollection:
    return model.SubmodelElementCollection(
        short, elements, semantic_id=external(semantic) if semantic else None
    )


def unit_specification(name: str, unit: str) -> model.EmbeddedDataSpecification:
    """The unit where AAS tools look for it: an IEC 61360 data specification."""
    return model.EmbeddedDataSpecification(
        external(IEC61360),
        model.DataSpecificationIEC61360(
            model.PreferredNameTypeIEC61360({"en": clip(name, _PREFERRED_NAME_MAX)}),
            unit=unit,
        ),
    )


def plain_value(value: Any) -> tuple[type, Any]:
    """The XSD type and value of a plain scalar from a document (bool before int: a bool
    is an int in Python)."""
    if isinstance(value, bool):
        return model.datatypes.Boolean, value
    if isinstance(value, int):
        return model.datatypes.Long, value
    if isinstance(value, float):
        return model.datatypes.Double, value
    return model.datatypes.String, None if value is None else str(value)


def generic(short: str, value: Any) -> model.SubmodelElement:
    """Any plain data as submodel elements: a mapping or a list as a collection (a list's
    items named item_0, item_1, ...: an AAS list holds elements of one kind only), a scalar
    as a property of its type."""
    if isinstance(value, dict):
        taken: set[str] = set()
        return collection(short, [generic(id_short(str(k), taken), v) for k, v in value.items()])
    if isinstance(value, list):
        return collection(short, [generic(f"item_{i}", v) for i, v in enumerate(value)])
    value_type, scalar = plain_value(value)
    return model.Property(short, value_type, scalar)
