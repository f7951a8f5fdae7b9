"""The OPC UA connector's sessions and channels against real crane servers: username and
password (right, wrong, missing), and Basic256Sha256 with a client certificate from files (its
key under a password) or generated."""

from __future__ import annotations

import ipaddress
from collections.abc import AsyncIterator
from pathlib import Path
from typing import Any

import pytest
import pytest_asyncio
from asyncua.crypto import cert_gen
from cryptography import x509
from cryptography.hazmat.primitives import serialization
from cryptography.x509.oid import ExtendedKeyUsageOID

from ilmatar_crane.opcua import CraneOpcUaServer, OpcUaAccess
from ilmatar_crane.plant import CranePlant
from tests.integration._opcua import (
    Platform,
    connected,
    crane_config,
    crane_server,
    eventually,
    running,
    running_platform,
)

pytestmark = [pytest.mark.integration, pytest.mark.asyncio(loop_scope="module")]

USERS = {"operator": "s3cret"}
SERVER_URI = "urn:freeopcua:python:server"  # asyncua's, as its certificate must say


def write_identity(
    folder: Path, name: str, uri: str, *, server: bool = False, password: bytes | None = None
) -> tuple[Path, Path]:
    """A self-signed application certificate and its key, as PEM files."""
    key = cert_gen.generate_private_key()
    names: list[x509.GeneralName] = [
        x509.UniformResourceIdentifier(uri),
        x509.DNSName("localhost"),
        x509.IPAddress(ipaddress.ip_address("127.0.0.1")),
    ]
    usage = ExtendedKeyUsageOID.SERVER_AUTH if server else ExtendedKeyUsageOID.CLIENT_AUTH
    cert = cert_gen.generate_self_signed_app_certificate(key, name, {}, names, [usage])
    cert_path, key_path = folder / f"{name}.pem", folder / f"{name}.key.pem"
    cert_path.write_bytes(cert.public_bytes(serialization.Encoding.PEM))
    encryption = (
        serialization.BestAvailableEncryption(password)
        if password
        else serialization.NoEncryption()
    )
    key_path.write_bytes(
        key.private_bytes(serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8, encryption)
    )
    return cert_path, key_path


@pytest_asyncio.fixture(loop_scope="module", scope="module")
async def users_server() -> AsyncIterator[CraneOpcUaServer]:
    """Username/password sessions only, security None."""
    async with crane_server(CranePlant(), access=OpcUaAccess(users=USERS)) as server:
        yield server


@pytest_asyncio.fixture(loop_scope="module", scope="module")
async def secure_server(
    tmp_path_factory: pytest.TempPathFactory,
) -> AsyncIterator[CraneOpcUaServer]:
    """Basic256Sha256 endpoints only (Sign, SignAndEncrypt), anonymous sessions."""
    cert, key = write_identity(tmp_path_factory.mktemp("server"), "server", SERVER_URI, server=True)
    access = OpcUaAccess(certificate=cert, private_key=key)
    async with crane_server(CranePlant(), access=access) as server:
        yield server


@pytest_asyncio.fixture(loop_scope="module")
async def platform(tmp_path: Path) -> AsyncIterator[Platform]:
    async with running_platform(tmp_path) as platform:
        yield platform


async def values_flow(platform: Platform) -> None:
    """The subscription works: the current values arrived."""
    await eventually(
        lambda: any(s.get("running") is True for s in platform.samples().values()),
        "the crane's current values",
    )


async def test_a_session_with_username_and_password(
    platform: Platform, users_server: CraneOpcUaServer
) -> None:
    config = crane_config(users_server.url, username="operator", password="s3cret")
    async with running(platform.connector(config)) as connector:
        await connected(connector)
        await values_flow(platform)
        record = await platform.command("set_bridge_speed", value=0.0)
        assert record.state == "succeeded", record.error
    assert not connector.status.errors, connector.status.errors


@pytest.mark.parametrize(
    ("credentials", "message"),
    [
        (
            {"username": "operator", "password": "wrong"},
            "auth_failed: opc.tcp://127.0.0.1:{port}/ilmatar/ refused user 'operator' "
            "(BadUserAccessDenied); its endpoints: None (username); check username and "
            "password",
        ),
        (
            {},
            "auth_failed: opc.tcp://127.0.0.1:{port}/ilmatar/ refused an anonymous session "
            "(BadIdentityTokenRejected); its endpoints: None (username); set username and "
            "password",
        ),
    ],
)
async def test_refused_credentials_show_an_error_and_are_retried(
    platform: Platform,
    users_server: CraneOpcUaServer,
    credentials: dict[str, Any],
    message: str,
) -> None:
    config = crane_config(users_server.url, **credentials)
    async with running(platform.connector(config)) as connector:
        await eventually(lambda: connector.status.errors["auth_failed"] >= 3, "three attempts")
        assert connector.status.state == "error"
        assert connector.status.last_error == message.format(port=users_server.port)
    assert platform.samples() == {}


async def test_sign_and_encrypt_with_a_certificate_from_files(
    platform: Platform, secure_server: CraneOpcUaServer, tmp_path: Path
) -> None:
    cert, key = write_identity(tmp_path, "client", "urn:example:crane-client", password=b"pw")
    config = crane_config(
        secure_server.url,
        security_policy="Basic256Sha256",
        security_mode="SignAndEncrypt",
        certificate=str(cert),
        private_key=str(key),
        private_key_password="pw",
    )
    async with running(platform.connector(config)) as connector:
        await connected(connector)
        await values_flow(platform)
        record = await platform.command("set_bridge_speed", value=0.0)
        assert record.state == "succeeded", record.error


async def test_sign_with_a_generated_certificate(
    platform: Platform, secure_server: CraneOpcUaServer
) -> None:
    config = crane_config(secure_server.url, security_policy="Basic256Sha256", security_mode="Sign")
    async with running(platform.connector(config)) as connector:
        await connected(connector)
        await values_flow(platform)


async def test_no_security_against_a_secured_server_is_an_error(
    platform: Platform, secure_server: CraneOpcUaServer
) -> None:
    async with running(platform.connector(crane_config(secure_server.url))) as connector:
        await eventually(lambda: connector.status.errors["security"] >= 2, "two attempts")
        assert connector.status.state == "error"
        assert connector.status.last_error == (
            f"security: {secure_server.url} offers no endpoint without security (its endpoints: "
            "Basic256Sha256 SignAndEncrypt (anonymous); Basic256Sha256 Sign (anonymous)); set "
            "security_policy"
        )


async def test_a_missing_endpoint_is_named(
    platform: Platform, users_server: CraneOpcUaServer
) -> None:
    config = crane_config(users_server.url, security_policy="Basic256Sha256")
    async with running(platform.connector(config)) as connector:
        await eventually(lambda: connector.status.errors["security"] >= 1, "an attempt")
        assert connector.status.state == "error"
    assert connector.status.last_error == (
        f"security: {users_server.url} offers no endpoint with security_policy Basic256Sha256 "
        "and security_mode SignAndEncrypt (its endpoints: None (username))"
    )
