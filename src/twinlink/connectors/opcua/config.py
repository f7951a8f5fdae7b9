"""The OPC UA connector's configuration, and the node references it names.

A node is named either by its node id (`ns=2;s=Ilmatar.Bridge.Position`, `i=2258`, or with the
namespace's URI instead of its index: `nsu=http://twinlink.example/ilmatar;s=Ilmatar.Hook.Load`)
or by a browse path from the Objects folder, starting with `/`
(`/2:Ilmatar/2:Bridge/2:Position`). Both are checked here, before any connection; browse paths
and namespace URIs are resolved against the server on each connect.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Literal, Self

from asyncua import ua
from pydantic import BaseModel, ConfigDict, Field, SecretStr, field_validator, model_validator

from twinlink.connectors.opcua.certs import read_certificate, read_key_pair
from twinlink.domain.samples import SIGNAL_NAME, STREAM_NAME

SecurityPolicy = Literal["None", "Basic256Sha256", "Aes128_Sha256_RsaOaep", "Aes256_Sha256_RsaPss"]
SecurityMode = Literal["Sign", "SignAndEncrypt"]
DEFAULT_APPLICATION_URI = "urn:twinlink:opcua-client"
MAX_QUEUE_SIZE = 10_000
HOUR_S = 3600.0  # the longest timeout or wait a setting may ask for
DAY_MS = 86_400_000.0  # the longest sampling or publishing interval


@dataclass(frozen=True, slots=True)
class NodeRef:
    """A node as the configuration names it: exactly one of `node_id` (with the namespace's
    URI in `namespace_uri` when it was given by URI) and `browse_path` is set."""

    text: str
    node_id: ua.NodeId | None = None
    namespace_uri: str | None = None
    browse_path: str | None = None


def parse_node_ref(text: str) -> NodeRef:
    """Read a node reference; raises ValueError saying what is wrong with it."""
    text = text.strip()
    if text.startswith("/"):
        try:
            path = ua.RelativePath.from_string(text)
        except Exception as err:
            raise ValueError(f"browse path {text!r} cannot be read: {err}") from err
        if not path.Elements or any(
            not (e.TargetName and e.TargetName.Name) for e in path.Elements
        ):
            raise ValueError(f"browse path {text!r} names no node (e.g. /2:Ilmatar/2:Bridge)")
        return NodeRef(text, browse_path=text)
    try:
        node_id = ua.NodeId.from_string(text)
    except Exception as err:
        raise ValueError(
            f"{text!r} is neither a node id (ns=2;s=Name, i=2258, nsu=<uri>;s=Name) nor a "
            "browse path starting with / (/2:Ilmatar/2:Bridge/2:Position)"
        ) from err
    uri = node_id.NamespaceUri if isinstance(node_id, ua.ExpandedNodeId) else None
    if uri is not None:
        node_id = ua.NodeId(node_id.Identifier, node_id.NamespaceIndex, node_id.NodeIdType)
    return NodeRef(text, node_id=node_id, namespace_uri=uri)


def _node_text(value: str) -> str:
    parse_node_ref(value)
    return value.strip()


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


class SignalMapping(_Strict):
    """One subscribed node and the signal its values become."""

    node: str = Field(description="Node id or browse path of the variable.")
    signal: str = Field(description="Signal name its values are stored under.")
    sampling_interval_ms: float | None = Field(
        None,
        ge=0,
        le=DAY_MS,
        description="How often the server samples the node; default: the connector's.",
    )
    deadband: float = Field(
        0.0,
        ge=0,
        le=1e300,
        description="Report a change only when it exceeds this (0: every change).",
    )
    deadband_type: Literal["absolute", "percent"] = Field(
        "absolute",
        description="`absolute`: in the node's unit; `percent`: of its EURange (the server "
        "must know the range).",
    )
    queue_size: int | None = Field(
        None,
        ge=1,
        le=MAX_QUEUE_SIZE,
        description="Samples the server keeps between two publishes; default: enough for two "
        "publishing intervals.",
    )

    check_node = field_validator("node")(_node_text)

    @field_validator("signal")
    @classmethod
    def _check_signal(cls, value: str) -> str:
        if not SIGNAL_NAME.match(value):
            raise ValueError(f"signal name {value!r} must match {SIGNAL_NAME.pattern}")
        return value


class WriteCommand(_Strict):
    """A command that writes one of its arguments to a variable."""

    node: str = Field(description="Node id or browse path of the variable to write.")
    arg: str = Field("value", description="The command argument whose value is written.")

    check_node = field_validator("node")(_node_text)


class MethodCommand(_Strict):
    """A command that calls a method, with command arguments as its input arguments."""

    object: str = Field(description="Node id or browse path of the object owning the method.")
    method: str = Field(description="Node id or browse path of the method.")
    args: list[str] = Field(
        default_factory=list, description="Command argument names, in the method's order."
    )

    check_nodes = field_validator("object", "method")(_node_text)


class OpcUaConfig(_Strict):
    """What an OPC UA connector connects to, subscribes to and may write."""

    url: str = Field(description="Endpoint URL, opc.tcp://host:port/path.")
    stream: str = Field("telemetry", description="Stream the samples are stored in.")
    signals: list[SignalMapping] = Field(
        default_factory=list, description="Subscribed nodes and their signal names."
    )
    commands: dict[str, WriteCommand | MethodCommand] = Field(
        default_factory=dict, description="Twin command name -> node write or method call."
    )
    username: str | None = Field(None, description="User for username/password sessions.")
    password: SecretStr | None = Field(None, description="Password of `username`.")
    security_policy: SecurityPolicy = Field(
        "None", description="Secure channel policy; anything but None needs certificates."
    )
    security_mode: SecurityMode = Field(
        "SignAndEncrypt", description="Sign or SignAndEncrypt (ignored with policy None)."
    )
    certificate: Path | None = Field(
        None, description="Client certificate (PEM or DER); none: one is generated at start."
    )
    private_key: Path | None = Field(None, description="Private key (PEM or DER) of it.")
    private_key_password: SecretStr | None = Field(None, description="Password of the key.")
    server_certificate: Path | None = Field(
        None, description="Expected server certificate; none: the one the server presents."
    )
    application_uri: str | None = Field(
        None,
        description="The client's application URI; default: the certificate's, or "
        f"{DEFAULT_APPLICATION_URI}.",
    )
    publishing_interval_ms: float = Field(
        100.0, gt=0, le=DAY_MS, description="How often the server sends the changes it collected."
    )
    sampling_interval_ms: float = Field(
        100.0, ge=0, le=DAY_MS, description="Default sampling interval of each node (0: fastest)."
    )
    batch_max_samples: int = Field(
        1000, ge=1, le=100_000, description="A batch goes to the platform at this many samples..."
    )
    batch_window_ms: float = Field(
        20.0, gt=0, le=10_000, description="...or this long after its first sample."
    )
    request_timeout_s: float = Field(
        5.0,
        gt=0,
        le=HOUR_S,
        description="Timeout of each OPC UA request; a method call may take until its command "
        "expires.",
    )
    watchdog_interval_s: float = Field(
        1.0,
        gt=0,
        le=HOUR_S,
        description="How often the connection is checked by reading the server's state (a "
        "check not answered within request_timeout_s ends the session).",
    )
    reconnect_initial_s: float = Field(
        1.0, gt=0, le=HOUR_S, description="First wait before reconnecting."
    )
    reconnect_max_s: float = Field(
        30.0, gt=0, le=HOUR_S, description="Longest wait between attempts."
    )

    @field_validator("url")
    @classmethod
    def _check_url(cls, value: str) -> str:
        if not value.startswith("opc.tcp://") or len(value) <= len("opc.tcp://"):
            raise ValueError(f"url {value!r} must look like opc.tcp://host:4840/path")
        return value

    @field_validator("stream")
    @classmethod
    def _check_stream(cls, value: str) -> str:
        if not STREAM_NAME.match(value):
            raise ValueError(f"stream {value!r} must match {STREAM_NAME.pattern}")
        return value

    @model_validator(mode="after")
    def _check_together(self) -> Self:
        names = [s.signal for s in self.signals]
        doubled = sorted({n for n in names if names.count(n) > 1})
        if doubled:
            raise ValueError(f"each signal is mapped once; doubled: {', '.join(doubled)}")
        for name in self.commands:
            if not SIGNAL_NAME.match(name):
                raise ValueError(f"command name {name!r} must match {SIGNAL_NAME.pattern}")
        if self.password is not None and self.username is None:
            raise ValueError("a password needs a username")
        if (self.certificate is None) != (self.private_key is None):
            raise ValueError("give both certificate and private_key, or neither (generated)")
        if self.security_policy == "None" and self.certificate is not None:
            raise ValueError("a certificate is used only with a security_policy other than None")
        if self.reconnect_max_s < self.reconnect_initial_s:
            raise ValueError("reconnect_max_s must be at least reconnect_initial_s")
        self._check_files()
        return self

    def _check_files(self) -> None:
        # Read here, so a file that cannot work (missing, not a certificate, a key of another
        # certificate) is a 422 when the connector is created, not a secure channel that
        # fails later with a timeout. CertificateFileError is a ValueError: pydantic reports it.
        if self.certificate is not None and self.private_key is not None:
            password = self.private_key_password
            read_key_pair(
                self.certificate,
                self.private_key,
                password.get_secret_value() if password is not None else None,
            )
        if self.server_certificate is not None:
            read_certificate(self.server_certificate, "server_certificate")

    def queue_size(self, signal: SignalMapping) -> int:
        """The signal's queue size, or enough for two publishing intervals of samples."""
        if signal.queue_size is not None:
            return signal.queue_size
        sampling = self.sampling_ms(signal)
        if sampling <= 0:
            return 100
        return max(1, min(MAX_QUEUE_SIZE, math.ceil(2 * self.publishing_interval_ms / sampling)))

    def sampling_ms(self, signal: SignalMapping) -> float:
        if signal.sampling_interval_ms is None:
            return self.sampling_interval_ms
        return signal.sampling_interval_ms
