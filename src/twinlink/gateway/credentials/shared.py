"""A service's fetched token shared by the nodes of one store (store/tokens.py), so that the
nodes log in once between them: a node starting, or one whose token another node renewed,
takes the stored token; nodes refreshing together wait for the first one's login.

The token leaves this module sealed by the vault (every node has the same key,
TWINLINK_SECRET_KEY), and the row is named by the service and a keyed fingerprint of its
credential settings: changed credentials never take the token of the old ones.
"""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from typing import NamedTuple

import orjson

from twinlink.auth.vault import Vault, VaultError
from twinlink.gateway.credentials.base import CredentialConfig, RefreshError
from twinlink.plugins import split_secrets
from twinlink.store.tokens import NewToken, SharedRefreshFailed, SharedToken, SharedTokens

# A login: (header value, renew after s, life s).
Login = Callable[[], Awaitable[tuple[str, float, float]]]


class Held(NamedTuple):
    """A shared token, opened: the header value, and its times in seconds from now."""

    value: str
    sealed: bytes
    renew_in_s: float
    expires_in_s: float


class TokenShare:
    def __init__(
        self, store: SharedTokens, vault: Vault, service: str, config: CredentialConfig
    ) -> None:
        self.store = store
        self.vault = vault
        self.service = service
        public, secret = split_secrets(config)
        settings = {"method": config.method, "public": public, "secret": secret}
        self.fingerprint = vault.fingerprint(orjson.dumps(settings, option=orjson.OPT_SORT_KEYS))

    async def current(self) -> Held | None:
        """The stored token of these credentials, if any (StorageError: the store is away)."""
        token = await self.store.current(self.service, self.fingerprint)
        return self._opened(token) if token is not None else None

    async def refresh_once(self, stale: bytes | None, login: Login, wait_s: float) -> Held:
        """A token other than `stale`: from `login`, or from another node's, whichever came
        first; RefreshError when that login failed, StorageError when the store is away."""

        async def fetch() -> NewToken:
            value, renew_after_s, life_s = await login()
            return NewToken(self.vault.seal({"value": value}), renew_after_s, life_s)

        try:
            token = await self.store.refresh_once(
                self.service, self.fingerprint, stale, fetch, wait_s
            )
        except SharedRefreshFailed as err:
            raise RefreshError(str(err)) from None
        return self._opened(token)

    def _opened(self, token: SharedToken) -> Held:
        try:
            value = self.vault.unseal(token.sealed).get("value")
        except VaultError:
            value = None
        if not isinstance(value, str):
            raise RefreshError(
                "the token another node stored cannot be read with this node's secret key: "
                "give every node the same TWINLINK_SECRET_KEY"
            )
        return Held(value, token.sealed, token.renew_in_s, token.expires_in_s)
