"""Stored gateway credentials keep their shape now that each method is a plug-in: settings
are split into the same public and sealed parts as before, and records written in that shape
(by the hand-kept table of secret fields this replaced) sign requests in as they did."""

from __future__ import annotations

import base64
from pathlib import Path
from typing import Any

import pytest

from twinlink.auth.vault import Vault
from twinlink.domain.records import ServiceRecord, TwinRecord
from twinlink.gateway.credentials.base import Credentials
from twinlink.gateway.spec import ServiceSettings, origin
from twinlink.gateway.table import Service, ServiceBuilder
from twinlink.plugins import split_secrets

URL = "http://svc.example:8080/api/"
TWIN = TwinRecord(1, "tingen", "https://twin.example/tingen", "Tingen", 0, 0, "private")

# What the replaced code stored per method: (auth as given, public part, secret part).
# Its table named the secret fields: basic password; bearer token; api_key value;
# oauth2_client_credentials client_secret; oauth2_password password and client_secret;
# custom_login body.
STORED: dict[str, tuple[dict[str, Any], dict[str, Any], dict[str, Any]]] = {
    "basic": (
        {"method": "basic", "username": "u", "password": "pw-basic"},
        {"method": "basic", "username": "u"},
        {"password": "pw-basic"},
    ),
    "bearer": (
        {"method": "bearer", "token": "tok-bearer"},
        {"method": "bearer"},
        {"token": "tok-bearer"},
    ),
    "api_key": (
        {"method": "api_key", "name": "X-Key", "value": "key-header"},
        {"method": "api_key", "name": "X-Key", "in": "header"},
        {"value": "key-header"},
    ),
    "api_key_query": (
        {"method": "api_key", "name": "key", "value": "key query&", "in": "query"},
        {"method": "api_key", "name": "key", "in": "query"},
        {"value": "key query&"},
    ),
    "oauth2_client_credentials": (
        {"method": "oauth2_client_credentials", "token_url": "http://idp.example/t",
         "client_id": "c", "client_secret": "cs-secret", "scope": "read"},
        {"method": "oauth2_client_credentials", "token_url": "http://idp.example/t",
         "client_id": "c", "scope": "read", "client_auth": "basic"},
        {"client_secret": "cs-secret"},
    ),
    "oauth2_password": (
        {"method": "oauth2_password", "token_url": "http://idp.example/t", "username": "u",
         "password": "pw-owner", "client_id": "c", "client_secret": "cs-owner",
         "client_auth": "body"},
        {"method": "oauth2_password", "token_url": "http://idp.example/t", "username": "u",
         "client_id": "c", "scope": None, "client_auth": "body"},
        {"password": "pw-owner", "client_secret": "cs-owner"},
    ),
    "custom_login": (
        {"method": "custom_login", "login_url": "http://svc.example/login",
         "body": {"user": "login-user", "pass": "pw-login"}, "header": "X-Token",
         "template": "{token}"},
        {"method": "custom_login", "login_url": "http://svc.example/login", "token_path": "token",
         "expires_in_path": None, "header": "X-Token", "template": "{token}"},
        {"body": {"user": "login-user", "pass": "pw-login"}},
    ),
}  # fmt: skip


@pytest.mark.parametrize("case", sorted(STORED))
def test_settings_split_into_the_stored_shape(case: str) -> None:
    given, public, secret = STORED[case]
    settings = ServiceSettings.model_validate({"base_url": URL, "auth": given})
    assert split_secrets(settings.auth) == (public, secret)


def _record(vault: Vault, public: dict[str, Any], secret: dict[str, Any]) -> ServiceRecord:
    settings = {"base_url": URL, "auth": public, "secret_keys": sorted(secret)}
    return ServiceRecord(
        1, TWIN.id, "svc", "api", settings, vault.seal(secret), origin(URL), None, 1, 1
    )


def _built(tmp_path: Path, public: dict[str, Any], secret: dict[str, Any]) -> Service:
    vault = Vault.open(tmp_path, None)
    builder = ServiceBuilder(store=None, vault=vault)  # type: ignore[arg-type]  # not read
    return builder._service(TWIN, "svc", None, _record(vault, public, secret))


def _signed(credentials: Credentials[Any]) -> tuple[list[tuple[bytes, bytes]], list[str]]:
    headers: list[tuple[bytes, bytes]] = [(b"accept", b"*/*")]
    query: list[str] = []
    credentials.apply(headers, query)
    return headers, query


@pytest.mark.parametrize("case", sorted(STORED))
def test_records_of_the_stored_shape_are_shown_without_their_secrets(
    case: str, tmp_path: Path
) -> None:
    _, public, secret = STORED[case]
    service = _built(tmp_path, public, secret)
    assert service.blocked is None
    shown = service.public()["auth"]
    assert shown == {**public, **{f"{k}_set": True for k in secret}}
    for value in service.credentials.secrets():
        assert value not in str(service.public())


def test_records_of_the_stored_shape_sign_requests_in(tmp_path: Path) -> None:
    def signed(case: str) -> tuple[list[tuple[bytes, bytes]], list[str]]:
        _, public, secret = STORED[case]
        return _signed(_built(tmp_path, public, secret).credentials)

    basic = base64.b64encode(b"u:pw-basic")
    assert signed("basic") == ([(b"accept", b"*/*"), (b"authorization", b"Basic " + basic)], [])
    assert signed("bearer")[0][-1] == (b"authorization", b"Bearer tok-bearer")
    assert signed("api_key")[0][-1] == (b"x-key", b"key-header")
    assert signed("api_key_query") == ([(b"accept", b"*/*")], ["key=key%20query%26"])


def test_an_old_record_with_an_unset_client_secret_still_loads(tmp_path: Path) -> None:
    # The replaced code sealed secret fields left unset as null.
    _, public, _ = STORED["oauth2_password"]
    service = _built(
        tmp_path, {**public, "client_id": None}, {"password": "pw", "client_secret": None}
    )
    assert service.blocked is None
    assert service.credentials.secrets() == ["pw"]
