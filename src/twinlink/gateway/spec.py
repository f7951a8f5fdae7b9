"""A gateway service's settings: where it is, how the gateway signs in to it, and its limits.

The credential methods are a tagged union on `method`. Their secret fields (passwords, tokens,
client secrets, API key values, custom login bodies) are kept encrypted at rest and are never
shown again: `public_auth` replaces each with `<field>_set: true`.
"""

from __future__ import annotations

import functools
import re
import ssl
from typing import Annotated, Any, Literal
from urllib.parse import urlsplit

from pydantic import AfterValidator, BaseModel, ConfigDict, Field, field_validator, model_validator

from twinlink.gateway.headers import is_field_name, is_field_value

METHODS = ("GET", "HEAD", "OPTIONS", "POST", "PUT", "PATCH", "DELETE")
READ_METHODS = frozenset({"GET", "HEAD", "OPTIONS"})
NAME_PATTERN = r"^[a-z0-9](?:[a-z0-9-]{0,62}[a-z0-9])?$"
_NAME = re.compile(NAME_PATTERN)


def _header_name(value: str) -> str:
    if not is_field_name(value):
        raise ValueError(f"{value!r} is not a header name (letters, digits, !#$%&'*+-.^_`|~)")
    return value


def _header_value(value: str) -> str:
    # The value is not echoed: it may be a secret.
    if not is_field_value(value):
        raise ValueError("a header value may not hold line breaks, NUL or non-Latin-1 characters")
    return value


def _http_url(value: str) -> str:
    parts = urlsplit(value.strip())
    if parts.scheme not in ("http", "https") or not parts.hostname:
        raise ValueError("not an http:// or https:// URL with a host")
    return value.strip()


HeaderName = Annotated[str, AfterValidator(_header_name)]
HeaderValue = Annotated[str, AfterValidator(_header_value)]
HttpUrl = Annotated[str, AfterValidator(_http_url)]


class _Auth(BaseModel):
    model_config = ConfigDict(extra="forbid")


class NoAuth(_Auth):
    method: Literal["none"] = "none"


class BasicAuth(_Auth):
    method: Literal["basic"]
    username: str = Field(min_length=1)
    password: str


class BearerAuth(_Auth):
    method: Literal["bearer"]
    token: HeaderValue = Field(min_length=1)


class ApiKeyAuth(_Auth):
    method: Literal["api_key"]
    name: str = Field(min_length=1, max_length=200)
    value: str = Field(min_length=1)
    in_: Literal["header", "query"] = Field("header", alias="in")
    model_config = ConfigDict(extra="forbid", populate_by_name=True)

    @model_validator(mode="after")
    def _fits_a_header(self) -> ApiKeyAuth:
        if self.in_ == "header":  # a query parameter is percent-encoded: anything goes
            _header_name(self.name)
            _header_value(self.value)
        return self


class OAuth2ClientCredentials(_Auth):
    method: Literal["oauth2_client_credentials"]
    token_url: HttpUrl
    client_id: str = Field(min_length=1)
    client_secret: str
    scope: str | None = None
    # RFC 6749 section 2.3.1: servers must accept HTTP Basic; some also take the form body.
    client_auth: Literal["basic", "body"] = "basic"


class OAuth2Password(_Auth):
    method: Literal["oauth2_password"]
    token_url: HttpUrl
    username: str = Field(min_length=1)
    password: str
    client_id: str | None = None
    client_secret: str | None = None
    scope: str | None = None
    client_auth: Literal["basic", "body"] = "basic"


class CustomLogin(_Auth):
    """The Data Link paper's "custom methods for updating access tokens": POST `body` as JSON to
    `login_url`, read the token at `token_path` (dots, list indexes as numbers) of the JSON
    answer and send it as header `header`, formatted by `template`."""

    method: Literal["custom_login"]
    login_url: HttpUrl
    body: dict[str, Any] = Field(default_factory=dict)
    token_path: str = Field("token", min_length=1)
    expires_in_path: str | None = None
    header: HeaderName = "Authorization"
    template: HeaderValue = "Bearer {token}"

    @field_validator("template")
    @classmethod
    def _has_token(cls, value: str) -> str:
        if "{token}" not in value:
            raise ValueError("the template must contain {token}")
        return value


AuthSettings = Annotated[
    NoAuth
    | BasicAuth
    | BearerAuth
    | ApiKeyAuth
    | OAuth2ClientCredentials
    | OAuth2Password
    | CustomLogin,
    Field(discriminator="method"),
]

# The fields of each method that are secret: stored encrypted, never returned or logged.
SECRET_FIELDS: dict[str, tuple[str, ...]] = {
    "none": (),
    "basic": ("password",),
    "bearer": ("token",),
    "api_key": ("value",),
    "oauth2_client_credentials": ("client_secret",),
    "oauth2_password": ("password", "client_secret"),
    "custom_login": ("body",),
}


class Limits(BaseModel):
    model_config = ConfigDict(extra="forbid")

    connect_timeout_s: float = Field(5.0, gt=0, le=120)
    timeout_s: float = Field(
        60.0, gt=0, le=3600, description="Longest wait for the service's answer to start."
    )
    max_body_mb: float = Field(
        100.0, gt=0, le=1_048_576, description="Largest request body forwarded (at most 1 TiB)."
    )


class Tls(BaseModel):
    """How an https:// service's certificate is checked."""

    model_config = ConfigDict(extra="forbid")

    verify: bool = Field(
        True, description="Check the certificate and host name (false: accept any; avoid)."
    )
    ca_pem: str | None = Field(
        None,
        max_length=65536,
        description="CA certificate(s) in PEM to trust for this service (a private CA).",
    )

    @field_validator("ca_pem")
    @classmethod
    def _pem(cls, value: str | None) -> str | None:
        if value is not None:
            try:
                ssl.create_default_context(cadata=value)
            except (ssl.SSLError, ValueError):
                raise ValueError("ca_pem is not a PEM certificate") from None
        return value

    def context(self) -> ssl.SSLContext:
        return _tls_context(self.verify, self.ca_pem)


@functools.lru_cache(maxsize=256)
def _tls_context(verify: bool, ca_pem: str | None) -> ssl.SSLContext:
    """One context per distinct setting: the pool keys connections by it, so services rebuilt
    with the same settings keep reusing their connections."""
    ctx = ssl.create_default_context(cadata=ca_pem) if ca_pem else ssl.create_default_context()
    if not verify:
        ctx.check_hostname = False
        ctx.verify_mode = ssl.CERT_NONE
    return ctx


class ServiceSettings(BaseModel):
    """What an API call may set on a service. `base_url` is required for a service added by
    API and refused for one that comes from the DT document (its `apiAddress` is the URL)."""

    model_config = ConfigDict(extra="forbid")

    base_url: str | None = None
    description: str | None = Field(None, max_length=2000)
    auth: AuthSettings = Field(default_factory=NoAuth)
    methods: list[str] = Field(default_factory=lambda: list(METHODS))
    limits: Limits = Field(default_factory=Limits)
    health_path: str | None = Field(None, max_length=500)
    websocket: bool = True
    tls: Tls = Field(default_factory=Tls)

    @field_validator("methods")
    @classmethod
    def _methods(cls, value: list[str]) -> list[str]:
        upper = sorted({m.upper() for m in value}, key=value_order)
        unknown = [m for m in upper if m not in METHODS]
        if unknown:
            raise ValueError(f"unknown methods {unknown}; use some of {list(METHODS)}")
        return upper

    @field_validator("base_url")
    @classmethod
    def _base_url(cls, value: str | None) -> str | None:
        return None if value is None else check_base_url(value)


def value_order(method: str) -> int:
    return METHODS.index(method) if method in METHODS else len(METHODS)


def check_base_url(url: str) -> str:
    """An http(s) URL with a host and no credentials, query or fragment; ends with `/` so
    paths are joined below it."""
    parts = urlsplit(url.strip())
    # The URL is never echoed back: it may hold credentials.
    if parts.username or parts.password:
        raise ValueError("put credentials in `auth`, not in the URL")
    if parts.scheme not in ("http", "https") or not parts.hostname:
        raise ValueError("the base URL must be an http:// or https:// URL with a host")
    if parts.query or parts.fragment:
        raise ValueError("a base URL has no query or fragment")
    path = parts.path if parts.path.endswith("/") else parts.path + "/"
    return f"{parts.scheme}://{parts.netloc}{path}"


def check_name(name: str) -> str:
    if not _NAME.match(name):
        raise ValueError(
            f"{name!r} is not a service name: lowercase letters, digits and '-', at most 64"
        )
    return name


def service_name(feature_name: str) -> str:
    """The gateway name of a DT document feature: `Sensor manager` -> `sensor-manager`."""
    return re.sub(r"[^a-z0-9]+", "-", feature_name.lower()).strip("-")[:64].strip("-")


def origin(url: str) -> str:
    parts = urlsplit(url)
    port = parts.port or (443 if parts.scheme == "https" else 80)
    return f"{parts.scheme}://{(parts.hostname or '').lower()}:{port}"


def split_secrets(auth: dict[str, Any]) -> tuple[dict[str, Any], dict[str, Any]]:
    """(the settings a caller may see, the secret fields) of an auth dict."""
    secret_keys = SECRET_FIELDS.get(str(auth.get("method")), ())
    public = {k: v for k, v in auth.items() if k not in secret_keys}
    secret = {k: v for k, v in auth.items() if k in secret_keys}
    return public, secret


def public_auth(public: dict[str, Any], secret_keys: set[str]) -> dict[str, Any]:
    """Auth settings as shown: every secret field replaced by `<field>_set`."""
    method = str(public.get("method"))
    shown = dict(public)
    for key in SECRET_FIELDS.get(method, ()):
        shown[f"{key}_set"] = key in secret_keys
    return shown
