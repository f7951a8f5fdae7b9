"""The kinds of connector, their configuration models, and splitting a configuration into
what may be shown and what is secret.

A kind is a plug-in of the `twinlink.connectors` entry-point group (docs/plugins.md): the
built-in `udp` and `opcua` exactly as a third-party package's. A kind whose package is broken
(a library missing, an error on import) is listed as not available and refuses connectors;
the other kinds work on.
"""

from __future__ import annotations

import re
from typing import Any

from pydantic import BaseModel, ValidationError

from twinlink.connectors.base import Connector
from twinlink.domain.errors import InvalidInputError
from twinlink.plugins import (
    CONNECTORS,
    Plugins,
    PluginUnavailable,
    secret_fields,
    shown_settings,
    split_secrets,
)

KINDS: Plugins[Connector] = Plugins(CONNECTORS, Connector, "kind")

CONNECTOR_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._:-]{0,63}$")


def connector_class(kind: str) -> type[Connector]:
    """The class of `kind`: a 422 naming the kinds if there is none, PluginUnavailable if
    its package cannot be loaded."""
    try:
        return KINDS.get(kind)
    except KeyError as err:
        known = ", ".join(KINDS.names())
        raise InvalidInputError(f"unknown connector kind {kind!r}; the kinds are {known}") from err


def kinds_view() -> list[dict[str, Any]]:
    """Each kind with its documentation and its configuration's JSON schema."""
    out: list[dict[str, Any]] = []
    for kind in KINDS.names():
        try:
            cls = KINDS.get(kind)
        except PluginUnavailable as err:
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


def checked_config(kind: str, config: Any) -> BaseModel:
    """The configuration validated by its kind's model; a 422 naming each problem if not."""
    if not isinstance(config, dict):
        raise InvalidInputError("`config` is a JSON object with the connector's settings")
    try:
        model = connector_class(kind).Config
    except PluginUnavailable as err:
        raise InvalidInputError(f"the {kind} connector is not available here: {err}") from err
    try:
        return model.model_validate(config)
    except ValidationError as err:
        problems = "; ".join(
            f"{'.'.join(str(p) for p in e['loc']) or 'config'}: {e['msg']}" for e in err.errors()
        )
        # from None: pydantic's error repeats the values, the connector's secrets among them.
        raise InvalidInputError(f"the {kind} connector's config is not valid: {problems}") from None


def split_config(config: BaseModel) -> tuple[dict[str, Any], dict[str, Any]]:
    """(the settings that may be shown and stored in the clear, the secret ones)."""
    return split_secrets(config)


def shown_config(kind: str, public: dict[str, Any], secret_names: set[str]) -> dict[str, Any]:
    """Settings as the API shows them: secret fields only as `<field>_set`."""
    try:
        model: type[BaseModel] | None = connector_class(kind).Config
    except (InvalidInputError, PluginUnavailable):
        model = None
    return shown_settings(model, public, secret_names)
