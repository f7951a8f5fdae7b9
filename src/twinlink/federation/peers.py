"""Peers: service-account tokens for other instances, by origin (docs/federation.md
"Security").

An instance fetches other instances' documents without credentials, so it sees what the
public sees. Given a token for a peer (made there for a service account), it sends that
token to that peer's exact origin, and nowhere else, to see what the account may see.

The tokens are sealed with the Vault, the same key as the gateway's service credentials,
in one file (<data_dir>/federation-peers, mode 0600): a copy of the data dir without the key
reveals none. They are never logged and never returned; the API lists origins only.
"""

from __future__ import annotations

import os
from pathlib import Path
from urllib.parse import urlsplit

from twinlink.auth.vault import Vault
from twinlink.domain.errors import InvalidInputError
from twinlink.federation.guard import FetchRefused, origin_of

PEERS_FILE = "federation-peers"
MAX_TOKEN = 4096


def peer_origin(peer: str, scheme: str = "https") -> str:
    """The origin a peer is stored under, from `host[:port]` and a scheme (or a whole
    origin), written as the guard writes origins (lower case, default port left out)."""
    text = peer.strip()
    url = text if "://" in text else f"{scheme}://{text}"
    try:
        origin = origin_of(url)
    except FetchRefused as err:
        raise InvalidInputError(f"the peer {peer!r} is not an http(s) origin: {err}") from err
    parts = urlsplit(url)
    if parts.path not in ("", "/") or parts.query or parts.fragment:
        raise InvalidInputError(
            f"the peer {peer!r} has a path; give its origin only, as https://host[:port]"
        )
    return origin


class Peers:
    """The tokens, in memory, written through to the sealed file on every change."""

    def __init__(self, vault: Vault, data_dir: Path) -> None:
        self._vault = vault
        self._path = data_dir / PEERS_FILE
        self._tokens: dict[str, str] = {}
        if self._path.exists():
            self._tokens = {
                str(k): str(v) for k, v in vault.unseal(self._path.read_bytes()).items()
            }

    def token_for(self, origin: str) -> str | None:
        """The token for exactly this origin (the Fetcher asks for every hop's own)."""
        return self._tokens.get(origin)

    def origins(self) -> list[str]:
        return sorted(self._tokens)

    def put(self, peer: str, token: str, scheme: str = "https") -> str:
        """Store (or replace) the token for `peer`; returns its origin."""
        origin = peer_origin(peer, scheme)
        token = token.strip()
        if not token or len(token) > MAX_TOKEN or any(c.isspace() for c in token):
            raise InvalidInputError(f"the token must be 1 to {MAX_TOKEN} characters without spaces")
        self._tokens[origin] = token
        self._save()
        return origin

    def delete(self, peer: str) -> list[str]:
        """Forget the tokens of `peer` (host[:port], over http and https, or one origin);
        returns the origins forgotten."""
        wanted = {peer_origin(peer, "https"), peer_origin(peer, "http")}
        gone = [o for o in self._tokens if o in wanted]
        for origin in gone:
            del self._tokens[origin]
        if gone:
            self._save()
        return gone

    def _save(self) -> None:
        self._path.parent.mkdir(parents=True, exist_ok=True)
        tmp = self._path.with_name(self._path.name + ".tmp")
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        with os.fdopen(fd, "wb") as f:
            f.write(self._vault.seal(dict(self._tokens)))
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, self._path)

    def __repr__(self) -> str:  # never show a token
        return f"Peers({len(self._tokens)} origins)"
