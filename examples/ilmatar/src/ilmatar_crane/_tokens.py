"""Short-lived opaque access tokens, as the historian and the sensor manager hand them out."""

from __future__ import annotations

import secrets
import time
from collections.abc import Callable
from dataclasses import dataclass, field


@dataclass
class TokenStore:
    ttl_s: float
    clock: Callable[[], float] = time.monotonic
    issued: int = 0  # tokens handed out since start; tests count logins with it
    _expiry: dict[str, tuple[str, float]] = field(default_factory=dict)

    def issue(self, subject: str) -> str:
        self._forget_expired()
        token = secrets.token_urlsafe(32)
        self._expiry[token] = (subject, self.clock() + self.ttl_s)
        self.issued += 1
        return token

    def subject(self, token: str) -> str | None:
        """Who the token was issued to, or None when it is unknown or has expired."""
        found = self._expiry.get(token)
        if found is None:
            return None
        subject, expires = found
        if self.clock() >= expires:
            del self._expiry[token]
            return None
        return subject

    def _forget_expired(self) -> None:
        now = self.clock()
        for token in [t for t, (_, expires) in self._expiry.items() if now >= expires]:
            del self._expiry[token]


class IssuesTokens:
    """A service that hands out tokens from `_tokens`: how many so far, and their lifetime
    (which tests shorten on a running service)."""

    _tokens: TokenStore

    @property
    def tokens_issued(self) -> int:
        return self._tokens.issued

    @property
    def token_ttl_s(self) -> float:
        """The lifetime of tokens issued from now on (s)."""
        return self._tokens.ttl_s

    @token_ttl_s.setter
    def token_ttl_s(self, seconds: float) -> None:
        self._tokens.ttl_s = seconds
