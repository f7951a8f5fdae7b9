"""The OPC UA connector without a server: what a failed attempt tells the person reading the
status, the client's certificate (from files or generated), and commands it cannot carry out."""

from __future__ import annotations

import asyncio
from pathlib import Path
from typing import Any

import pytest
from asyncua.crypto import cert_gen
from asyncua.ua.status_codes import StatusCodes
from asyncua.ua.uaerrors import UaError, UaStatusCodeError
from cryptography import x509
from cryptography.hazmat.primitives import serialization
from cryptography.x509.oid import ExtendedKeyUsageOID

from twinlink.connectors.base import ConnectorError, ConnectorTransport
from twinlink.connectors.opcua import OpcUaConnector
from twinlink.connectors.opcua_client import Failure, explain_failure, load_identity
from twinlink.connectors.opcua_config import OpcUaConfig
from twinlink.ingest.link import DeviceLink
from twinlink.store.records import Device

URL = "opc.tcp://plc.example:4840/"


def config(**fields: Any) -> OpcUaConfig:
    return OpcUaConfig.model_validate({"url": URL, **fields})


def status_error(code: int) -> UaStatusCodeError:
    return UaStatusCodeError(code)  # type: ignore[no-untyped-call]


@pytest.mark.parametrize(
    ("err", "fields", "expected"),
    [
        (status_error(StatusCodes.BadUserAccessDenied), {"username": "op"},
         Failure("auth_failed", f"{URL} refused user 'op' (BadUserAccessDenied); check "
                 "username and password", "error")),
        (status_error(StatusCodes.BadIdentityTokenRejected), {},
         Failure("auth_failed", f"{URL} refused an anonymous session (BadIdentityTokenRejected);"
                 " set username and password", "error")),
        (status_error(StatusCodes.BadCertificateUntrusted), {},
         Failure("security", f"{URL} refused the secure channel (BadCertificateUntrusted); check"
                 " security_policy, security_mode and that the server trusts the client "
                 "certificate", "error")),
        (UaError("No matching endpoints: 3, http://..."), {"security_policy": "Basic256Sha256"},
         Failure("security", f"{URL} offers no endpoint with security_policy Basic256Sha256 and "
                 "security_mode SignAndEncrypt", "error")),
        (status_error(StatusCodes.BadTooManySessions), {},
         Failure("connect_failed", f"{URL} refused the connection (BadTooManySessions)",
                 "reconnecting")),
        (ConnectionRefusedError(111, "Connection refused"), {},
         Failure("connect_failed", f"cannot reach {URL}: connection refused (is the server "
                 "running?)", "reconnecting")),
        (OSError(113, "No route to host"), {},
         Failure("connect_failed", f"cannot reach {URL}: No route to host", "reconnecting")),
        (TimeoutError(), {"request_timeout_s": 2.5},
         Failure("connect_failed", f"{URL} did not answer within 2.5 s", "reconnecting")),
    ],
)  # fmt: skip
def test_a_failed_attempt_says_what_to_do(
    err: BaseException, fields: dict[str, Any], expected: Failure
) -> None:
    assert explain_failure(err, config(**fields)) == expected


async def test_no_identity_without_security_and_a_generated_one_with() -> None:
    assert await load_identity(config()) is None
    identity = await load_identity(config(security_policy="Basic256Sha256"))
    assert identity is not None and identity.generated
    cert = x509.load_pem_x509_certificate(identity.certificate)
    uris = cert.extensions.get_extension_for_class(x509.SubjectAlternativeName).value
    assert uris.get_values_for_type(x509.UniformResourceIdentifier) == ["urn:twinlink:opcua-client"]
    assert identity.application_uri == "urn:twinlink:opcua-client"
    serialization.load_pem_private_key(identity.private_key, None)


def write_identity(folder: Path, *, der: bool = False, password: bytes | None = None) -> Any:
    key = cert_gen.generate_private_key()
    san: list[x509.GeneralName] = [x509.UniformResourceIdentifier("urn:example:plc-client")]
    cert = cert_gen.generate_self_signed_app_certificate(
        key, "client", {}, san, [ExtendedKeyUsageOID.CLIENT_AUTH]
    )
    encoding = serialization.Encoding.DER if der else serialization.Encoding.PEM
    protect = serialization.BestAvailableEncryption(password) if password else None
    (folder / "c").write_bytes(cert.public_bytes(encoding))
    (folder / "k").write_bytes(
        key.private_bytes(
            encoding,
            serialization.PrivateFormat.PKCS8,
            protect or serialization.NoEncryption(),
        )
    )
    return {"security_policy": "Basic256Sha256", "certificate": folder / "c",
            "private_key": folder / "k"}  # fmt: skip


@pytest.mark.parametrize("der", [False, True])
async def test_an_identity_from_files_takes_the_certificates_uri(tmp_path: Path, der: bool) -> None:
    files = write_identity(tmp_path, der=der, password=b"pw")
    identity = await load_identity(config(**files, private_key_password="pw"))
    assert identity is not None and not identity.generated
    assert identity.application_uri == "urn:example:plc-client"
    assert identity.certificate.startswith(b"-----BEGIN CERTIFICATE")


async def test_files_that_cannot_be_used_stop_the_start(tmp_path: Path) -> None:
    files = write_identity(tmp_path, password=b"pw")
    with pytest.raises(ConnectorError, match="is private_key_password right"):
        await load_identity(config(**files, private_key_password="wrong"))
    connector = OpcUaConnector("plc", config(**{**files, "certificate": tmp_path / "gone"}), Host())
    with pytest.raises(ConnectorError, match=r"certificate .*gone: No such file"):
        await connector.start()
    (tmp_path / "junk").write_text("junk")
    with pytest.raises(ConnectorError, match="is not a PEM or DER certificate"):
        await load_identity(config(**{**files, "certificate": tmp_path / "junk"}))


# -- commands without a connection -------------------------------------------------------


class Host:
    """A device nobody ever connects (the connector is not run in these tests)."""

    device = Device(1, 1, "crane", "plc", "", "tld_x", 0, None)

    async def connect(self, transport: ConnectorTransport) -> DeviceLink:
        raise AssertionError("not connected in these tests")

    async def disconnect(self, link: DeviceLink) -> None:
        raise AssertionError("not connected in these tests")


async def test_commands_it_cannot_carry_out_are_answered_once_each() -> None:
    commands = {"stop": {"object": "ns=2;s=Crane", "method": "ns=2;s=Crane.Stop"}}
    connector = OpcUaConnector("plc", config(commands=commands), Host())
    answers: list[tuple[str, Any, str | None]] = []

    async def answer(command_id: str, result: Any = None, error: str | None = None) -> None:
        answers.append((command_id, result, error))

    connector.answer = answer  # type: ignore[method-assign]
    for count, (command_id, name) in enumerate(
        (("c1", "explode"), ("c2", "stop"), ("c1", "explode")), start=1
    ):
        await connector.on_message({"type": "command", "id": command_id, "name": name})
        async with asyncio.timeout(5):
            while len(answers) < count:  # each runs in a task of its own
                await asyncio.sleep(0)
    await connector.on_message({"type": "desired", "properties": {"x": 1}})  # not for a PLC
    unknown = "no command 'explode' in this OPC UA connector; it knows: stop"
    offline = "not connected to the OPC UA server (stopped); try again when connected"
    assert answers == [("c1", None, unknown), ("c2", None, offline), ("c1", None, unknown)]
    assert connector.status.errors["command_failed"] == 2  # the repeat is answered, not rerun
