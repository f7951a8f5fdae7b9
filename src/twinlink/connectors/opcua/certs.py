"""Certificate and key files of the OPC UA connector: read (PEM or DER, a key optionally under
a password), checked to belong together, and described for a person (subject, fingerprint).

The configuration checks the files when a connector is created or changed (a 422 names the
file), and the connector reads them again when it starts: they may have changed since.
"""

from __future__ import annotations

from pathlib import Path

from cryptography import x509
from cryptography.hazmat.primitives import hashes, serialization
from cryptography.hazmat.primitives.asymmetric.types import PrivateKeyTypes, PublicKeyTypes
from cryptography.x509.oid import NameOID

from twinlink.domain.errors import TwinlinkError


class CertificateFileError(TwinlinkError, ValueError):
    """A certificate or key file that cannot be used; the text names the file and why."""


def read_certificate(path: Path, field: str = "certificate") -> x509.Certificate:
    """A certificate file, PEM or DER."""
    data = _read(path, field)
    try:
        if b"-----BEGIN" in data:
            return x509.load_pem_x509_certificate(data)
        return x509.load_der_x509_certificate(data)
    except ValueError as err:
        raise CertificateFileError(
            f"{field} {path} is not a PEM or DER certificate: {err}"
        ) from err


def read_private_key(path: Path, password: str | None) -> PrivateKeyTypes:
    """A private key file, PEM or DER, unencrypted or under `password`."""
    data = _read(path, "private_key")
    secret = password.encode() if password else None
    try:
        if b"-----BEGIN" in data:
            return serialization.load_pem_private_key(data, secret)
        return serialization.load_der_private_key(data, secret)
    except (ValueError, TypeError) as err:
        raise CertificateFileError(
            f"private_key {path} cannot be read (PEM or DER; is private_key_password right?): {err}"
        ) from err


def read_key_pair(
    cert_path: Path, key_path: Path, password: str | None
) -> tuple[x509.Certificate, PrivateKeyTypes]:
    """The client's certificate and its private key, refused when the key is another
    certificate's: a server would refuse every secure channel signed with it, with nothing
    but a timeout or BadSecurityChecksFailed to show for it."""
    cert = read_certificate(cert_path)
    key = read_private_key(key_path, password)
    if _public_der(cert.public_key()) != _public_der(key.public_key()):
        raise CertificateFileError(
            f"private_key {key_path} does not belong to certificate {cert_path}: their public "
            "keys differ (give the key the certificate was issued for)"
        )
    return cert, key


def describe(cert: x509.Certificate) -> str:
    """How a person tells certificates apart: the subject's common name and the thumbprint
    (SHA-1, as OPC UA names certificates and UaExpert shows them)."""
    names = cert.subject.get_attributes_for_oid(NameOID.COMMON_NAME)
    name = str(names[0].value) if names else cert.subject.rfc4514_string() or "no subject"
    thumbprint = cert.fingerprint(hashes.SHA1()).hex().upper()  # a name, not a signature
    return f"{name!r} (thumbprint {thumbprint})"


def first_certificate(der: bytes) -> bytes:
    """The first certificate of a DER chain (an endpoint may present its issuers after it)."""
    if len(der) < 2 or der[0] != 0x30:
        return der
    size = der[1]
    if size < 0x80:
        return der[: 2 + size]
    octets = size & 0x7F
    length = int.from_bytes(der[2 : 2 + octets], "big")
    return der[: 2 + octets + length]


def _read(path: Path, field: str) -> bytes:
    try:
        return path.read_bytes()
    except OSError as err:
        raise CertificateFileError(f"{field} {path}: {err.strerror or err}") from err


def _public_der(key: PublicKeyTypes) -> bytes:
    return key.public_bytes(
        serialization.Encoding.DER, serialization.PublicFormat.SubjectPublicKeyInfo
    )
