"""A gateway service's settings: where it is, how the gateway signs in to it, and its limits.

`auth` holds the settings of one credential method, checked by that method's model
(`gateway/credentials/`, plug-ins of the `twinlink.credentials` entry points). Their secret
fields (passwords, tokens, client secrets, API key values, custom login bodies) are kept
encrypted at rest and are never shown again: only `<field>_set: true`.
"""

from __future__ import annotations

import functools
import re
import ssl
from urllib.parse import urlsplit

from pydantic import BaseModel, ConfigDict, Field, field_validator

from twinlink.gateway.credentials.methods import AuthSettings
from twinlink.gateway.credentials.static import NoConfig

METHODS = ("GET", "HEAD", "OPTIONS", "POST", "PUT", "PATCH", "DELETE")
READ_METHODS = frozenset({"GET", "HEAD", "OPTIONS"})
NAME_PATTERN = r"^[a-z0-9](?:[a-z0-9-]{0,62}[a-z0-9])?$"
_NAME = re.compile(NAME_PATTERN)


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
            except (ssl.SSLError, ValueError) as err:
                raise ValueError("ca_pem is not a PEM certificate") from err
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
    auth: AuthSettings = Field(default_factory=NoConfig)
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
