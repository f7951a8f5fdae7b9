"""An Asset Administration Shell read back into a DT document fragment: the shell's names,
the Nameplate's manufacturer, the owner from the contact informations, and the interface
from an operational data submodel.

twinlink's own exports come back as they went out. A third party's shell is read by the same
rules where it has the same shape, and otherwise by what the metamodel says: a submodel
whose idShort or semantic id speaks of operational data gives its Properties and Ranges as
signals, its Operations as commands.
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from typing import Any

from basyx.aas import model

from twinlink.domain.errors import InvalidInputError
from twinlink.formats import _aas_model as m
from twinlink.formats._aas_model import Store


def fragment(store: Store) -> dict[str, Any]:
    shells = [x for x in store if isinstance(x, model.AssetAdministrationShell)]
    if not shells:
        raise InvalidInputError(
            "The AAS environment has no assetAdministrationShells: twinlink imports a twin "
            "from a shell (its id, names and submodels)."
        )
    shell = shells[0]
    submodels = _submodels_of(shell, store)
    out: dict[str, Any] = {"id": shell.asset_information.global_asset_id or shell.id}
    nameplate = _by_semantics(submodels, m.NAMEPLATE, "nameplate")
    designation = _text_of(nameplate, "ManufacturerProductDesignation")
    out["name"] = designation or _lang(shell.display_name) or shell.id_short or shell.id
    if shell.description:
        out["description"] = _lang(shell.description)
    if nameplate is not None:
        maker = _party(
            _get(nameplate, "AddressInformation"), _text_of(nameplate, "ManufacturerName")
        )
        if maker:
            out["manufacturer"] = maker
    contacts = _by_semantics(submodels, m.CONTACT_INFORMATIONS, "contactinformation")
    owner = _party(_role(contacts, m.OWNER), None)
    if owner:
        out["owner"] = owner
    contact = _role(contacts, m.ROLE_OTHER_CONTACT)
    if contact is not None:  # a contact is always a mapping (the document's rule)
        person = {
            "name": _text_of(contact, "NameOfContact"),
            "email": _text_of(_get(contact, "Email"), "EmailAddress"),
            "website": _text_of(contact, "AddressOfAdditionalLink"),
        }
        out["contact"] = {k: v for k, v in person.items() if v}
    operational = _by_semantics(submodels, m.OPERATIONAL_DATA, "operational")
    if operational is not None:
        out["interface"] = _interface(operational)
    return out


def _submodels_of(shell: model.AssetAdministrationShell, store: Store) -> list[model.Submodel]:
    found = []
    for ref in shell.submodel:
        try:
            found.append(ref.resolve(store))
        except (KeyError, model.UnexpectedTypeError):
            continue  # validate_aas reports a reference the environment does not hold
    return found


def _by_semantics(
    submodels: list[model.Submodel], semantic: str, word: str
) -> model.Submodel | None:
    for sm in submodels:
        if _semantic(sm) == semantic:
            return sm
    for sm in submodels:
        if word in (sm.id_short or "").lower():
            return sm
    return None


def _semantic(element: model.HasSemantics) -> str | None:
    ref = element.semantic_id
    return ref.key[0].value if ref is not None and ref.key else None


def _get(namespace: Any, short: str) -> Any:
    if namespace is None:
        return None
    for element in _elements(namespace):
        if element.id_short == short:
            return element
    return None


def _elements(namespace: Any) -> Iterable[model.SubmodelElement]:
    if isinstance(namespace, model.Submodel):
        return namespace.submodel_element
    if isinstance(namespace, model.SubmodelElementCollection | model.SubmodelElementList):
        return namespace.value
    return ()


def _lang(strings: model.LangStringSet | None) -> str | None:
    """English where there is English, else the first language's text."""
    if not strings:
        return None
    for lang, value in strings.items():
        if lang.lower().startswith("en"):
            return value
    return next(iter(strings.values()))


def _text_of(namespace: Any, short: str) -> str | None:
    element = _get(namespace, short)
    if isinstance(element, model.MultiLanguageProperty):
        return _lang(element.value)
    if isinstance(element, model.Property) and element.value is not None:
        return str(element.value)
    return None


def _party(address: Any, name: str | None) -> str | dict[str, Any] | None:
    """A manufacturer or owner: text when only a name is known, else a mapping."""
    if address is None and name is None:
        return None
    email = _text_of(_get(address, "Email"), "EmailAddress")
    website = _text_of(address, "AddressOfAdditionalLink")
    name = name or _text_of(address, "Company")
    if not (email or website):
        return name
    party = {"name": name, "email": email, "website": website}
    return {k: v for k, v in party.items() if v}


def _role(contacts: model.Submodel | None, role: str) -> Any:
    """The contact information with that role (RoleOfContactPerson), if any."""
    for element in _elements(contacts):
        if _text_of(element, "RoleOfContactPerson") == role:
            return element
    return None


def _interface(submodel: model.Submodel) -> dict[str, Any]:
    signals_smc, properties_smc = _get(submodel, "Signals"), _get(submodel, "Properties")
    commands_smc = _get(submodel, "Commands")
    if signals_smc is None and properties_smc is None and commands_smc is None:
        # A third party's submodel: its own data elements are the signals.
        signals_smc = commands_smc = submodel
    interface: dict[str, Any] = {
        "signals": [_variable(e) for e in _variables(signals_smc)],
        "properties": [_variable(e, property_=True) for e in _variables(properties_smc)],
        "commands": [
            _command(e) for e in _elements(commands_smc) if isinstance(e, model.Operation)
        ],
    }
    for key, allowed in (
        ("unknown_signals", ("accept", "drop", "reject")),
        ("out_of_range", ("accept", "reject")),
    ):
        value = _text_of(submodel, key)
        if value in allowed:
            interface[key] = value
    default_device = _text_of(submodel, "default_device")
    if default_device:
        interface["default_device"] = default_device
    return interface


def _variables(namespace: Any) -> list[model.Property | model.Range]:
    return [e for e in _elements(namespace) if isinstance(e, model.Property | model.Range)]


def _type_of(value_type: type) -> str:
    if value_type is model.datatypes.Boolean:
        return "bool"
    if issubclass(value_type, int):
        return "integer"
    if issubclass(value_type, float) or value_type is model.datatypes.Decimal:
        return "number"
    return "string"


def _qualifiers(element: model.Qualifiable) -> dict[str, Any]:
    """twinlink's qualifiers, their JSON text read (the name stays text)."""
    out: dict[str, Any] = {}
    for q in element.qualifier:
        if q.type == m.Q_NAME or q.value is None:
            out[q.type] = q.value
            continue
        try:
            out[q.type] = json.loads(str(q.value))
        except ValueError:
            out[q.type] = q.value
    return out


def _number(value: Any) -> int | float | None:
    if isinstance(value, bool) or value is None:
        return None
    if isinstance(value, int):
        return int(value)
    try:
        return float(value)
    except (TypeError, ValueError):
        return None


def _variable(element: model.Property | model.Range, property_: bool = False) -> dict[str, Any]:
    quals = _qualifiers(element)
    out: dict[str, Any] = {"name": str(quals.get(m.Q_NAME) or element.id_short)}
    out["type"] = _type_of(element.value_type)
    unit = _unit(element)
    if unit:
        out["unit"] = unit
    low, high = quals.get(m.Q_MIN), quals.get(m.Q_MAX)
    if isinstance(element, model.Range):
        low, high = element.min if low is None else low, element.max if high is None else high
    for key, bound in (("min", low), ("max", high)):
        if _number(bound) is not None and out["type"] in ("number", "integer"):
            out[key] = _number(bound)
    if element.description:
        out["description"] = _lang(element.description)
    if property_:
        writable = quals.get(m.Q_WRITABLE)
        if not isinstance(writable, bool):  # a third party's: PARAMETER is what may be set
            writable = element.category == "PARAMETER"
        out["writable"] = writable
    if isinstance(quals.get(m.Q_REQUIRED), bool):
        out["required"] = quals[m.Q_REQUIRED]
    if quals.get(m.Q_DEFAULT) is not None:
        out["default"] = quals[m.Q_DEFAULT]
    return out


def _unit(element: model.HasDataSpecification) -> str | None:
    for spec in element.embedded_data_specifications:
        content = spec.data_specification_content
        if isinstance(content, model.DataSpecificationIEC61360) and content.unit:
            return str(content.unit)
    return None


def _command(operation: model.Operation) -> dict[str, Any]:
    quals = _qualifiers(operation)
    out: dict[str, Any] = {"name": str(quals.get(m.Q_NAME) or operation.id_short)}
    if operation.description:
        out["description"] = _lang(operation.description)
    params = [*operation.input_variable, *operation.in_output_variable]
    out["parameters"] = [
        _variable(p) for p in params if isinstance(p, model.Property | model.Range)
    ]
    return out
