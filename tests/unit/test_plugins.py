"""Plug-ins found through entry points (docs/plugins.md): the built-in connector kinds and
credential methods registered as a third party's would be, and a broken, misshapen or
name-stealing package contained. The packages here are real distributions on sys.path (a
dist-info folder with its entry_points.txt), as pip would leave them."""

from __future__ import annotations

import logging
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Annotated, Any

import pytest
from pydantic import BaseModel, Field, Secret, SecretStr, ValidationError

from twinlink.auth.vault import Vault
from twinlink.connectors import kinds
from twinlink.connectors.base import Connector
from twinlink.connectors.udp.connector import UdpConnector
from twinlink.domain.errors import InvalidInputError
from twinlink.domain.records import ServiceRecord, TwinRecord
from twinlink.gateway import signin
from twinlink.gateway.credentials import methods
from twinlink.gateway.credentials.base import Credentials
from twinlink.gateway.credentials.static import Basic
from twinlink.gateway.exchange import GatewayProblem
from twinlink.gateway.spec import ServiceSettings
from twinlink.gateway.table import Service, ServiceBuilder
from twinlink.plugins import (
    BLUEPRINTS,
    CONNECTORS,
    CREDENTIALS,
    Plugins,
    PluginUnavailable,
    is_secret,
    registered,
    secret_fields,
    shown_settings,
    split_secrets,
)

PACKAGE = "i14_fake_plugins"
TWIN = TwinRecord(1, "tingen", "https://twin.example/tingen", "Tingen", 0, 0, "private")
SHAPES = """
from pydantic import BaseModel
from twinlink.connectors.base import Connector
from twinlink.gateway.credentials.base import CredentialConfig, Credentials


class Settings(BaseModel):
    pass


class NotAConnector:
    kind = "not_a_connector"
    Config = Settings


class Misnamed(Connector):
    kind = "something_else"
    Config = Settings

    async def run(self) -> None: ...


class Shapeless(Connector):
    kind = "shapeless"  # and no Config

    async def run(self) -> None: ...


class Schemaless(Connector):
    kind = "schemaless"
    Config = BaseModel  # itself, which has no schema

    async def run(self) -> None: ...


class StealsUdp(Connector):
    kind = "udp"
    Config = Settings

    async def run(self) -> None: ...


class Fine(Connector):
    kind = "fine"
    Config = Settings

    async def run(self) -> None: ...


class Nothing(Credentials[CredentialConfig]):
    method = "nothing"
    Config = CredentialConfig


class Buggy(Credentials[CredentialConfig]):
    method = "buggy"
    Config = CredentialConfig

    async def ready(self) -> int:
        raise ZeroDivisionError("the-secret-in-a-message")


class Unbuildable(Credentials[CredentialConfig]):
    method = "unbuildable"
    Config = CredentialConfig

    def __init__(self, config: CredentialConfig) -> None:
        raise KeyError("unbuildable")
"""
ENTRY_POINTS = f"""
[twinlink.connectors]
broken = {PACKAGE}.broken:Thing
not_a_connector = {PACKAGE}.shapes:NotAConnector
misnamed = {PACKAGE}.shapes:Misnamed
shapeless = {PACKAGE}.shapes:Shapeless
schemaless = {PACKAGE}.shapes:Schemaless
udp = {PACKAGE}.shapes:StealsUdp
fine = {PACKAGE}.shapes:Fine

[twinlink.credentials]
broken = {PACKAGE}.broken:Thing
nothing = {PACKAGE}.shapes:Nothing
buggy = {PACKAGE}.shapes:Buggy
unbuildable = {PACKAGE}.shapes:Unbuildable
"""


@pytest.fixture
def installed(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    """A package `i14-fake-plugins` installed on sys.path, with plug-ins good and bad."""
    package = tmp_path / PACKAGE
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "broken.py").write_text("raise RuntimeError('broken on purpose')\n")
    (package / "shapes.py").write_text(SHAPES)
    dist = tmp_path / "i14_fake_plugins-1.0.dist-info"
    dist.mkdir()
    (dist / "METADATA").write_text("Metadata-Version: 2.1\nName: i14-fake-plugins\nVersion: 1.0\n")
    (dist / "entry_points.txt").write_text(ENTRY_POINTS)
    monkeypatch.syspath_prepend(str(tmp_path))
    yield
    for name in [m for m in sys.modules if m.split(".")[0] == PACKAGE]:
        del sys.modules[name]  # the next test's package is another folder


def test_the_built_in_kinds_and_methods_are_entry_points_of_twinlink() -> None:
    connectors = registered(CONNECTORS)
    assert {"udp", "opcua"} <= set(connectors)
    assert connectors["udp"].package == "twinlink"
    assert Plugins(CONNECTORS, Connector, "kind").get("udp") is UdpConnector
    credentials = Plugins(CREDENTIALS, Credentials, "method")
    builtin = {"none", "basic", "bearer", "api_key", "oauth2_client_credentials",
               "oauth2_password", "custom_login"}  # fmt: skip
    assert builtin <= set(credentials.names())
    assert credentials.get("basic") is Basic
    assert credentials.unavailable() == {}


@pytest.mark.usefixtures("installed")
def test_a_plugin_that_cannot_load_is_left_out_with_its_reason(
    caplog: pytest.LogCaptureFixture,
) -> None:
    plugins: Plugins[Connector] = Plugins(CONNECTORS, Connector, "kind")
    with caplog.at_level(logging.WARNING, "twinlink.plugins"):
        for _ in range(2):  # tried once: the same answer after, and one line in the log
            with pytest.raises(PluginUnavailable, match="broken on purpose") as err:
                plugins.get("broken")
            assert "i14-fake-plugins" in str(err.value)
    assert len([r for r in caplog.records if "'broken'" in r.getMessage()]) == 1
    reasons = plugins.unavailable()
    assert "not a subclass of Connector" in reasons["not_a_connector"]
    assert "registered as 'misnamed' but its kind is 'something_else'" in reasons["misnamed"]
    assert "Config is not a pydantic model" in reasons["shapeless"]
    assert "Config has no JSON schema" in reasons["schemaless"]
    assert set(reasons) == {"broken", "not_a_connector", "misnamed", "shapeless", "schemaless"}
    assert plugins.get("fine").__name__ == "Fine"  # the rest of the package works


@pytest.mark.usefixtures("installed")
def test_a_package_cannot_take_a_built_in_name(caplog: pytest.LogCaptureFixture) -> None:
    with caplog.at_level(logging.WARNING, "twinlink.plugins"):
        found = registered(CONNECTORS)
    assert found["udp"].package == "twinlink"
    assert Plugins(CONNECTORS, Connector, "kind").get("udp") is UdpConnector
    assert "'udp' of package i14-fake-plugins is ignored" in caplog.text


@pytest.mark.usefixtures("installed")
def test_a_broken_kind_is_listed_and_refuses_connectors(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(kinds, "KINDS", Plugins(CONNECTORS, Connector, "kind"))
    listed = {k["kind"]: k for k in kinds.kinds_view()}
    assert listed["broken"]["error"].startswith("not available: ")
    assert "schema" in listed["udp"] and "schema" in listed["fine"]
    with pytest.raises(InvalidInputError, match="broken connector is not available here"):
        kinds.checked_config("broken", {})
    with pytest.raises(InvalidInputError, match="unknown connector kind 'nope'; the kinds are"):
        kinds.checked_config("nope", {})


@pytest.mark.usefixtures("installed")
def test_a_broken_credential_method_refuses_settings_naming_it(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(methods, "METHODS", Plugins(CREDENTIALS, Credentials, "method"))
    with pytest.raises(ValidationError, match="'broken' is not available here"):
        ServiceSettings.model_validate({"auth": {"method": "broken"}})
    with pytest.raises(ValidationError, match=r"unknown method 'nope'; the methods are .*basic"):
        ServiceSettings.model_validate({"auth": {"method": "nope"}})
    settings = ServiceSettings.model_validate({"auth": {"method": "nothing"}})
    assert type(methods.credentials_for(settings.auth)).__name__ == "Nothing"


@pytest.mark.usefixtures("installed")
async def test_a_credential_methods_bug_fails_its_own_service_only(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    monkeypatch.setattr(methods, "METHODS", Plugins(CREDENTIALS, Credentials, "method"))
    builder = ServiceBuilder(store=None, vault=Vault.open(tmp_path, None))  # type: ignore[arg-type]

    def built(method: str) -> Service:
        settings = {"base_url": "http://svc.example/", "auth": {"method": method}}
        record = ServiceRecord(1, 1, method, "api", settings, None, "http://svc.example:80")
        return builder._service(TWIN, method, None, record)

    with caplog.at_level(logging.ERROR, "twinlink.gateway"):
        unbuildable = built("unbuildable")
        assert unbuildable.blocked == "its unbuildable credentials failed (KeyError)"
        with pytest.raises(GatewayProblem) as err:
            await signin.sign_in(built("buggy"))
    assert err.value.status == 502 and err.value.outcome == "refresh_failed"
    assert "the buggy credential method failed (ZeroDivisionError)" in err.value.detail
    assert "the-secret-in-a-message" not in err.value.detail
    assert "ZeroDivisionError" in caplog.text  # the traceback, for whoever fixes the plug-in
    assert await signin.sign_in(built("nothing")) == 0


class _Settings(BaseModel):
    user: str
    password: SecretStr
    key: SecretStr | None = None
    body: Secret[dict[str, Any]] = Field(default_factory=lambda: Secret({}))
    pin: Annotated[SecretStr, Field(min_length=4)] | None = Field(None, alias="PIN")


def test_secret_fields_are_those_typed_secret() -> None:
    assert not is_secret(str) and not is_secret(str | None)
    assert secret_fields(_Settings) == {"password", "key", "body", "pin"}
    given = {"user": "u", "password": "pw", "body": {"a": [1]}, "PIN": "1234"}
    config = _Settings.model_validate(given)
    public, secret = split_secrets(config)
    assert public == {"user": "u"}
    # Named as a person writes them (aliases); those left unset are not secrets kept.
    assert secret == {"password": "pw", "body": {"a": [1]}, "PIN": "1234"}
    shown = shown_settings(_Settings, public, set(secret))
    assert shown == {"user": "u", "password_set": True, "key_set": False, "body_set": True,
                     "PIN_set": True}  # fmt: skip


def test_every_built_in_plugin_is_documented() -> None:
    docs = Path(__file__).resolve().parents[2] / "docs"
    plugins, gateway = (docs / "plugins.md").read_text(), (docs / "gateway.md").read_text()
    for group in (CONNECTORS, CREDENTIALS, BLUEPRINTS):
        assert f"`{group}`" in plugins, f"docs/plugins.md does not name the group {group}"
    undocumented = [m for m in registered(CREDENTIALS) if f"| `{m}` |" not in gateway]
    assert undocumented == [], f"credential methods missing from docs/gateway.md: {undocumented}"
    pages = {p.stem for p in docs.glob("*.md")}
    no_page = [k for k in registered(CONNECTORS) if k not in pages]
    assert no_page == [], f"connector kinds without a page docs/<kind>.md: {no_page}"
