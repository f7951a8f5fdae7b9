"""The credential methods there are, found through the `twinlink.credentials` entry points,
and a service's `auth` settings checked, split and shown with them.

A method whose package cannot be loaded is left out (logged once): settings naming it are
refused, and a service stored with it is blocked with the reason, while every other service
works on.
"""

from __future__ import annotations

from typing import Annotated, Any

from pydantic import BeforeValidator, SerializeAsAny, WithJsonSchema
from pydantic_core import PydanticCustomError

from twinlink.gateway.credentials.base import CredentialConfig, Credentials
from twinlink.plugins import CREDENTIALS, Plugins, PluginUnavailable, shown_settings

METHODS: Plugins[Credentials[Any]] = Plugins(CREDENTIALS, Credentials, "method")


def method_class(method: str) -> type[Credentials[Any]]:
    """The class of `method`; a ValueError (a setting's error, worded for the person who gave
    it) if there is none here."""
    try:
        return METHODS.get(method)
    except KeyError as err:
        known = ", ".join(METHODS.names())
        raise _invalid(f"unknown method {method!r}; the methods are {known}") from err
    except PluginUnavailable as err:
        raise _invalid(f"the credential method {method!r} is not available here: {err}") from err


def checked_auth(value: Any) -> Any:
    """`auth` validated by its method's settings model (a pydantic before-validator)."""
    if isinstance(value, CredentialConfig):
        return value
    if not isinstance(value, dict):
        raise _invalid("`auth` is an object with a `method` and that method's settings")
    method = value.get("method")
    if not isinstance(method, str):
        raise _invalid(f"`auth` needs a `method`: one of {', '.join(METHODS.names())}")
    return method_class(method).Config.model_validate(value)


def _invalid(message: str) -> PydanticCustomError:
    # Not a plain ValueError, which pydantic would show as "Value error, <message>". Without
    # a context, braces in the message are left as they are.
    return PydanticCustomError("auth_method", message)


# A service's `auth`: any method's settings, checked by that method's model, dumped as such.
# Its JSON schema says only that much: the methods are known once the plug-ins are loaded.
_AUTH_SCHEMA = {
    "type": "object",
    "description": "`method` and that method's settings (docs/gateway.md#credential-methods)",
    "properties": {"method": {"type": "string", "description": "none, basic, bearer, ..."}},
    "required": ["method"],
    "additionalProperties": True,
}
AuthSettings = SerializeAsAny[
    Annotated[CredentialConfig, BeforeValidator(checked_auth), WithJsonSchema(_AUTH_SCHEMA)]
]


def credentials_for(config: CredentialConfig) -> Credentials[Any]:
    return method_class(config.method)(config)


def shown_auth(public: dict[str, Any], set_names: set[str]) -> dict[str, Any]:
    """Auth settings as shown: every secret field of the method replaced by `<field>_set`."""
    try:
        model: type[CredentialConfig] | None = method_class(str(public.get("method"))).Config
    except ValueError:
        model = None
    return shown_settings(model, public, set_names)
