"""Passwords (argon2id) and API tokens (random, shown once, stored as a SHA-256 hash).

Tokens carry 256 bits of randomness, so a fast hash is enough to store them safely and lets
every request be checked with one indexed lookup; passwords are low-entropy and get argon2.
"""

from __future__ import annotations

import functools
import hashlib
import secrets

from argon2 import PasswordHasher
from argon2.exceptions import InvalidHashError, VerificationError

TOKEN_PREFIX = "tl_"
_hasher = PasswordHasher()
# Verifying against this when the user does not exist keeps the timing the same.


@functools.cache
def _dummy_hash() -> str:
    return _hasher.hash("twinlink-timing-equaliser")


def hash_password(password: str) -> str:
    return _hasher.hash(password)


def verify_password(password_hash: str | None, password: str) -> bool:
    try:
        return (
            _hasher.verify(password_hash or _dummy_hash(), password) and password_hash is not None
        )
    except (VerificationError, InvalidHashError):
        return False


def new_token() -> str:
    return TOKEN_PREFIX + secrets.token_urlsafe(32)


def hash_token(token: str) -> bytes:
    return hashlib.sha256(token.encode()).digest()


def token_prefix(token: str) -> str:
    """The first characters, safe to show so a person can tell tokens apart."""
    return token[: len(TOKEN_PREFIX) + 6]


def new_password() -> str:
    return secrets.token_urlsafe(12)
