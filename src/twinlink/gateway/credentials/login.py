"""The Data Link paper's "custom methods for updating access tokens": a login endpoint of the
service's own, asked for a token with a JSON body."""

from __future__ import annotations

from typing import Any

from pydantic import Field, Secret, field_validator

from twinlink.gateway.credentials.base import (
    CredentialConfig,
    HeaderName,
    HeaderValue,
    HttpUrl,
    RefreshError,
)
from twinlink.gateway.credentials.token import TokenCredentials, json_body, json_path, seconds


class CustomLoginConfig(CredentialConfig):
    login_url: HttpUrl
    # All of it is secret: it holds whatever the login asks for (a user, a password, a key).
    body: Secret[dict[str, Any]] = Field(default_factory=lambda: Secret({}))
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


class CustomLogin(TokenCredentials[CustomLoginConfig]):
    """POST `body` as JSON to `login_url`, read the token at `token_path` (dots, list indexes
    as numbers) of the JSON answer and send it as header `header`, formatted by `template`;
    `expires_in_path` says where its life in seconds is, if anywhere."""

    method = "custom_login"
    Config = CustomLoginConfig

    def __init__(self, config: CustomLoginConfig) -> None:
        super().__init__(config)
        self.header_name = config.header
        self.template = config.template

    async def fetch(self) -> tuple[str, float | None]:
        a = self.config
        answer = await self.post(
            a.login_url, json=a.body.get_secret_value(), headers={"Accept": "application/json"}
        )
        body = json_body(answer)
        token = json_path(body, a.token_path)
        if not 200 <= answer.status_code < 300 or not isinstance(token, str | int) or not token:
            reason = "" if answer.status_code >= 300 else f"; no token at {a.token_path!r}"
            raise RefreshError(f"the login at {a.login_url} answered {answer.status_code}{reason}")
        expires = json_path(body, a.expires_in_path) if a.expires_in_path else None
        return str(token), seconds(expires)
