"""The kinds of connector, their configuration models, and splitting a configuration into
what may be shown and what is secret."""

from __future__ import annotations

import importlib
import re
from functools import cache
from typing import Any

from pydantic import BaseModel, SecretStr, ValidationError

from twinlink.connectors.base import Connector
from twinlink.domain.errors import InvalidInputError

# kind -> "module:class"; imported when first needed, so a kind whose library is missing
# does not stop the others.
KINDS = {
    "udp": "twinlink.connectors.udp:UdpConnector",
    "opcua": "twinlink.connectors.opcua:OpcUaConnector",
}

CONNECTOR_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._:-]{0,63}$")


@cache
def connector_class(kind: str) -> type[Connector]:
    target = KINDS.get(kind)
    if target is None:
        known = ", ".join(sorted(KINDS))
        raise InvalidInputError(f"unknown connector kind {kind!r}; the kinds are {known}")
    module, _, name = target.partition(":")
    cls: type[Connector] = getattr(importlib.import_module(module), name)
    return cls


def kinds_view() -> list[dict[str, Any]]:
    """Each kind with its documentation and its configuration's JSON schema."""
    out: list[dict[str, Any]] = []
    for kind in sorted(KINDS):
        try:
            cls = connector_class(kind)
        except ImportError as err:  # a library it needs is missing
            out.append({"kind": kind, "error": f"not available: {err}"})
            continue
        out.append(
            {
                "kind": kind,
                "description": (cls.__doc__ or "").strip(),
                "schema": cls.Config.model_json_schema(),
                "secret_fields": sorted(secret_fields(cls.Config)),
            }
        )
    return out


@cache
def secret_fields(model: type[BaseModel]) -> frozenset[str]:
    """Top-level fields typed SecretStr (or SecretStr | None): stored sealed, never shown."""
    return frozenset(
        name for name, field in model.model_fields.items() if "SecretStr" in str(field.annotation)
    )


def checked_config(kind: str, config: Any) -> BaseModel:
    """The configuration validated by its kind's model; a 422 naming each problem if not."""
    if not isinstance(config, dict):
        raise InvalidInputError("`config` is a JSON object with the connector's settings")
    try:
        model = connector_class(kind).Config
    except ImportError as err:
        raise InvalidInputError(f"the {kind} connector is not available here: {err}") from None
    try:
        return model.model_validate(config)
    except ValidationError as err:
        problems = "; ".join(
            f"{'.'.join(str(p) for p in e['loc']) or 'config'}: {e['msg']}" for e in err.errors()
        )
        raise InvalidInputError(f"the {kind} connector's config is not valid: {problems}") from None


def split_config(config: BaseModel) -> tuple[dict[str, Any], dict[str, Any]]:
    """(the settings that may be shown and stored in the clear, the secret ones)."""
    secrets = secret_fields(type(config))
    public = config.model_dump(mode="json", exclude=set(secrets))
    secret = {}
    for name in secrets:
        value = getattr(config, name)
        if isinstance(value, SecretStr):
            secret[name] = value.get_secret_value()
    return public, secret


def shown_config(kind: str, public: dict[str, Any], secret_names: set[str]) -> dict[str, Any]:
    """Settings as the API shows them: secret fields only as `<field>_set`."""
    shown = dict(public)
    try:
        names = secret_fields(connector_class(kind).Config)
    except (InvalidInputError, ImportError):
        names = frozenset()
    for name in sorted(names):
        shown[f"{name}_set"] = name in secret_names
    return shown
