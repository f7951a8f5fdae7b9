"""The OPC UA connector without a server: what a failed attempt tells the person reading the
status, the client's certificate (from files or generated), and commands it cannot carry out."""

from __future__ import annotations

import asyncio
from pathlib import Path
from typing import Any

import pytest
from asyncua import ua
from asyncua.crypto import cert_gen
from asyncua.ua.status_codes import StatusCodes
from asyncua.ua.uaerrors import UaError, UaStatusCodeError
from cryptography import x509
from cryptography.hazmat.primitives import hashes, serialization
from cryptography.x509.oid import ExtendedKeyUsageOID

from twinlink.connectors.base import ConnectorError, ConnectorTransport
from twinlink.connectors.opcua.client import Failure, explain_failure, load_identity
from twinlink.connectors.opcua.config import OpcUaConfig
from twinlink.connectors.opcua.connector import OpcUaConnector
from twinlink.connectors.opcua.endpoints import (
    ServerCertificateMismatch,
    checked_server_certificate,
)
from twinlink.connectors.opcua.session import FailedNode
from twinlink.domain.records import Device
from twinlink.ingest.link import DeviceLink

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
                 " set username and password, or give a client certificate the server trusts",
                 "error")),
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
         Failure("connect_failed", f"{URL} did not answer within 2.5 s (request_timeout_s)",
                 "reconnecting")),
    ],
)  # fmt: skip
def test_a_failed_attempt_says_what_to_do(
    err: BaseException, fields: dict[str, Any], expected: Failure
) -> None:
    assert explain_failure(err, config(**fields)) == expected


# -- what the server's endpoints take, after it refused a session -------------------------

TOKEN_TYPES = {
    "anonymous": ua.UserTokenType.Anonymous,
    "username": ua.UserTokenType.UserName,
    "certificate": ua.UserTokenType.Certificate,
}


def endpoint(policy: str, mode: ua.MessageSecurityMode, *tokens: str) -> ua.EndpointDescription:
    """An endpoint as GetEndpoints describes it."""
    return ua.EndpointDescription(
        EndpointUrl=URL,
        SecurityMode=mode,
        SecurityPolicyUri=f"http://opcfoundation.org/UA/SecurityPolicy#{policy}",
        UserIdentityTokens=[
            ua.UserTokenPolicy(PolicyId=t, TokenType=TOKEN_TYPES[t]) for t in tokens
        ],
    )


NONE = ua.MessageSecurityMode.None_
SIGN_ENCRYPT = ua.MessageSecurityMode.SignAndEncrypt
USERS_ONLY = [endpoint("None", NONE, "username")]
# asyncua's server-with-encryption example: every token listed, a CertificateUserManager
# deciding by the client's certificate.
KNOWN_CERTIFICATES = [
    endpoint("Basic256Sha256", SIGN_ENCRYPT, "anonymous", "certificate", "username")
]
SECURE = {"security_policy": "Basic256Sha256"}
REFUSED = f"{URL} refused an anonymous session (BadUserAccessDenied); its endpoints: "


@pytest.mark.parametrize(
    ("endpoints", "fields", "generated", "text"),
    [
        (USERS_ONLY, {}, False,
         REFUSED + "None (username); set username and password"),
        (KNOWN_CERTIFICATES, SECURE, True,
         REFUSED + "Basic256Sha256 SignAndEncrypt (anonymous, user certificate, username); it "
         "accepts anonymous sessions only from client certificates it knows, and this one was "
         "generated at start: give certificate and private_key its administrator trusts, or "
         "set username and password"),
        ([endpoint("None", NONE, "anonymous")], {}, False,
         f"{URL} refused an anonymous session (BadUserAccessDenied); its endpoints: None "
         "(anonymous); it accepts anonymous sessions only from client certificates it knows: "
         "set security_policy, and certificate and private_key its administrator trusts"),
        ([endpoint("None", NONE, "certificate")], {}, False,
         REFUSED + "None (user certificate); none of which this connector sends (it sends "
         "anonymous or username)"),
        (KNOWN_CERTIFICATES, {"username": "op", **SECURE}, False,
         f"{URL} refused user 'op' (BadUserAccessDenied); its endpoints: Basic256Sha256 "
         "SignAndEncrypt (anonymous, user certificate, username); check username and "
         "password"),
        ([endpoint("None", NONE, "anonymous")], {"username": "op"}, False,
         f"{URL} refused user 'op' (BadUserAccessDenied); its endpoints: None (anonymous); this"
         " endpoint takes no username: remove username and password"),
    ],
)  # fmt: skip
def test_a_refused_session_says_what_the_endpoints_take(
    endpoints: list[ua.EndpointDescription], fields: dict[str, Any], generated: bool, text: str
) -> None:
    err = status_error(StatusCodes.BadUserAccessDenied)
    failure = explain_failure(err, config(**fields), endpoints, generated)
    assert failure == Failure("auth_failed", text, "error")


def test_a_missing_endpoint_lists_those_there_are() -> None:
    err = UaError("No matching endpoints: 3, http://...")
    failure = explain_failure(err, config(), KNOWN_CERTIFICATES)
    assert failure.text == (
        f"{URL} offers no endpoint without security (its endpoints: Basic256Sha256 "
        "SignAndEncrypt (anonymous, user certificate, username)); set security_policy"
    )


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


async def test_files_changed_since_the_configuration_stop_the_start(tmp_path: Path) -> None:
    # The configuration checked the files (test_opcua_config.py); they are read again at
    # start, as they may have changed since.
    files = write_identity(tmp_path, password=b"pw")
    checked = config(**files, private_key_password="pw")
    (tmp_path / "c").rename(tmp_path / "gone")
    connector = OpcUaConnector("plc", checked, Host())
    with pytest.raises(ConnectorError, match=r"certificate .*/c: No such file"):
        await connector.start()
    (tmp_path / "c").write_text("junk")
    with pytest.raises(ConnectorError, match="is not a PEM or DER certificate"):
        await load_identity(checked)
    write_identity(tmp_path)  # a new certificate, and its key without the password
    (tmp_path / "k").write_bytes(key_of_another_certificate())
    with pytest.raises(ConnectorError, match=r"private_key .*/k does not belong to certificate"):
        await load_identity(checked)


def key_of_another_certificate() -> bytes:
    return serialization.load_pem_private_key(
        cert_gen.dump_private_key_as_pem(cert_gen.generate_private_key()), None
    ).private_bytes(
        serialization.Encoding.PEM,
        serialization.PrivateFormat.PKCS8,
        serialization.BestAvailableEncryption(b"pw"),
    )


def test_a_server_presenting_another_certificate_is_refused_before_anything_is_sent(
    tmp_path: Path,
) -> None:
    presented = self_signed("plc")
    expected = self_signed("plc-before-reinstall")
    (tmp_path / "server.der").write_bytes(expected)
    settings = config(security_policy="Basic256Sha256", server_certificate=tmp_path / "server.der")
    offered = ua.EndpointDescription(ServerCertificate=presented)
    assert checked_server_certificate(offered, settings, presented) == presented
    assert checked_server_certificate(offered, settings, None) == presented
    with pytest.raises(ServerCertificateMismatch) as caught:
        checked_server_certificate(offered, settings, expected)
    failure = explain_failure(caught.value, settings)
    thumbprint = x509.load_der_x509_certificate(presented).fingerprint(hashes.SHA1()).hex()
    assert (failure.kind, failure.state) == ("security", "error")
    assert failure.text.startswith(
        f"{URL}: server certificate does not match: the server presents 'plc' (thumbprint "
        f"{thumbprint.upper()}), server_certificate {tmp_path / 'server.der'} is "
        "'plc-before-reinstall' (thumbprint "
    )
    assert failure.text.endswith(
        "; if the server's certificate was replaced on purpose, set server_certificate to the "
        "new one"
    )


def self_signed(name: str) -> bytes:
    key = cert_gen.generate_private_key()
    san: list[x509.GeneralName] = [x509.UniformResourceIdentifier(f"urn:{name}")]
    cert = cert_gen.generate_self_signed_app_certificate(
        key, name, {}, san, [ExtendedKeyUsageOID.SERVER_AUTH]
    )
    return cert.public_bytes(serialization.Encoding.DER)


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


def test_the_status_lists_the_nodes_not_subscribed_up_to_a_bound() -> None:
    connector = OpcUaConnector("plc", config(), Host())
    failed = [
        FailedNode(f"s{i}", f"ns=2;s=S{i}", f"the server has no node S{i}") for i in range(60)
    ]
    connector.status.nodes_failed(failed)
    view = connector.status.view()
    assert view["failed_nodes"][:2] == [
        {"signal": "s0", "node": "ns=2;s=S0", "reason": "the server has no node S0"},
        {"signal": "s1", "node": "ns=2;s=S1", "reason": "the server has no node S1"},
    ]
    assert [f["signal"] for f in view["failed_nodes"]] == [f"s{i}" for i in range(50)]
    assert view["failed_nodes_more"] == 10
    assert view["errors"] == {"subscribe_failed": 60}
    assert view["last_error"] == "subscribe_failed: s59: the server has no node S59"
    connector.status.nodes_failed([])  # the next session found them all
    assert (connector.status.view()["failed_nodes"], connector.status.failed_nodes_more) == ([], 0)
