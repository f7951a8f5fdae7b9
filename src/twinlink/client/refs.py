"""Library references as people write them: `[lib:][<scope>/]<kind>/<name>[@<ref>][#<path>]`.

The scope is `common`, `group:<group>`, `user:<username>` or `me`; the ref a tag, a digest
(`sha256:...`) or a digest prefix; the path a file of the version."""

from __future__ import annotations

import re
from dataclasses import dataclass

KINDS = ("data", "models", "tools", "functions", "twins")
_NAME = re.compile(r"^[a-z0-9][a-z0-9._-]{0,99}$")
_SCOPE = re.compile(r"^(common|me|group:[^/@#\s]+|user:[^/@#\s]+)$")


@dataclass(frozen=True, slots=True)
class AssetRef:
    kind: str
    name: str
    scope: str | None = None  # None: looked up (own space, then groups, then common)
    version: str | None = None  # None: `latest`
    path: str | None = None

    def at(self, scope: str) -> AssetRef:
        return AssetRef(self.kind, self.name, scope, self.version, self.path)

    @property
    def base(self) -> str:
        """The asset's URL path under /api/v1/library (scope needed)."""
        assert self.scope is not None, "look the scope up first"
        return f"/api/v1/library/{self.scope}/{self.kind}/{self.name}"

    def __str__(self) -> str:
        text = f"{self.scope}/" if self.scope else ""
        text += f"{self.kind}/{self.name}"
        text += f"@{self.version}" if self.version else ""
        return text + (f"#{self.path}" if self.path else "")


def parse_ref(text: str, kind: str | None = None) -> AssetRef:
    """`text` as an AssetRef; `kind` is the kind when the text names only the asset
    (`tingen-beam@1.0.0` with kind="models"). ValueError says what is wrong."""
    body = text.strip().removeprefix("lib:")
    body, _, path = body.partition("#")
    body, _, version = body.partition("@")
    parts = body.split("/")
    if len(parts) == 3:
        scope, found_kind, name = parts
    elif len(parts) == 2:
        scope, (found_kind, name) = None, parts
    elif len(parts) == 1 and kind is not None:
        scope, found_kind, name = None, kind, parts[0]
    else:
        raise ValueError(f"{text!r} is not a library reference: write [scope/]kind/name[@tag]")
    if found_kind not in KINDS:
        raise ValueError(f"{text!r}: the kind {found_kind!r} is not one of {', '.join(KINDS)}")
    if kind is not None and found_kind != kind:
        raise ValueError(f"{text!r} is of kind {found_kind!r}, not {kind!r}")
    if scope is not None and not _SCOPE.match(scope):
        raise ValueError(f"{text!r}: the scope {scope!r} is not common, me, group:G or user:U")
    if not _NAME.match(name):
        raise ValueError(
            f"{text!r}: the name {name!r} must be lower case letters, digits, '.', '_', '-'"
        )
    return AssetRef(found_kind, name, scope, version or None, path or None)
