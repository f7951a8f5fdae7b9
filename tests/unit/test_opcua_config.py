"""The OPC UA connector's configuration: node references, the checks made before any
connection, derived defaults, and secrets kept out of what is shown."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from asyncua import ua
from asyncua.crypto import cert_gen
from cryptography import x509
from cryptography.hazmat.primitives import serialization
from pydantic import ValidationError

from twinlink.connectors.opcua.config import (
    MethodCommand,
    NodeRef,
    OpcUaConfig,
    WriteCommand,
    parse_node_ref,
)
from twinlink.connectors.opcua.connector import OpcUaConnector

URL = "opc.tcp://plc.example:4840/"


def config(**fields: Any) -> OpcUaConfig:
    return OpcUaConfig.model_validate({"url": URL, **fields})


def problem(**fields: Any) -> str:
    with pytest.raises(ValidationError) as caught:
        config(**fields)
    return str(caught.value)


def node_id(identifier: str | int, namespace: int) -> ua.NodeId:
    wrapped = ua.Int32(identifier) if isinstance(identifier, int) else ua.String(identifier)
    return ua.NodeId(wrapped, ua.Int16(namespace))


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("ns=2;s=Ilmatar.Hook.Load",
         NodeRef("ns=2;s=Ilmatar.Hook.Load", node_id=node_id("Ilmatar.Hook.Load", 2))),
        ("i=2258", NodeRef("i=2258", node_id=node_id(2258, 0))),
        ("nsu=http://x.example/ns;s=Hook.Load",
         NodeRef("nsu=http://x.example/ns;s=Hook.Load", node_id=node_id("Hook.Load", 0),
                 namespace_uri="http://x.example/ns")),
        ("/2:Ilmatar/2:Bridge", NodeRef("/2:Ilmatar/2:Bridge", browse_path="/2:Ilmatar/2:Bridge")),
    ],
)  # fmt: skip
def test_node_references(text: str, expected: NodeRef) -> None:
    assert parse_node_ref(text) == expected


@pytest.mark.parametrize("text", ["Ilmatar.Bridge", "ns=x;s=A", "/", ""])
def test_a_node_reference_that_cannot_be_read_is_refused(text: str) -> None:
    with pytest.raises(ValueError, match=r"node id|browse path"):
        parse_node_ref(text)


def test_commands_are_writes_or_method_calls() -> None:
    parsed = config(
        commands={
            "set_speed": {"node": "ns=2;s=Speed"},
            "stop": {"object": "ns=2;s=Crane", "method": "ns=2;s=Crane.Stop", "args": ["why"]},
        }
    )
    assert parsed.commands == {
        "set_speed": WriteCommand(node="ns=2;s=Speed", arg="value"),
        "stop": MethodCommand(object="ns=2;s=Crane", method="ns=2;s=Crane.Stop", args=["why"]),
    }


@pytest.mark.parametrize(
    ("fields", "text"),
    [
        ({"url": "http://plc:4840"}, "must look like opc.tcp://host:4840/path"),
        ({"stream": "Tele metry"}, "stream 'Tele metry' must match"),
        ({"signals": [{"node": "ns=2;s=A", "signal": "a b"}]}, "signal name 'a b' must match"),
        ({"signals": [{"node": "ns=2;s=A", "signal": "a"}, {"node": "ns=2;s=B", "signal": "a"}]},
         "each signal is mapped once; doubled: a"),
        ({"signals": [{"node": "ns=2;s=A", "signal": "a", "deadband_type": "relative"}]},
         "'absolute' or 'percent'"),
        ({"commands": {"go now": {"node": "ns=2;s=A"}}}, "command name 'go now' must match"),
        ({"commands": {"go": {"node": "ns=2;s=A", "method": "ns=2;s=B"}}}, "Extra inputs"),
        ({"password": "x"}, "a password needs a username"),
        ({"security_policy": "Basic256Sha256", "certificate": "c.pem"},
         "give both certificate and private_key"),
        ({"certificate": "c.pem", "private_key": "k.pem"}, "used only with a security_policy"),
        ({"security_policy": "Basic128Rsa15"}, "Basic256Sha256"),
        ({"reconnect_initial_s": 5, "reconnect_max_s": 1}, "reconnect_max_s must be at least"),
        ({"sampling": 10}, "Extra inputs are not permitted"),
    ],
)  # fmt: skip
def test_what_cannot_work_is_refused_with_the_reason(fields: dict[str, Any], text: str) -> None:
    assert text in problem(**fields)


def test_queue_size_by_default_holds_two_publishing_intervals() -> None:
    parsed = config(
        publishing_interval_ms=100,
        sampling_interval_ms=10,
        signals=[
            {"node": "ns=2;s=A", "signal": "a"},
            {"node": "ns=2;s=B", "signal": "b", "sampling_interval_ms": 1000},
            {"node": "ns=2;s=C", "signal": "c", "queue_size": 7},
            {"node": "ns=2;s=D", "signal": "d", "sampling_interval_ms": 0},
        ],
    )
    assert [parsed.queue_size(s) for s in parsed.signals] == [20, 1, 7, 100]
    assert [parsed.sampling_ms(s) for s in parsed.signals] == [10, 1000, 10, 0]


def test_secrets_are_not_shown() -> None:
    parsed = config(username="operator", password="s3cret", security_policy="Basic256Sha256")
    assert "s3cret" not in repr(parsed)
    assert "s3cret" not in parsed.model_dump_json()
    assert parsed.password is not None and parsed.password.get_secret_value() == "s3cret"


def test_the_connector_declares_its_kind_and_config() -> None:
    assert OpcUaConnector.kind == "opcua"
    assert OpcUaConnector.Config is OpcUaConfig
    schema = OpcUaConfig.model_json_schema()
    documented = {name for name, prop in schema["properties"].items() if prop.get("description")}
    assert documented == set(schema["properties"])


# -- certificate files, read when the configuration is checked ------------------------------


def write_pair(folder: Path, name: str, password: bytes | None = None) -> tuple[Path, Path]:
    key = cert_gen.generate_private_key()
    san: list[x509.GeneralName] = [x509.UniformResourceIdentifier(f"urn:example:{name}")]
    cert = cert_gen.generate_self_signed_app_certificate(key, name, {}, san, [])
    cert_path, key_path = folder / f"{name}.pem", folder / f"{name}.key"
    cert_path.write_bytes(cert.public_bytes(serialization.Encoding.PEM))
    protect = serialization.BestAvailableEncryption(password) if password else None
    key_path.write_bytes(
        key.private_bytes(
            serialization.Encoding.PEM,
            serialization.PrivateFormat.PKCS8,
            protect or serialization.NoEncryption(),
        )
    )
    return cert_path, key_path


def test_a_private_key_of_another_certificate_is_refused(tmp_path: Path) -> None:
    cert, key = write_pair(tmp_path, "client", b"pw")
    _, other_key = write_pair(tmp_path, "other")
    secure = {"security_policy": "Basic256Sha256", "certificate": str(cert)}
    assert config(**secure, private_key=str(key), private_key_password="pw").certificate == cert
    assert (
        f"private_key {other_key} does not belong to certificate {cert}: their public keys "
        "differ (give the key the certificate was issued for)"
    ) in problem(**secure, private_key=str(other_key))


@pytest.mark.parametrize(
    ("change", "text"),
    [
        ({"certificate": "gone.pem"}, "certificate gone.pem: No such file or directory"),
        (
            {"private_key_password": "wrong"},
            "private_key client.key cannot be read (PEM or DER; is private_key_password right?)",
        ),
        ({"certificate": "junk"}, "certificate junk is not a PEM or DER certificate"),
        ({"server_certificate": "junk"}, "server_certificate junk is not a PEM or DER"),
        ({"server_certificate": "gone.der"}, "server_certificate gone.der: No such file"),
    ],
)
def test_certificate_files_that_cannot_be_used_are_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, change: dict[str, str], text: str
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "junk").write_text("junk")
    cert, key = write_pair(tmp_path, "client", b"pw")
    fields = {"security_policy": "Basic256Sha256", "certificate": cert.name,
              "private_key": key.name, "private_key_password": "pw"}  # fmt: skip
    assert text in problem(**{**fields, **change})
