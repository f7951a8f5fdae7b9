"""The library's words: asset kinds, scopes, names, tags, versions and `lib:` references.

An asset is (scope, kind, name); a version is an immutable list of files named by the digest
of its manifest; a tag points at one version of its asset. The rules of each name live here so
that the API, the CLI's server side, the processors and the deploy package check them alike.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any

from twinlink.domain.errors import InvalidInputError

KINDS: tuple[str, ...] = ("data", "models", "tools", "functions", "twins")
COMMON = "common"
GROUP_PREFIX = "group:"
USER_PREFIX = "user:"
ME = "me"  # in URLs and refs: the caller's own `user:<name>`

NAME = re.compile(r"^[a-z0-9][a-z0-9._-]{0,99}$")
TAG = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._+-]{0,63}$")
# What follows `group:` / `user:`: the characters group and user names may have.
_PRINCIPAL = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.:@-]{0,127}$")
DIGEST = re.compile(r"^sha256:[0-9a-f]{64}$")
DIGEST_PREFIX = re.compile(r"^sha256:[0-9a-f]{12,64}$")
LATEST = "latest"
REF_SCHEME = "lib:"


@dataclass(frozen=True, slots=True)
class FileEntry:
    """One file of a version: its path inside the version, content hash, size, exec bit."""

    path: str
    sha256: str
    size: int
    executable: bool = False

    def as_dict(self) -> dict[str, Any]:
        return {
            "path": self.path,
            "sha256": self.sha256,
            "size": self.size,
            "executable": self.executable,
        }


@dataclass(slots=True)
class AssetRecord:
    id: int
    scope: str
    kind: str
    name: str
    description: str
    keywords: list[str]
    licence: str
    author: str
    created_by: str | None
    created_ns: int
    updated_ns: int
    # Filled where an asset is listed or shown: its tags (tag -> digest) and version count.
    tags: dict[str, str] = field(default_factory=dict)
    versions: int = 0

    @property
    def ref(self) -> str:
        return f"{self.scope}/{self.kind}/{self.name}"


@dataclass(slots=True)
class VersionRecord:
    asset_id: int
    digest: str
    files: list[FileEntry]
    size: int
    meta: dict[str, Any]
    created_by: str | None
    created_ns: int


@dataclass(frozen=True, slots=True)
class LibRef:
    """A parsed reference: `[lib:][<scope>/][<kind>/]<name>[@<ref>][#<path>]`. `scope` and
    `kind` are None when the text leaves them out; `ref` None means `latest`."""

    scope: str | None
    kind: str | None
    name: str
    ref: str | None = None
    path: str | None = None

    def __str__(self) -> str:
        text = "/".join(p for p in (self.scope, self.kind, self.name) if p)
        text += f"@{self.ref}" if self.ref else ""
        return REF_SCHEME + text + (f"#{self.path}" if self.path else "")


def check_kind(kind: str) -> str:
    if kind not in KINDS:
        raise InvalidInputError(f"{kind!r} is not an asset kind: use one of {', '.join(KINDS)}")
    return kind


def check_name(name: str) -> str:
    if not NAME.match(name):
        raise InvalidInputError(
            f"{name!r} is not an asset name: 1 to 100 lower-case letters, digits, '.', '_' or "
            "'-', starting with a letter or digit"
        )
    return name


def check_tag(tag: str) -> str:
    if not TAG.match(tag):
        raise InvalidInputError(
            f"{tag!r} is not a tag: 1 to 64 letters, digits, '.', '_', '+' or '-', starting "
            "with a letter or digit"
        )
    return tag


def check_scope(scope: str, username: str | None = None) -> str:
    """The scope as stored: `me` becomes `user:<username>`; anything but `common`,
    `group:<g>` or `user:<u>` is refused."""
    if scope == ME and username is not None:
        return USER_PREFIX + username
    for prefix in (GROUP_PREFIX, USER_PREFIX):
        if scope.startswith(prefix) and _PRINCIPAL.match(scope[len(prefix) :]):
            return scope
    if scope == COMMON:
        return scope
    raise InvalidInputError(
        f"{scope!r} is not a library scope: use 'common', 'group:<group>', 'user:<username>' "
        "or 'me'"
    )


def check_ref(ref: str) -> str:
    """A version ref as written after `@`: a tag or a (prefix of a) digest."""
    if ref.startswith("sha256:"):
        if not DIGEST_PREFIX.match(ref):
            raise InvalidInputError(
                f"{ref!r} is not a digest: 'sha256:' and 12 to 64 lower-case hex characters"
            )
        return ref
    return check_tag(ref)


def is_scope(text: str) -> bool:
    return text in (COMMON, ME) or text.startswith((GROUP_PREFIX, USER_PREFIX))


def parse_ref(text: str) -> LibRef:
    """Parse a reference; `lib:` in front is optional. Two segments are `<kind>/<name>` when
    the first is a kind, else `<scope>/<name>`."""
    body = text[len(REF_SCHEME) :] if text.startswith(REF_SCHEME) else text
    head, hashed, path = body.partition("#")
    *front, last = head.split("/")
    name, at, ref = last.partition("@")
    if len(front) > 2 or (hashed and not path) or (at and not ref):
        raise InvalidInputError(_bad_ref(text))
    scope: str | None = None
    kind: str | None = None
    if len(front) == 2:
        scope, kind = front
    elif len(front) == 1:
        if front[0] in KINDS:
            kind = front[0]
        elif is_scope(front[0]):
            scope = front[0]
        else:
            raise InvalidInputError(_bad_ref(text))
    try:
        if scope is not None:
            check_scope(scope, "me")  # `me` is resolved by the caller's name later
        if kind is not None:
            check_kind(kind)
        check_name(name)
        if ref:
            check_ref(ref)
    except InvalidInputError as err:
        raise InvalidInputError(f"{_bad_ref(text)}: {err}") from err
    return LibRef(scope, kind, name, ref or None, path or None)


def _bad_ref(text: str) -> str:
    return (
        f"{text!r} is not a library reference: write "
        "lib:[<scope>/]<kind>/<name>[@<tag or digest>][#<path>]"
    )
