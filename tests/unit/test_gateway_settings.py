"""A service's settings: validation, secrets kept apart and shown only as *_set."""

from __future__ import annotations

import stat
import time
from pathlib import Path

import pytest
from pydantic import ValidationError

from twinlink.auth.vault import Vault, VaultError
from twinlink.gateway.credentials.base import CredentialConfig, RefreshError, scrub
from twinlink.gateway.credentials.methods import credentials_for, shown_auth
from twinlink.gateway.credentials.token import TokenCredentials, json_path, seconds
from twinlink.gateway.spec import ServiceSettings, check_base_url, origin, service_name
from twinlink.plugins import split_secrets


def test_feature_names_become_service_names() -> None:
    assert service_name("Sensor manager") == "sensor-manager"
    assert service_name("OPC UA server") == "opc-ua-server"
    assert service_name("  CAD store (exports) ") == "cad-store-exports"


@pytest.mark.parametrize(
    "url",
    ["ftp://h/x", "http:///x", "http://user:pw@h/", "http://h/?q=1", "http://h/#f", "file:///etc"],
)
def test_unusable_base_urls_are_refused(url: str) -> None:
    with pytest.raises(ValueError):
        check_base_url(url)


def test_base_urls_end_with_a_slash_and_origins_name_the_port() -> None:
    assert check_base_url("https://h.example/api") == "https://h.example/api/"
    assert origin("https://H.example/api/") == "https://h.example:443"
    assert origin("http://h:8701/x") == "http://h:8701"


def test_secrets_are_split_off_and_shown_only_as_set() -> None:
    settings = ServiceSettings.model_validate(
        {
            "base_url": "http://h/",
            "auth": {
                "method": "oauth2_password",
                "token_url": "http://h/t",
                "username": "u",
                "password": "pw",
                "client_id": "c",
                "client_secret": "cs",
            },
        }
    )
    public, secret = split_secrets(settings.auth)
    assert secret == {"password": "pw", "client_secret": "cs"}
    shown = shown_auth(public, set(secret))
    assert shown["password_set"] is True and shown["client_secret_set"] is True
    assert "pw" not in str(shown) and "cs" not in str(shown)


def test_unknown_methods_and_templates_without_a_token_are_refused() -> None:
    with pytest.raises(ValidationError):
        ServiceSettings.model_validate({"methods": ["GET", "BREW"]})
    with pytest.raises(ValidationError):
        ServiceSettings.model_validate(
            {"auth": {"method": "custom_login", "login_url": "http://h/", "template": "Token"}}
        )


def test_static_credentials_go_where_they_belong() -> None:
    headers: list[tuple[bytes, bytes]] = []
    query: list[str] = []
    credentials_for(
        ServiceSettings.model_validate(
            {"auth": {"method": "api_key", "name": "key", "value": "a b&c", "in": "query"}}
        ).auth
    ).apply(headers, query)
    assert headers == [] and query == ["key=a%20b%26c"]
    basic = credentials_for(
        ServiceSettings.model_validate(
            {"auth": {"method": "basic", "username": "u", "password": "p"}}
        ).auth
    )
    basic.apply(headers, query)
    assert headers == [(b"authorization", b"Basic dTpw")]


def test_json_paths_and_scrubbing() -> None:
    body = {"data": {"token": "t1", "items": [{"k": 2}]}}
    assert json_path(body, "data.token") == "t1"
    assert json_path(body, "$.data.items.0.k") == 2
    assert json_path(body, "data.missing.x") is None
    assert scrub("bad password hunter2 given", ["hunter2"]) == "bad password *** given"


def test_the_vault_key_file_is_private_and_other_keys_cannot_read(tmp_path: Path) -> None:
    vault = Vault.open(tmp_path, None)
    sealed = vault.seal({"password": "hunter2"})
    assert b"hunter2" not in sealed
    assert stat.S_IMODE((tmp_path / "secret.key").stat().st_mode) == 0o600
    assert Vault.open(tmp_path, None).unseal(sealed) == {"password": "hunter2"}
    other = Vault.open(tmp_path / "other", None)
    with pytest.raises(VaultError):
        other.unseal(sealed)
    assert "key" not in repr(vault).replace("<key hidden>", "")


class _Flaky(TokenCredentials[CredentialConfig]):
    template = "Token {token}"

    def __init__(self) -> None:
        super().__init__(CredentialConfig(method="flaky"))
        self.fail = False
        self.fetches = 0

    async def fetch(self) -> tuple[str, float | None]:
        self.fetches += 1
        if self.fail:
            raise RefreshError("the login endpoint is down")
        return f"t{self.fetches}", 100.0


async def test_a_token_in_its_renewal_margin_is_used_while_the_login_is_down() -> None:
    creds = _Flaky()
    await creds.ready()
    headers: list[tuple[bytes, bytes]] = []
    creds.apply(headers, [])
    assert headers == [(b"authorization", b"Token t1")]
    creds.fail = True
    creds._renew_at = 0.0  # in the margin: due for renewal, not yet expired
    await creds.ready()  # the fetch fails, the old token still serves
    assert creds.fetches == 2 and creds.last_error is not None
    creds._expires_at = 0.0  # expired: nothing usable is left
    with pytest.raises(RefreshError):
        await creds.ready()


@pytest.mark.parametrize(
    ("expires_in", "life_s"),
    [(100, 100.0), ("60", 60.0), (None, 3600.0), (float("inf"), 3600.0),
     (float("nan"), 3600.0), (10**400, 3600.0), ("soon", 3600.0), (-5, 3600.0)],
)  # fmt: skip
async def test_a_login_endpoints_expires_in_that_is_no_finite_number_means_an_hour(
    expires_in: object, life_s: float
) -> None:
    # A hostile or broken endpoint's 400-digit expires_in overflowed float(): a failed call.
    class Endpoint(TokenCredentials[CredentialConfig]):
        async def fetch(self) -> tuple[str, float | None]:
            return "t", seconds(expires_in)

    creds = Endpoint(CredentialConfig(method="endpoint"))
    before = time.monotonic()
    await creds.ready()
    assert before + life_s <= creds._expires_at <= time.monotonic() + life_s


@pytest.mark.parametrize(
    "limits",
    [{"max_body_mb": 1e300}, {"max_body_mb": 0}, {"timeout_s": 1e10}, {"connect_timeout_s": -1}],
)
def test_limits_have_a_range(limits: dict[str, float]) -> None:
    with pytest.raises(ValidationError):
        ServiceSettings.model_validate({"base_url": "http://a.example/", "limits": limits})
    top = {"max_body_mb": 1_048_576, "timeout_s": 3600, "connect_timeout_s": 120}
    ServiceSettings.model_validate({"base_url": "http://a.example/", "limits": top})
