"""OAuth2 (RFC 6749): the client credentials grant and the resource owner password grant.
The access token goes to the service as `Authorization: Bearer <token>`."""

from __future__ import annotations

import base64
from typing import Literal, TypeVar
from urllib.parse import quote

from pydantic import Field, SecretStr

from twinlink.gateway.credentials.base import CredentialConfig, HttpUrl, RefreshError, scrub
from twinlink.gateway.credentials.token import TokenCredentials, json_body, seconds


class OAuth2Config(CredentialConfig):
    token_url: HttpUrl
    client_id: str | None = None
    client_secret: SecretStr | None = None
    scope: str | None = None
    # RFC 6749 section 2.3.1: servers must accept HTTP Basic; some also take the form body.
    client_auth: Literal["basic", "body"] = "basic"


class ClientCredentialsConfig(OAuth2Config):
    client_id: str = Field(min_length=1)
    client_secret: SecretStr


class PasswordConfig(OAuth2Config):
    username: str = Field(min_length=1)
    password: SecretStr


G = TypeVar("G", bound=OAuth2Config)


class OAuth2(TokenCredentials[G]):
    """Base of the grants: `grant()` is the form that asks the token endpoint for a token."""

    def grant(self) -> dict[str, str]:
        raise NotImplementedError

    async def fetch(self) -> tuple[str, float | None]:
        a = self.config
        form = self.grant()
        if a.scope:
            form["scope"] = a.scope
        headers = {"Accept": "application/json"}
        if a.client_id is not None:
            secret = a.client_secret.get_secret_value() if a.client_secret else ""
            if a.client_auth == "basic":
                pair = f"{quote(a.client_id, safe='')}:{quote(secret, safe='')}"
                headers["Authorization"] = "Basic " + base64.b64encode(pair.encode()).decode()
            else:
                form["client_id"] = a.client_id
                form["client_secret"] = secret
        answer = await self.post(a.token_url, data=form, headers=headers)
        body = json_body(answer)
        if answer.status_code != 200 or not isinstance(body.get("access_token"), str):
            reason = body.get("error_description") or body.get("error") or "no access_token"
            raise RefreshError(
                f"the token endpoint {a.token_url} answered {answer.status_code}: "
                f"{scrub(str(reason)[:200], self.secrets())}"
            )
        return body["access_token"], seconds(body.get("expires_in"))


class ClientCredentials(OAuth2[ClientCredentialsConfig]):
    """OAuth2 client credentials grant: a token for `client_id` and `client_secret` from
    `token_url` (optional `scope`; `client_auth` basic or body)."""

    method = "oauth2_client_credentials"
    Config = ClientCredentialsConfig

    def grant(self) -> dict[str, str]:
        return {"grant_type": "client_credentials"}


class PasswordGrant(OAuth2[PasswordConfig]):
    """OAuth2 resource owner password grant: a token for `username` and `password` from
    `token_url` (optional client, `scope`)."""

    method = "oauth2_password"
    Config = PasswordConfig

    def grant(self) -> dict[str, str]:
        c = self.config
        return {
            "grant_type": "password",
            "username": c.username,
            "password": c.password.get_secret_value(),
        }
