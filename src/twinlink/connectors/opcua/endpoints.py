"""What an OPC UA server's endpoints offer, from GetEndpoints (asked over a channel without
security, as the standard allows any client to): the endpoint the connector's security
settings pick and the certificate it presents, and, when the server refuses a session, what
its endpoints take instead, so the status can say what to set.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from asyncua import ua
from asyncua.client.client import Client
from asyncua.crypto import security_policies
from asyncua.ua.uaerrors import UaError
from cryptography import x509

from twinlink.connectors.opcua.certs import describe, first_certificate
from twinlink.connectors.opcua.config import OpcUaConfig
from twinlink.domain.errors import TwinlinkError

POLICIES: dict[str, type[security_policies.SecurityPolicy]] = {
    "Basic256Sha256": security_policies.SecurityPolicyBasic256Sha256,
    "Aes128_Sha256_RsaOaep": security_policies.SecurityPolicyAes128Sha256RsaOaep,
    "Aes256_Sha256_RsaPss": security_policies.SecurityPolicyAes256Sha256RsaPss,
}
MODES = {
    "Sign": ua.MessageSecurityMode.Sign,
    "SignAndEncrypt": ua.MessageSecurityMode.SignAndEncrypt,
}
TOKENS = {
    ua.UserTokenType.Anonymous: "anonymous",
    ua.UserTokenType.UserName: "username",
    ua.UserTokenType.Certificate: "user certificate",
    ua.UserTokenType.IssuedToken: "issued token",
}
_POLICY_PREFIX = "http://opcfoundation.org/UA/SecurityPolicy#"
_MODE_NAMES = {
    ua.MessageSecurityMode.None_: "",
    ua.MessageSecurityMode.Sign: " Sign",
    ua.MessageSecurityMode.SignAndEncrypt: " SignAndEncrypt",
}


class ServerCertificateMismatch(TwinlinkError, UaError):
    """The server presents a certificate other than the configured `server_certificate`."""

    def __init__(self, presented: x509.Certificate, expected: x509.Certificate, path: Path):
        super().__init__("server certificate does not match")
        self.presented = presented
        self.expected = expected
        self.path = path

    def explain(self) -> str:
        return (
            f"server certificate does not match: the server presents {describe(self.presented)}"
            f", server_certificate {self.path} is {describe(self.expected)}; if the server's "
            "certificate was replaced on purpose, set server_certificate to the new one"
        )


async def get_endpoints(config: OpcUaConfig) -> list[ua.EndpointDescription]:
    """The server's endpoints; raises what connecting raises (OSError, TimeoutError, ...)."""
    client = Client(config.url, timeout=config.request_timeout_s)
    return await client.connect_and_get_server_endpoints()


def pick_endpoint(
    endpoints: Sequence[ua.EndpointDescription], config: OpcUaConfig
) -> ua.EndpointDescription:
    """The endpoint of the configured policy and mode; raises UaError("No matching endpoints
    ...") as asyncua does, which explain_failure turns into what is offered."""
    return Client.find_endpoint(
        endpoints, MODES[config.security_mode], POLICIES[config.security_policy].URI
    )


def checked_server_certificate(
    endpoint: ua.EndpointDescription, config: OpcUaConfig, expected: bytes | None
) -> bytes:
    """The DER certificate `endpoint` presents, refused (ServerCertificateMismatch) when it is
    not the configured one: without this check the client would encrypt for a key the server
    does not have, and the server would drop the channel without a word (a timeout)."""
    presented = first_certificate(endpoint.ServerCertificate or b"")
    if expected is not None and presented != expected:
        assert config.server_certificate is not None
        raise ServerCertificateMismatch(
            x509.load_der_x509_certificate(presented),
            x509.load_der_x509_certificate(expected),
            config.server_certificate,
        )
    return presented


def offered(endpoints: Sequence[ua.EndpointDescription]) -> str:
    """The endpoints as a person reads them: `None (username); Basic256Sha256 Sign
    (anonymous, username, user certificate)`."""
    parts: list[str] = []
    for endpoint in endpoints:
        policy = (endpoint.SecurityPolicyUri or "").removeprefix(_POLICY_PREFIX) or "None"
        mode = _MODE_NAMES.get(endpoint.SecurityMode, f" {endpoint.SecurityMode}")
        tokens = ", ".join(dict.fromkeys(_token_names(endpoint))) or "no user tokens"
        part = f"{policy}{mode} ({tokens})"
        if part not in parts:
            parts.append(part)
    return "; ".join(parts) or "no endpoints"


def _token_names(endpoint: ua.EndpointDescription) -> list[str]:
    return [
        TOKENS.get(token.TokenType, str(token.TokenType))
        for token in endpoint.UserIdentityTokens or []
    ]


def _takes(endpoint: ua.EndpointDescription, token: ua.UserTokenType) -> bool:
    return any(t.TokenType == token for t in endpoint.UserIdentityTokens or [])


def refused_session_hint(
    endpoints: Sequence[ua.EndpointDescription], config: OpcUaConfig, generated: bool
) -> str:
    """What to change after the server refused the session, from what its endpoints take.

    A server may list anonymous sessions and still refuse them: asyncua's
    CertificateUserManager (its server-with-encryption example) and servers with a trust
    list accept a session only from a client certificate they know."""
    takes = f"its endpoints: {offered(endpoints)}"
    endpoint = endpoint_for(endpoints, config)
    if endpoint is None:
        return takes
    users = _takes(endpoint, ua.UserTokenType.UserName)
    if config.username is not None:
        if not users:
            return f"{takes}; this endpoint takes no username: remove username and password"
        return f"{takes}; check username and password"
    if not _takes(endpoint, ua.UserTokenType.Anonymous):
        if users:
            return f"{takes}; set username and password"
        return f"{takes}; none of which this connector sends (it sends anonymous or username)"
    # Anonymous sessions are offered, yet this one was refused: the client certificate decides.
    if config.security_policy == "None":
        advice = (
            "it accepts anonymous sessions only from client certificates it knows: set "
            "security_policy, and certificate and private_key its administrator trusts"
        )
    elif generated:
        advice = (
            "it accepts anonymous sessions only from client certificates it knows, and this "
            "one was generated at start: give certificate and private_key its administrator "
            "trusts"
        )
    else:
        advice = (
            f"it does not accept the client certificate {config.certificate} for anonymous "
            "sessions: have its administrator trust it"
        )
    return f"{takes}; {advice}" + (", or set username and password" if users else "")


def endpoint_for(
    endpoints: Sequence[ua.EndpointDescription], config: OpcUaConfig
) -> ua.EndpointDescription | None:
    """The endpoint the settings pick, None when the server has none like it."""
    if config.security_policy == "None":
        for endpoint in endpoints:
            if endpoint.SecurityMode == ua.MessageSecurityMode.None_:
                return endpoint
        return None
    try:
        return pick_endpoint(endpoints, config)
    except UaError:
        return None
