"""Making the asyncua client of an OPC UA connector: its identity (user, certificate), its
security, and what a failed connection attempt means for the person reading the status."""

from __future__ import annotations

import asyncio
import socket
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from asyncua import ua
from asyncua.client.client import Client
from asyncua.crypto import cert_gen
from asyncua.crypto.uacrypto import CertProperties
from asyncua.ua.status_codes import get_name_and_doc
from asyncua.ua.uaerrors import UaError, UaStatusCodeError
from cryptography import x509
from cryptography.hazmat.primitives import serialization
from cryptography.x509.oid import ExtendedKeyUsageOID

from twinlink.connectors.base import ConnectorError
from twinlink.connectors.opcua.certs import CertificateFileError, read_certificate, read_key_pair
from twinlink.connectors.opcua.config import DEFAULT_APPLICATION_URI, OpcUaConfig
from twinlink.connectors.opcua.endpoints import (
    MODES,
    POLICIES,
    ServerCertificateMismatch,
    checked_server_certificate,
    get_endpoints,
    offered,
    pick_endpoint,
    refused_session_hint,
)

SESSION_TIMEOUT_MS = 60_000  # a session the connector left behind is dropped after this
# asyncua's watchdog reads the server's state every `watchdog_intervall` with a timeout of that
# interval, and a server may answer a session's requests one at a time (asyncua's does): a
# method call longer than the interval ended the session. The connector checks the server
# itself (OpcUaConnector._watch, which waits for calls in flight), so asyncua's periodic read
# is put off for good; asyncua still notices a closed connection at once.
ASYNCUA_WATCHDOG_S = 1e9
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
    try:
        cert, key = read_key_pair(cert_path, key_path, password)
    except CertificateFileError as err:
        raise ConnectorError(str(err)) from err
    key_pem = key.private_bytes(
        serialization.Encoding.PEM,
        serialization.PrivateFormat.PKCS8,
        serialization.NoEncryption(),
    )
    uri = application_uri or _certificate_uri(cert) or DEFAULT_APPLICATION_URI
    return ClientIdentity(
        cert.public_bytes(serialization.Encoding.PEM), key_pem, uri, generated=False
    )


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
    """A client ready to connect. For a secured channel this asks the server for its
    endpoints first, and refuses a server that presents another certificate than
    `server_certificate` (ServerCertificateMismatch) before anything is sent to it."""
    client = Client(
        config.url, timeout=config.request_timeout_s, watchdog_intervall=ASYNCUA_WATCHDOG_S
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
        endpoint = pick_endpoint(await get_endpoints(config), config)
        presented = checked_server_certificate(endpoint, config, server_certificate)
        client.application_uri = identity.application_uri
        await client.set_security(
            POLICIES[config.security_policy],
            CertProperties(identity.certificate, "pem"),
            CertProperties(identity.private_key, "pem"),
            server_certificate=CertProperties(presented, "der"),
            mode=MODES[config.security_mode],
        )
    return client


def server_certificate_der(config: OpcUaConfig) -> bytes | None:
    if config.server_certificate is None:
        return None
    try:
        cert = read_certificate(config.server_certificate, "server_certificate")
    except CertificateFileError as err:
        raise ConnectorError(str(err)) from err
    return cert.public_bytes(serialization.Encoding.DER)


@dataclass(frozen=True, slots=True)
class Failure:
    """Why an attempt failed: an error kind for the status, its text, and the state to show
    while retrying (`error` when a person has to change something, else `reconnecting`)."""

    kind: str
    text: str
    state: str


async def explain_attempt(
    err: BaseException, config: OpcUaConfig, identity: ClientIdentity | None
) -> Failure:
    """What a failed attempt means; when the server refused the session or has no endpoint
    like the settings, its endpoints are asked (GetEndpoints) to say what it takes instead."""
    failure = explain_failure(err, config)
    if failure.kind != "auth_failed" and not _no_matching_endpoint(err):
        return failure
    try:
        async with asyncio.timeout(config.request_timeout_s):
            endpoints = await get_endpoints(config)
    except (OSError, TimeoutError, UaError):
        return failure  # the first explanation stands
    generated = identity is not None and identity.generated
    return explain_failure(err, config, endpoints, generated)


def explain_failure(
    err: BaseException,
    config: OpcUaConfig,
    endpoints: Sequence[ua.EndpointDescription] | None = None,
    generated: bool = False,
) -> Failure:
    """What a failed attempt means for the person reading the status; `endpoints` (when they
    could be read) tell what the server takes instead of what it refused."""
    url = config.url
    if isinstance(err, ServerCertificateMismatch):
        return Failure("security", f"{url}: {err.explain()}", "error")
    if isinstance(err, UaStatusCodeError):
        name = status_name(err)
        if name in AUTH_CODES:
            return Failure("auth_failed", _refused_session(name, config, endpoints, generated),
                           "error")  # fmt: skip
        if name in SECURITY_CODES or name.startswith("BadCertificate"):
            text = (
                f"{url} refused the secure channel ({name}); check security_policy, "
                "security_mode and that the server trusts the client certificate"
            )
            return Failure("security", text, "error")
        return Failure("connect_failed", f"{url} refused the connection ({name})", "reconnecting")
    if _no_matching_endpoint(err):
        listed = "" if endpoints is None else f" (its endpoints: {offered(endpoints)})"
        if config.security_policy == "None":
            text = f"{url} offers no endpoint without security{listed}; set security_policy"
        else:
            text = (
                f"{url} offers no endpoint with security_policy {config.security_policy} and "
                f"security_mode {config.security_mode}{listed}"
            )
        return Failure("security", text, "error")
    return _unreachable(err, config)


def _no_matching_endpoint(err: BaseException) -> bool:
    # asyncua's Client.find_endpoint raises a bare UaError with this text.
    return isinstance(err, UaError) and "No matching endpoints" in str(err)


def _refused_session(
    name: str,
    config: OpcUaConfig,
    endpoints: Sequence[ua.EndpointDescription] | None,
    generated: bool,
) -> str:
    who = "an anonymous session" if config.username is None else f"user {config.username!r}"
    if endpoints is not None:
        hint = refused_session_hint(endpoints, config, generated)
    elif config.username is None:
        hint = "set username and password, or give a client certificate the server trusts"
    else:
        hint = "check username and password"
    return f"{config.url} refused {who} ({name}); {hint}"


def _unreachable(err: BaseException, config: OpcUaConfig) -> Failure:
    url = config.url
    if isinstance(err, TimeoutError):
        text = f"{url} did not answer within {config.request_timeout_s:g} s (request_timeout_s)"
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
