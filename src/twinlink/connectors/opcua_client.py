"""Making the asyncua client of an OPC UA connector: its identity (user, certificate), its
security, and what a failed connection attempt means for the person reading the status."""

from __future__ import annotations

import asyncio
import socket
from dataclasses import dataclass
from pathlib import Path

from asyncua import ua
from asyncua.client.client import Client
from asyncua.crypto import cert_gen, security_policies
from asyncua.crypto.uacrypto import CertProperties
from asyncua.ua.status_codes import get_name_and_doc
from asyncua.ua.uaerrors import UaError, UaStatusCodeError
from cryptography import x509
from cryptography.hazmat.primitives import serialization
from cryptography.x509.oid import ExtendedKeyUsageOID

from twinlink.connectors.base import ConnectorError
from twinlink.connectors.opcua_config import DEFAULT_APPLICATION_URI, OpcUaConfig

SESSION_TIMEOUT_MS = 60_000  # a session the connector left behind is dropped after this
POLICIES: dict[str, type[security_policies.SecurityPolicy]] = {
    "Basic256Sha256": security_policies.SecurityPolicyBasic256Sha256,
    "Aes128_Sha256_RsaOaep": security_policies.SecurityPolicyAes128Sha256RsaOaep,
    "Aes256_Sha256_RsaPss": security_policies.SecurityPolicyAes256Sha256RsaPss,
}
MODES = {
    "Sign": ua.MessageSecurityMode.Sign,
    "SignAndEncrypt": ua.MessageSecurityMode.SignAndEncrypt,
}
AUTH_CODES = {"BadUserAccessDenied", "BadIdentityTokenRejected", "BadIdentityTokenInvalid"}
SECURITY_CODES = {
    "BadSecurityChecksFailed",
    "BadSecurityPolicyRejected",
    "BadSecurityModeRejected",
    "BadSecurityModeInsufficient",
}


@dataclass(frozen=True, slots=True)
class ClientIdentity:
    """The client's application instance certificate and key (PEM, key unencrypted, in
    memory only) and the application URI that goes with them."""

    certificate: bytes
    private_key: bytes
    application_uri: str
    generated: bool


async def load_identity(config: OpcUaConfig) -> ClientIdentity | None:
    """The identity for a secure channel: from the configured files, or generated; None with
    security policy None. Raises ConnectorError when the files cannot be used."""
    if config.security_policy == "None":
        return None
    if config.certificate is None or config.private_key is None:
        uri = config.application_uri or DEFAULT_APPLICATION_URI
        return await asyncio.to_thread(_generate_identity, uri)
    password = config.private_key_password
    return await asyncio.to_thread(
        _read_identity,
        config.certificate,
        config.private_key,
        password.get_secret_value() if password else None,
        config.application_uri,
    )


def _generate_identity(application_uri: str) -> ClientIdentity:
    key = cert_gen.generate_private_key()
    host = socket.gethostname()
    cert = cert_gen.generate_self_signed_app_certificate(
        key,
        "twinlink OPC UA connector",
        {},
        [x509.UniformResourceIdentifier(application_uri), x509.DNSName(host)],
        [ExtendedKeyUsageOID.CLIENT_AUTH],
    )
    return ClientIdentity(
        cert.public_bytes(serialization.Encoding.PEM),
        cert_gen.dump_private_key_as_pem(key),
        application_uri,
        generated=True,
    )


def _read_identity(
    cert_path: Path, key_path: Path, password: str | None, application_uri: str | None
) -> ClientIdentity:
    cert = read_certificate(cert_path)
    try:
        data = key_path.read_bytes()
    except OSError as err:
        raise ConnectorError(f"private_key {key_path}: {err.strerror or err}") from err
    secret = password.encode() if password else None
    try:
        if b"-----BEGIN" in data:
            key = serialization.load_pem_private_key(data, secret)
        else:
            key = serialization.load_der_private_key(data, secret)
    except (ValueError, TypeError) as err:
        raise ConnectorError(
            f"private_key {key_path} cannot be read (PEM or DER; is private_key_password "
            f"right?): {err}"
        ) from err
    key_pem = key.private_bytes(
        serialization.Encoding.PEM,
        serialization.PrivateFormat.PKCS8,
        serialization.NoEncryption(),
    )
    uri = application_uri or _certificate_uri(cert) or DEFAULT_APPLICATION_URI
    return ClientIdentity(
        cert.public_bytes(serialization.Encoding.PEM), key_pem, uri, generated=False
    )


def read_certificate(path: Path) -> x509.Certificate:
    """A certificate file, PEM or DER; raises ConnectorError saying why it cannot be used."""
    try:
        data = path.read_bytes()
    except OSError as err:
        raise ConnectorError(f"certificate {path}: {err.strerror or err}") from err
    try:
        if b"-----BEGIN" in data:
            return x509.load_pem_x509_certificate(data)
        return x509.load_der_x509_certificate(data)
    except ValueError as err:
        raise ConnectorError(f"{path} is not a PEM or DER certificate: {err}") from err


def _certificate_uri(cert: x509.Certificate) -> str | None:
    # OPC UA clients are known to servers by the URI in their certificate's subjectAltName.
    try:
        names = cert.extensions.get_extension_for_class(x509.SubjectAlternativeName).value
    except x509.ExtensionNotFound:
        return None
    uris = names.get_values_for_type(x509.UniformResourceIdentifier)
    return uris[0] if uris else None


async def new_client(
    config: OpcUaConfig, identity: ClientIdentity | None, server_certificate: bytes | None
) -> Client:
    """A client ready to connect (for a secured channel, without a server certificate given,
    this asks the server for its endpoints first)."""
    client = Client(
        config.url,
        timeout=config.request_timeout_s,
        watchdog_intervall=config.watchdog_interval_s,
    )
    client.name = client.description = "twinlink OPC UA connector"
    client.product_uri = "urn:twinlink"
    client.application_uri = config.application_uri or DEFAULT_APPLICATION_URI
    client.session_timeout = SESSION_TIMEOUT_MS
    if config.username is not None:
        client.set_user(config.username)
        if config.password is not None:
            client.set_password(config.password.get_secret_value())
    if identity is not None:
        client.application_uri = identity.application_uri
        await client.set_security(
            POLICIES[config.security_policy],
            CertProperties(identity.certificate, "pem"),
            CertProperties(identity.private_key, "pem"),
            server_certificate=(
                None if server_certificate is None else CertProperties(server_certificate, "der")
            ),
            mode=MODES[config.security_mode],
        )
    return client


def server_certificate_der(config: OpcUaConfig) -> bytes | None:
    if config.server_certificate is None:
        return None
    cert = read_certificate(config.server_certificate)
    return cert.public_bytes(serialization.Encoding.DER)


@dataclass(frozen=True, slots=True)
class Failure:
    """Why an attempt failed: an error kind for the status, its text, and the state to show
    while retrying (`error` when a person has to change something, else `reconnecting`)."""

    kind: str
    text: str
    state: str


def explain_failure(err: BaseException, config: OpcUaConfig) -> Failure:
    url = config.url
    if isinstance(err, UaStatusCodeError):
        name = status_name(err)
        if name in AUTH_CODES:
            if config.username is None:
                text = f"{url} refused an anonymous session ({name}); set username and password"
            else:
                text = (
                    f"{url} refused user {config.username!r} ({name}); check username and password"
                )
            return Failure("auth_failed", text, "error")
        if name in SECURITY_CODES or name.startswith("BadCertificate"):
            text = (
                f"{url} refused the secure channel ({name}); check security_policy, "
                "security_mode and that the server trusts the client certificate"
            )
            return Failure("security", text, "error")
        return Failure("connect_failed", f"{url} refused the connection ({name})", "reconnecting")
    if isinstance(err, UaError) and "No matching endpoints" in str(err):
        if config.security_policy == "None":
            text = f"{url} offers no endpoint without security; set security_policy"
        else:
            text = (
                f"{url} offers no endpoint with security_policy {config.security_policy} and "
                f"security_mode {config.security_mode}"
            )
        return Failure("security", text, "error")
    if isinstance(err, TimeoutError):
        text = f"{url} did not answer within {config.request_timeout_s:g} s"
        return Failure("connect_failed", text, "reconnecting")
    if isinstance(err, ConnectionRefusedError):
        text = f"cannot reach {url}: connection refused (is the server running?)"
        return Failure("connect_failed", text, "reconnecting")
    if isinstance(err, OSError):
        reason = err.strerror or str(err) or type(err).__name__
        return Failure("connect_failed", f"cannot reach {url}: {reason}", "reconnecting")
    text = f"{url}: {err or type(err).__name__}"
    return Failure("connect_failed", text, "reconnecting")


def status_name(err: UaStatusCodeError) -> str:
    code = getattr(err, "code", None)
    if isinstance(code, int):
        name, _ = get_name_and_doc(code)
        return str(name)
    return type(err).__name__
