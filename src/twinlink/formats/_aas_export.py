"""A twin's document as an Asset Administration Shell and its submodels, built with the
BaSyx SDK's model (which checks the metamodel's constraints as each object is made).

The shell's id is the twin's dt-id, as is the asset's global id: the dt-id names the twin
and, through it, the asset. Submodel ids are under the twin's canonical URL, where they are
served from. Submodels: Nameplate (IDTA 02006-3-0), ContactInformations (IDTA 02002-1-0:
owner and contact), TechnicalData (IDTA 02003-1-2: what the document says about the asset,
its other keys as a generic collection) and OperationalData (the interface, and the twin's
endpoints).
"""

from __future__ import annotations

import json
from typing import Any

from basyx.aas import model

from twinlink.formats import _aas_model as m
from twinlink.formats._aas_model import Store
from twinlink.formats.context import ExportContext

# Keys the submodels below map; every other top-level key goes to the generic collection.
_MAPPED = {
    "version", "privacy", "id", "dt-id", "hosting-iri", "name", "description", "owner",
    "contact", "manufacturer", "interface", "slug", "relations", "features", "location",
    "apiGatewayAddress", "createdMachine", "createdHuman", "modifiedMachine", "modifiedHuman",
}  # fmt: skip


def twin_id(document: dict[str, Any], ctx: ExportContext) -> str:
    return str(document.get("id") or document.get("dt-id") or ctx.twin_url)


def build(document: dict[str, Any], ctx: ExportContext) -> Store:
    """The shell and its submodels for one twin, in an SDK object store."""
    submodels = [
        _nameplate(document, ctx),
        _contacts(document, ctx),
        _technical_data(document, ctx),
        _operational_data(document, ctx),
    ]
    name = str(document.get("name") or ctx.slug)
    shell = model.AssetAdministrationShell(
        model.AssetInformation(model.AssetKind.INSTANCE, global_asset_id=twin_id(document, ctx)),
        twin_id(document, ctx),
        id_short=m.id_short(ctx.slug, set()),
        display_name=model.MultiLanguageNameType({"en": m.clip(name, 64)}),
        description=m.text(str(document["description"])) if document.get("description") else None,
        submodel={model.ModelReference.from_referable(sm) for sm in submodels},
    )
    store: Store = Store([shell, *submodels])
    return store


def _submodel(
    ctx: ExportContext, short: str, semantic: str, elements: list[model.SubmodelElement]
) -> model.Submodel:
    return model.Submodel(
        f"{ctx.twin_url}/aas/submodels/{short}",
        elements,
        id_short=short,
        semantic_id=m.external(semantic),
    )


def _party(value: Any) -> dict[str, Any]:
    """An owner or manufacturer: text, or a mapping with name, email and website."""
    if isinstance(value, dict):
        return value
    return {"name": str(value)} if value not in (None, "") else {}


def _nameplate(document: dict[str, Any], ctx: ExportContext) -> model.Submodel:
    maker = _party(document.get("manufacturer"))
    elements: list[model.SubmodelElement] = [
        m.prop(
            "URIOfTheProduct", twin_id(document, ctx), m.URI_OF_THE_PRODUCT, model.datatypes.AnyURI
        )
    ]
    if maker.get("name"):
        elements.append(m.mlp("ManufacturerName", str(maker["name"]), m.MANUFACTURER_NAME))
    designation = str(document.get("name") or ctx.slug)
    elements.append(
        m.mlp("ManufacturerProductDesignation", designation, m.MANUFACTURER_PRODUCT_DESIGNATION)
    )
    address = _address(maker)
    if address:
        elements.append(m.collection("AddressInformation", address, m.ADDRESS_INFORMATION))
    return _submodel(ctx, "Nameplate", m.NAMEPLATE, elements)


def _address(party: dict[str, Any], person: bool = False) -> list[model.SubmodelElement]:
    """Name, e-mail and web site, as the Contact Information template names them: the name
    is the `Company`, or for a contact person the `NameOfContact`."""
    out: list[model.SubmodelElement] = []
    if party.get("name"):
        short, semantic = ("NameOfContact", m.NAME_OF_CONTACT) if person else ("Company", m.COMPANY)
        out.append(m.mlp(short, str(party["name"]), semantic))
    if party.get("email"):
        email = m.prop("EmailAddress", str(party["email"]), m.EMAIL_ADDRESS)
        out.append(m.collection("Email", [email], m.EMAIL))
    if party.get("website"):
        out.append(
            m.prop("AddressOfAdditionalLink", str(party["website"]), m.ADDRESS_OF_ADDITIONAL_LINK)
        )
    return out


def _contacts(document: dict[str, Any], ctx: ExportContext) -> model.Submodel:
    """The owner and the contact: the Nameplate has no place for an owner, the Contact
    Information template has one for any role (a role without an ECLASS code as text)."""
    elements: list[model.SubmodelElement] = []
    for short, key, role in (
        ("Owner", m.OWNER, m.OWNER),
        ("Contact", "contact", m.ROLE_OTHER_CONTACT),
    ):
        party = _party(document.get(key))
        if party:
            role_element = m.prop("RoleOfContactPerson", role, m.ROLE_OF_CONTACT_PERSON)
            address = _address(party, person=key == "contact")
            elements.append(m.collection(short, [role_element, *address], m.CONTACT_INFORMATION))
    return _submodel(ctx, "ContactInformations", m.CONTACT_INFORMATIONS, elements)


def _technical_data(document: dict[str, Any], ctx: ExportContext) -> model.Submodel:
    maker = _party(document.get("manufacturer"))
    general: list[model.SubmodelElement] = []
    if maker.get("name"):
        general.append(m.prop("ManufacturerName", str(maker["name"]), m.TD_MANUFACTURER_NAME))
    general.append(
        m.mlp(
            "ManufacturerProductDesignation",
            str(document.get("name") or ctx.slug),
            m.TD_PRODUCT_DESIGNATION,
        )
    )
    taken: set[str] = set()
    technical = [
        m.generic(m.id_short(key, taken), value)
        for key, value in document.items()
        if key not in _MAPPED or key in ("location", "apiGatewayAddress", "features", "relations")
    ]
    further: list[model.SubmodelElement] = []
    if document.get("description"):
        statement = m.text(str(document["description"]))
        further.append(
            model.MultiLanguageProperty(
                "TextStatement01", statement, semantic_id=m.external(m.TEXT_STATEMENT)
            )
        )
    valid = _date(document.get("modifiedHuman"))
    if valid is not None:  # the document's data is as of its last change
        further.append(m.prop("ValidDate", valid, m.VALID_DATE, model.datatypes.Date))
    return _submodel(
        ctx,
        "TechnicalData",
        m.TECHNICAL_DATA,
        [
            m.collection("GeneralInformation", general, m.GENERAL_INFORMATION),
            m.collection("ProductClassifications", [], m.PRODUCT_CLASSIFICATIONS),
            m.collection("TechnicalProperties", technical, m.TECHNICAL_PROPERTIES),
            m.collection("FurtherInformation", further, m.FURTHER_INFORMATION),
        ],
    )


def _date(value: Any) -> model.datatypes.Date | None:
    try:
        parsed = model.datatypes.from_xsd(str(value)[:10], model.datatypes.Date)
    except ValueError:
        return None  # not a time twinlink wrote; the date is left out
    return parsed if isinstance(parsed, model.datatypes.Date) else None


def _operational_data(document: dict[str, Any], ctx: ExportContext) -> model.Submodel:
    interface = document.get("interface") or {}
    # One namespace each: a name's idShort depends only on the names of its own list.
    taken_signals: set[str] = set()
    taken_properties: set[str] = set()
    taken_commands: set[str] = set()
    signals = [
        _variable(s, m.SIGNAL, taken_signals, i)
        for i, s in enumerate(interface.get("signals") or [])
    ]
    properties = [
        _variable(p, m.PROPERTY, taken_properties, i)
        for i, p in enumerate(interface.get("properties") or [])
    ]
    commands = [
        _operation(c, taken_commands, i) for i, c in enumerate(interface.get("commands") or [])
    ]
    endpoints = [
        m.prop(short, url, None, model.datatypes.AnyURI)
        for short, url in (
            ("Twin", ctx.twin_url),
            ("Api", f"{ctx.api_url}/twins/{ctx.slug}"),
            ("Live", ctx.ws_url),
            ("Mqtt", ctx.mqtt_url),
        )
        if url
    ]
    policies = [
        m.prop(key, str(interface[key]))
        for key in ("unknown_signals", "out_of_range", "default_device")
        if isinstance(interface.get(key), str)
    ]
    return _submodel(
        ctx,
        "OperationalData",
        m.OPERATIONAL_DATA,
        [
            m.collection("Signals", signals),
            m.collection("Properties", properties),
            m.collection("Commands", commands),
            m.collection("Endpoints", endpoints, m.ENDPOINTS),
            *policies,
        ],
    )


def _variable(entry: dict[str, Any], semantic: str, taken: set[str], index: int) -> model.Property:
    """A signal, property or command parameter as a Property of its value type: the unit in
    an IEC 61360 data specification, range and flags as qualifiers."""
    name = str(entry.get("name") or f"value_{index}")
    value_type = m.VALUE_TYPES.get(str(entry.get("type", "number")), model.datatypes.Double)
    short = m.id_short(name, taken)
    qualifiers = [] if short == name else [m.qualifier(m.Q_NAME, name)]
    # Values as JSON text: the SDK's writers leave out a qualifier value that is false or 0
    # (basyx-python-sdk 2.2.0), which would lose `min: 0` and `writable: false`.
    for key, q_type in (("min", m.Q_MIN), ("max", m.Q_MAX)):
        bound = entry.get(key)
        if isinstance(bound, int | float) and not isinstance(bound, bool):
            qualifiers.append(m.qualifier(q_type, json.dumps(bound)))
    for key, q_type in (("writable", m.Q_WRITABLE), ("required", m.Q_REQUIRED)):
        if isinstance(entry.get(key), bool):
            qualifiers.append(m.qualifier(q_type, json.dumps(entry[key])))
    if entry.get("default") is not None:
        qualifiers.append(m.qualifier(m.Q_DEFAULT, json.dumps(entry["default"])))
    unit = entry.get("unit")
    element = model.Property(
        short,
        value_type,
        description=m.text(str(entry["description"])) if entry.get("description") else None,
        semantic_id=m.external(semantic),
        qualifier=qualifiers,
        embedded_data_specifications=[m.unit_specification(name, str(unit))] if unit else [],
    )
    element.category = "PARAMETER" if entry.get("writable") is True else "VARIABLE"
    return element


def _operation(entry: dict[str, Any], taken_commands: set[str], index: int) -> model.Operation:
    name = str(entry.get("name") or f"command_{index}")
    taken: set[str] = set()
    short = m.id_short(name, taken_commands)
    inputs = [
        _variable(p, m.COMMAND, taken, i) for i, p in enumerate(entry.get("parameters") or [])
    ]
    return model.Operation(
        short,
        input_variable=inputs,
        description=m.text(str(entry["description"])) if entry.get("description") else None,
        semantic_id=m.external(m.COMMAND),
        qualifier=[] if short == name else [m.qualifier(m.Q_NAME, name)],
    )
