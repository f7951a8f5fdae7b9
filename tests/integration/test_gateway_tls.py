"""https:// services: the certificate is checked against the system's CAs, or a private CA
given in the service's `tls.ca_pem`; `tls.verify: false` accepts any certificate."""

from __future__ import annotations

import asyncio
import datetime
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import uvicorn
from cryptography import x509
from cryptography.hazmat.primitives import hashes, serialization
from cryptography.hazmat.primitives.asymmetric import ec
from cryptography.x509.oid import NameOID

from tests.conftest import Server
from tests.integration._gateway import add_service, new_twin, server  # noqa: F401 (fixture)

pytestmark = pytest.mark.integration


def _name(common: str) -> x509.Name:
    return x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, common)])


def make_ca_and_cert(folder: Path) -> tuple[str, Path, Path]:
    """A private CA (its PEM) and a server certificate for DNS name `localhost` only."""
    now = datetime.datetime.now(datetime.UTC)
    ca_key = ec.generate_private_key(ec.SECP256R1())
    ca = (
        x509.CertificateBuilder()
        .subject_name(_name("twinlink test CA"))
        .issuer_name(_name("twinlink test CA"))
        .public_key(ca_key.public_key())
        .serial_number(x509.random_serial_number())
        .not_valid_before(now)
        .not_valid_after(now + datetime.timedelta(days=1))
        .add_extension(x509.BasicConstraints(ca=True, path_length=None), critical=True)
        .sign(ca_key, hashes.SHA256())
    )
    key = ec.generate_private_key(ec.SECP256R1())
    cert = (
        x509.CertificateBuilder()
        .subject_name(_name("localhost"))
        .issuer_name(ca.subject)
        .public_key(key.public_key())
        .serial_number(x509.random_serial_number())
        .not_valid_before(now)
        .not_valid_after(now + datetime.timedelta(days=1))
        .add_extension(x509.SubjectAlternativeName([x509.DNSName("localhost")]), critical=False)
        .sign(ca_key, hashes.SHA256())
    )
    cert_file, key_file = folder / "cert.pem", folder / "key.pem"
    cert_file.write_bytes(cert.public_bytes(serialization.Encoding.PEM))
    key_file.write_bytes(
        key.private_bytes(
            serialization.Encoding.PEM,
            serialization.PrivateFormat.PKCS8,
            serialization.NoEncryption(),
        )
    )
    return ca.public_bytes(serialization.Encoding.PEM).decode(), cert_file, key_file


async def hello(scope: dict[str, Any], receive: Any, send: Any) -> None:
    assert scope["type"] == "http"
    body = b'{"over": "tls"}'
    await send(
        {
            "type": "http.response.start",
            "status": 200,
            "headers": [(b"content-type", b"application/json")],
        }
    )
    await send({"type": "http.response.body", "body": body})


@pytest.fixture(scope="module")
def tls_upstream(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[str, int]]:
    """(the CA's PEM, the port of an https server with a certificate for `localhost`)."""
    ca_pem, cert, key = make_ca_and_cert(tmp_path_factory.mktemp("tls"))
    config = uvicorn.Config(
        hello,
        host="127.0.0.1",
        port=0,
        lifespan="off",
        log_config=None,
        ssl_certfile=str(cert),
        ssl_keyfile=str(key),
    )
    https = uvicorn.Server(config)
    thread = threading.Thread(target=lambda: asyncio.run(https.serve()), daemon=True)
    thread.start()
    deadline = time.monotonic() + 20
    while not https.started:
        assert thread.is_alive() and time.monotonic() < deadline, "the https server did not start"
        time.sleep(0.01)
    port = https.servers[0].sockets[0].getsockname()[1]
    try:
        yield ca_pem, port
    finally:
        https.should_exit = True
        thread.join(timeout=20)


def test_a_private_ca_is_trusted_only_when_given(
    server: Server,  # noqa: F811
    tls_upstream: tuple[str, int],
) -> None:
    ca_pem, port = tls_upstream
    slug = new_twin(server)
    with server.admin as admin:
        add_service(admin, slug, "plain", f"https://localhost:{port}/")
        add_service(admin, slug, "private", f"https://localhost:{port}/", tls={"ca_pem": ca_pem})
        add_service(admin, slug, "any", f"https://localhost:{port}/", tls={"verify": False})
        add_service(admin, slug, "wrong-host", f"https://127.0.0.1:{port}/", tls={"ca_pem": ca_pem})
        refused = admin.get(f"/twins/{slug}/services/plain/x")
        assert refused.status_code == 502 and "certificate" in refused.json()["detail"].lower()
        assert admin.get(f"/twins/{slug}/services/private/x").json() == {"over": "tls"}
        assert admin.get(f"/twins/{slug}/services/any/x").json() == {"over": "tls"}
        mismatch = admin.get(f"/twins/{slug}/services/wrong-host/x")
        assert mismatch.status_code == 502, mismatch.text
        shown = admin.get(f"/api/v1/twins/{slug}/services/private").json()["tls"]
        assert shown == {"verify": True, "ca_pem_set": True}


def test_a_ca_pem_that_is_not_a_certificate_is_refused(server: Server) -> None:  # noqa: F811
    slug = new_twin(server)
    with server.admin as admin:
        r = admin.post(
            f"/api/v1/twins/{slug}/services",
            json={"name": "x", "base_url": "https://localhost/", "tls": {"ca_pem": "nope"}},
        )
    assert r.status_code == 422 and "ca_pem" in r.json()["detail"]
