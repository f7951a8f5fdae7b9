"""The static credential methods: none, HTTP Basic, a bearer token and an API key, each put
on every request as stored. A 401 from the service cannot be cured by the gateway: their
refresh fails with a message saying an owner must set new ones."""

from __future__ import annotations

import base64
from typing import Literal
from urllib.parse import quote, unquote_plus

from pydantic import ConfigDict, Field, SecretStr, model_validator

from twinlink.gateway.credentials.base import (
    CredentialConfig,
    Credentials,
    HeaderCredentials,
    Headers,
    SecretHeaderValue,
    header_name,
    header_value,
    replace_header,
)


class NoConfig(CredentialConfig):
    method: str = "none"


class NoCredentials(Credentials[NoConfig]):
    """No credentials: the request goes on without any (the caller's own are never passed)."""

    method = "none"
    Config = NoConfig


class BasicConfig(CredentialConfig):
    username: str = Field(min_length=1)
    password: SecretStr


class Basic(HeaderCredentials[BasicConfig]):
    """HTTP Basic authentication (RFC 7617): `username` and `password`."""

    method = "basic"
    Config = BasicConfig

    def header(self) -> tuple[str, str]:
        c = self.config
        pair = f"{c.username}:{c.password.get_secret_value()}".encode()
        return "authorization", f"Basic {base64.b64encode(pair).decode()}"


class BearerConfig(CredentialConfig):
    token: SecretHeaderValue


class Bearer(HeaderCredentials[BearerConfig]):
    """A fixed bearer token (RFC 6750): `Authorization: Bearer <token>`."""

    method = "bearer"
    Config = BearerConfig

    def header(self) -> tuple[str, str]:
        return "authorization", f"Bearer {self.config.token.get_secret_value()}"


class ApiKeyConfig(CredentialConfig):
    model_config = ConfigDict(extra="forbid", populate_by_name=True)

    name: str = Field(min_length=1, max_length=200)
    value: SecretStr = Field(min_length=1)
    in_: Literal["header", "query"] = Field("header", alias="in")

    @model_validator(mode="after")
    def _fits_a_header(self) -> ApiKeyConfig:
        if self.in_ == "header":  # a query parameter is percent-encoded: anything goes
            header_name(self.name)
            header_value(self.value.get_secret_value())
        return self


class ApiKey(Credentials[ApiKeyConfig]):
    """An API key `value`, sent as the header or the query parameter `name` (`in`)."""

    method = "api_key"
    Config = ApiKeyConfig

    def __init__(self, config: ApiKeyConfig) -> None:
        super().__init__(config)
        name, value = config.name, config.value.get_secret_value()
        self._in_query = config.in_ == "query"
        if self._in_query:  # percent-encoded: any character goes
            self._param = f"{quote(name, safe='')}={quote(value, safe='')}"
        else:  # checked to be Latin-1 without line breaks (ApiKeyConfig)
            self._header = (name.lower().encode("latin-1"), value.encode("latin-1"))

    def apply(self, headers: Headers, query: list[str]) -> None:
        if self._in_query:
            query.append(self._param)
        else:
            replace_header(headers, self._header)

    def client_query(self, query: bytes) -> bytes:
        if not self._in_query:
            return query
        # A key of the caller's own under the same name would leave the service two to pick
        # from; only the gateway's is sent.
        pairs = query.split(b"&") if query else []
        name = self.config.name
        return b"&".join(
            p for p in pairs if unquote_plus(p.partition(b"=")[0].decode("latin-1")) != name
        )
