"""A gateway credential method: a fixed token in a header of your choice (`X-Api-Key` unless
told otherwise), as many HTTP APIs ask for.

Its settings model declares the token `SecretStr`: the gateway stores it encrypted, shows only
`token_set`, and scrubs it from any message about the service. Registered by one line in
pyproject.toml:

    [project.entry-points."twinlink.credentials"]
    header_token = "twinlink_example_plugins.header_token:HeaderToken"

A service then uses it with `"auth": {"method": "header_token", "token": "..."}`.
"""

from __future__ import annotations

from pydantic import Field

from twinlink.gateway.credentials.base import (
    CredentialConfig,
    HeaderCredentials,
    HeaderName,
    SecretHeaderValue,
)


class HeaderTokenConfig(CredentialConfig):
    header: HeaderName = Field("X-Api-Key", description="The header the token goes in.")
    token: SecretHeaderValue = Field(description="The token, sent as the header's whole value.")


class HeaderToken(HeaderCredentials[HeaderTokenConfig]):
    """A fixed token sent as header `header` (default X-Api-Key) on every request."""

    method = "header_token"
    Config = HeaderTokenConfig

    def header(self) -> tuple[str, str]:
        return self.config.header, self.config.token.get_secret_value()
