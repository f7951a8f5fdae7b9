"""Plug-ins: connector kinds, gateway credential methods and blueprints (docs/plugins.md).

Each sort of plug-in is an entry-point group, and each entry names one class
(`name = "package.module:Class"`). The built-in plug-ins are ordinary entries of the
`twinlink` distribution, found exactly as a third-party package's are. A plug-in is imported
when it is first needed, so a heavy library (asyncua, FMPy) costs nothing until it is used.
One that cannot be imported, or is not the class its group expects, is logged once and left
out: a broken package never stops the server, nor the other plug-ins.

Settings are a pydantic model; fields typed `SecretStr` (or `Secret[...]`, or either of them
`| None`) are the secret ones: stored encrypted, never shown, only `<field>_set`.
"""

from __future__ import annotations

import importlib
import inspect
import logging
import types
import typing
from dataclasses import dataclass
from functools import cache
from importlib.metadata import entry_points
from typing import Any, Generic, TypeVar

from pydantic import BaseModel, Secret, SecretStr

from twinlink.domain.errors import TwinlinkError

log = logging.getLogger("twinlink.plugins")

CONNECTORS = "twinlink.connectors"
CREDENTIALS = "twinlink.credentials"
BLUEPRINTS = "twinlink.blueprints"
# A name claimed by two packages goes to this one: a package installed beside twinlink cannot
# quietly replace a built-in (the `basic` credential method, say).
HOME = "twinlink"

T = TypeVar("T")


class PluginUnavailable(TwinlinkError):
    """The plug-in is registered but cannot be used here; the message names its package and
    why (a library it needs is missing, the module fails to import, ...)."""


@dataclass(frozen=True, slots=True)
class Registered:
    """One entry of a group, not imported yet."""

    group: str
    name: str
    target: str  # "package.module:Class"
    package: str  # the distribution that registered it


def registered(group: str) -> dict[str, Registered]:
    """The entries of `group` by name. When two packages register one name, twinlink's own
    entry wins, else the first package by name; the other is logged and left out."""
    found: dict[str, Registered] = {}
    entries = sorted(entry_points(group=group), key=lambda ep: _rank(_package(ep)))
    for ep in entries:
        entry = Registered(group, ep.name, ep.value, _package(ep))
        kept = found.setdefault(ep.name, entry)
        if kept is not entry and kept.target != entry.target:
            log.warning(
                "%s %r of package %s is ignored: package %s registers that name",
                group, ep.name, entry.package, kept.package,
            )  # fmt: skip
    return found


def _package(ep: Any) -> str:
    dist = getattr(ep, "dist", None)
    return str(dist.name) if dist is not None else "?"


def _rank(package: str) -> tuple[bool, str]:
    return (package != HOME, package.lower())


class Plugins(Generic[T]):
    """The plug-ins of one group: classes derived from `base`, each with a pydantic `Config`
    and a class attribute `name_attr` equal to its entry's name (a connector's `kind`, a
    credential method's `method`). Each is imported once, when first asked for."""

    def __init__(self, group: str, base: type[Any], name_attr: str) -> None:
        # `type[Any]`: the base is usually abstract, which `type[T]` would refuse.
        self.group = group
        self.base = base
        self.name_attr = name_attr
        self._found: dict[str, Registered] | None = None
        self._loaded: dict[str, type[T] | str] = {}  # the class, or why it cannot be loaded

    def names(self) -> list[str]:
        return sorted(self._entries())

    def get(self, name: str) -> type[T]:
        """The class registered as `name`; KeyError if none is, PluginUnavailable if it
        cannot be loaded (the same error every time: it is tried once)."""
        loaded = self._loaded.get(name)
        if loaded is None:
            loaded = self._loaded[name] = self._load(self._entries()[name])
        if isinstance(loaded, str):
            raise PluginUnavailable(loaded)
        return loaded

    def unavailable(self) -> dict[str, str]:
        """Why each plug-in that cannot be loaded cannot, by name (it imports them all)."""
        reasons: dict[str, str] = {}
        for name in self.names():
            try:
                self.get(name)
            except PluginUnavailable as err:
                reasons[name] = str(err)
        return reasons

    def _entries(self) -> dict[str, Registered]:
        if self._found is None:
            self._found = registered(self.group)
        return self._found

    def _load(self, entry: Registered) -> type[T] | str:
        try:
            return self._checked(entry, load_class(entry.target))
        except Exception as err:  # a broken plug-in is left out, never fatal
            reason = f"{type(err).__name__}: {err}"
            log.warning(
                "%s %r of package %s cannot be loaded, left out: %s",
                self.group, entry.name, entry.package, reason,
                exc_info=not isinstance(err, ImportError),  # the traceback of a bug in it
            )  # fmt: skip
            return f"{entry.target} (package {entry.package}): {reason}"

    def _checked(self, entry: Registered, cls: Any) -> type[T]:
        if not (inspect.isclass(cls) and issubclass(cls, self.base)):
            raise TypeError(f"{entry.target} is not a subclass of {self.base.__name__}")
        if getattr(cls, self.name_attr, None) != entry.name:
            raise TypeError(
                f"{entry.target} is registered as {entry.name!r} but its "
                f"{self.name_attr} is {getattr(cls, self.name_attr, None)!r}"
            )
        config = getattr(cls, "Config", None)
        if not (inspect.isclass(config) and issubclass(config, BaseModel)):
            raise TypeError(f"{entry.target}.Config is not a pydantic model")
        try:  # the API shows it: a model without one would fail every listing of its group
            config.model_json_schema()
        except Exception as err:
            raise TypeError(f"{entry.target}.Config has no JSON schema: {err}") from err
        return typing.cast("type[T]", cls)


def load_class(target: str) -> Any:
    """The object `package.module:Class` names."""
    module, _, attr = target.partition(":")
    return getattr(importlib.import_module(module), attr)


# -- secrets in a plug-in's settings ---------------------------------------------------------

# Values that go into the vault as JSON: text, or any JSON value wrapped in Secret[...].
_SECRET_TYPES = (SecretStr, Secret)


def is_secret(annotation: Any) -> bool:
    """Whether a field's type is a secret one, alone or in a union with others (`| None`)."""
    if typing.get_origin(annotation) in (typing.Union, types.UnionType):
        return any(is_secret(arg) for arg in typing.get_args(annotation))
    if typing.get_origin(annotation) is typing.Annotated:
        return is_secret(typing.get_args(annotation)[0])
    cls = typing.get_origin(annotation) or annotation
    return inspect.isclass(cls) and issubclass(cls, _SECRET_TYPES)


@cache
def secret_fields(model: type[BaseModel]) -> frozenset[str]:
    """The top-level fields of `model` that hold secrets."""
    return frozenset(name for name, f in model.model_fields.items() if is_secret(f.annotation))


def split_secrets(config: BaseModel) -> tuple[dict[str, Any], dict[str, Any]]:
    """(the settings that may be shown and stored in the clear, the secret values that are
    set). Names are the fields' aliases, as a person writes them."""
    model = type(config)
    names = secret_fields(model)
    public = config.model_dump(mode="json", by_alias=True, exclude=set(names))
    secret: dict[str, Any] = {}
    for name in names:
        value = getattr(config, name)
        if isinstance(value, _SECRET_TYPES):
            secret[model.model_fields[name].alias or name] = value.get_secret_value()
    return public, secret


def shown_settings(
    model: type[BaseModel] | None, public: dict[str, Any], set_names: set[str]
) -> dict[str, Any]:
    """Settings as the API shows them: each secret field only as `<field>_set`."""
    shown = dict(public)
    fields = model.model_fields if model is not None else {}
    for name in sorted(secret_fields(model) if model is not None else ()):
        key = fields[name].alias or name
        shown[f"{key}_set"] = key in set_names
    return shown
