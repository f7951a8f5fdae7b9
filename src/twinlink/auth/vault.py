"""Credentials encrypted at rest (Fernet: AES-128-CBC with an HMAC-SHA256 tag, from the
`cryptography` package).

The key comes from `TWINLINK_SECRET_KEY` or, when that is unset, from `<data_dir>/secret.key`
(made on first use, readable by the server's user only). A copy of the database without the
key reveals no credential; keep the key out of backups that leave the machine.
"""

from __future__ import annotations

import hashlib
import hmac
import logging
import os
from pathlib import Path
from typing import Any

import orjson
from cryptography.fernet import Fernet, InvalidToken

from twinlink.config import Settings
from twinlink.domain.errors import TwinlinkError

KEY_FILE = "secret.key"
log = logging.getLogger("twinlink.app")  # where this warning was always logged


class VaultError(TwinlinkError):
    """Stored credentials cannot be read with this key (the key changed or was lost)."""


class Vault:
    def __init__(self, key: bytes) -> None:
        self._fernet = Fernet(key)
        self._mac_key = hashlib.sha256(b"twinlink fingerprint\0" + key).digest()

    @classmethod
    def configured(cls, settings: Settings) -> Vault:
        """The vault with the key of TWINLINK_SECRET_KEY, or else the data dir's."""
        secret_key = settings.secret_key.get_secret_value() if settings.secret_key else None
        if secret_key is None and settings.store_url.get_secret_value():
            # Each node would make a key of its own in its data dir, and read none of the
            # credentials the other nodes stored in the shared database.
            log.warning(
                "TWINLINK_STORE_URL is set but TWINLINK_SECRET_KEY is not: the gateway's "
                "stored credentials are encrypted with a key in this node's data dir, which "
                "other nodes do not have; give every node the same TWINLINK_SECRET_KEY "
                "(docs/scale-out.md)",
                extra={"event": "secret_key_per_node"},
            )
        return cls.open(settings.data_dir, secret_key)

    @classmethod
    def open(cls, data_dir: Path, key: str | None) -> Vault:
        if key:
            return cls(key.encode())
        path = data_dir / KEY_FILE
        if not path.exists():
            data_dir.mkdir(parents=True, exist_ok=True)
            fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
            with os.fdopen(fd, "wb") as f:
                f.write(Fernet.generate_key())
        return cls(path.read_bytes().strip())

    def seal(self, secret: dict[str, Any]) -> bytes:
        return self._fernet.encrypt(orjson.dumps(secret))

    def unseal(self, sealed: bytes) -> dict[str, Any]:
        try:
            value: dict[str, Any] = orjson.loads(self._fernet.decrypt(sealed))
        except InvalidToken as err:
            raise VaultError(
                "the stored credentials cannot be decrypted with this server's secret key "
                "(TWINLINK_SECRET_KEY or secret.key changed); set them again"
            ) from err
        return value

    def fingerprint(self, data: bytes) -> str:
        """A keyed digest of `data`: the same on every node with this key, and, unlike a plain
        hash, no help in guessing a weak secret in `data` to whoever reads it without the key."""
        return hmac.new(self._mac_key, data, hashlib.sha256).hexdigest()

    def __repr__(self) -> str:  # never show the key
        return "Vault(<key hidden>)"
