"""What every credential method of the gateway shares: its settings' base model, the object
that signs requests in to a service, and the field types methods' settings are made of.

A method is a plug-in of the `twinlink.credentials` entry-point group (docs/plugins.md): a
`Credentials` subclass whose `method` is its entry's name and whose `Config` is its settings.
Fields typed `SecretStr` (or `Secret[...]`) are its secrets: stored encrypted, never shown,
and scrubbed from any message about the service.
"""

from __future__ import annotations

from typing import Annotated, Any, ClassVar, Generic, TypeVar
from urllib.parse import urlsplit

from pydantic import AfterValidator, BaseModel, ConfigDict, SecretStr

from twinlink.domain.errors import TwinlinkError
from twinlink.gateway.headers import is_field_name, is_field_value
from twinlink.plugins import split_secrets

Headers = list[tuple[bytes, bytes]]


class RefreshError(TwinlinkError):
    """New credentials could not be obtained; the message never holds a secret."""


class CredentialConfig(BaseModel):
    """Base of a method's settings; `method` names the method. Unknown keys are an error, so a
    misspelt setting is caught rather than ignored."""

    model_config = ConfigDict(extra="forbid")

    method: str


C = TypeVar("C", bound=CredentialConfig)


class Credentials(Generic[C]):
    """One service's credentials. The base signs nothing in and cannot renew anything;
    subclasses set `method` and `Config` and override what they do: `apply` (put the
    credentials on a request), `ready` and `refresh` (for tokens that are fetched)."""

    method: ClassVar[str]
    Config: ClassVar[type[CredentialConfig]]
    can_refresh: ClassVar[bool] = False

    def __init__(self, config: C) -> None:
        self.config = config
        self.generation = 0
        self.refreshes = 0
        self.last_error: str | None = None

    async def ready(self) -> int:
        """Credentials usable now; the generation to report if the service refuses them."""
        return self.generation

    def apply(self, headers: Headers, query: list[str]) -> None:
        """Add the credentials to a request's headers or query parameters."""

    def client_query(self, query: bytes) -> bytes:
        """The caller's query string as sent on: without a parameter the credentials set."""
        return query

    async def refresh(self, refused_generation: int) -> None:
        raise RefreshError(
            f"the service refused the gateway's {self.method} credentials, which the gateway "
            "cannot renew by itself; an owner of the twin must set new ones"
        )

    def secrets(self) -> list[str]:
        """Secret values, for scrubbing them out of anything shown: every value held in the
        settings' secret fields."""
        _, secret = split_secrets(self.config)
        return [str(leaf) for leaf in leaves(secret) if str(leaf)]


class HeaderCredentials(Credentials[C]):
    """A method that sends one fixed header, made once from the settings by `header()`."""

    def __init__(self, config: C) -> None:
        super().__init__(config)
        name, value = self.header()
        self._header = (name.lower().encode("latin-1"), value.encode("latin-1"))

    def header(self) -> tuple[str, str]:
        """(name, value) of the header."""
        raise NotImplementedError

    def apply(self, headers: Headers, query: list[str]) -> None:
        replace_header(headers, self._header)


def replace_header(headers: Headers, header: tuple[bytes, bytes]) -> None:
    """Set `header`, dropping any the caller sent under that name: the service must see the
    gateway's credentials only, not a second value to choose from."""
    headers[:] = [h for h in headers if h[0] != header[0]]
    headers.append(header)


def scrub(text: str, secrets: list[str]) -> str:
    for secret in secrets:
        if len(secret) >= 3:
            text = text.replace(secret, "***")
    return text


def leaves(value: Any) -> list[Any]:
    """The scalars of a decoded JSON value."""
    if isinstance(value, dict):
        return [leaf for v in value.values() for leaf in leaves(v)]
    if isinstance(value, list):
        return [leaf for v in value for leaf in leaves(v)]
    return [value]


# -- field types of methods' settings --------------------------------------------------------


def header_name(value: str) -> str:
    if not is_field_name(value):
        raise ValueError(f"{value!r} is not a header name (letters, digits, !#$%&'*+-.^_`|~)")
    return value


def header_value(value: str) -> str:
    # The value is not echoed: it may be a secret.
    if not is_field_value(value):
        raise ValueError("a header value may not hold line breaks, NUL or non-Latin-1 characters")
    return value


def _secret_header_value(value: SecretStr) -> SecretStr:
    if not value.get_secret_value():
        raise ValueError("may not be empty")
    header_value(value.get_secret_value())
    return value


def _http_url(value: str) -> str:
    parts = urlsplit(value.strip())
    if parts.scheme not in ("http", "https") or not parts.hostname:
        raise ValueError("not an http:// or https:// URL with a host")
    return value.strip()


HeaderName = Annotated[str, AfterValidator(header_name)]
HeaderValue = Annotated[str, AfterValidator(header_value)]
# A secret sent as (part of) a header: not empty, and no character a header cannot carry.
SecretHeaderValue = Annotated[SecretStr, AfterValidator(_secret_header_value)]
HttpUrl = Annotated[str, AfterValidator(_http_url)]
