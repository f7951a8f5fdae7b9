"""The federation parts of one process, built from the settings: the fetch policy, the
Fetcher (with the peers' tokens), the remote twins and the resolver of relations."""

from __future__ import annotations

from dataclasses import dataclass

from twinlink.auth.vault import Vault
from twinlink.config import Settings
from twinlink.federation.fetch import Fetcher
from twinlink.federation.guard import FetchPolicy
from twinlink.federation.peers import Peers
from twinlink.federation.remote import RemoteTwins
from twinlink.federation.resolve import Resolver
from twinlink.store.remote import RemoteTwinStore

# A page showing remote relations waits at most this long for fetches it started.
PAGE_WAIT_S = 2.0


def policy_of(settings: Settings) -> FetchPolicy:
    hosts = tuple(h.strip() for h in settings.federation_hosts.split(",") if h.strip())
    return FetchPolicy(
        hosts=hosts,
        allow_private=settings.federation_allow_private,
        max_hops=settings.federation_max_hops,
        max_bytes=settings.federation_max_kb * 1024,
        timeout_s=settings.federation_timeout_s,
    )


@dataclass
class Federation:
    policy: FetchPolicy
    peers: Peers
    fetcher: Fetcher
    remote: RemoteTwins
    resolver: Resolver

    @classmethod
    def configured(cls, settings: Settings, store: RemoteTwinStore, vault: Vault) -> Federation:
        policy = policy_of(settings)
        peers = Peers(vault, settings.data_dir)
        fetcher = Fetcher(policy, peers.token_for)
        remote = RemoteTwins(store, fetcher, settings.federation_stale_s)
        wait = min(PAGE_WAIT_S, policy.timeout_s)
        resolver = Resolver(remote, settings.federation_stale_s, wait)
        return cls(policy, peers, fetcher, remote, resolver)

    async def aclose(self) -> None:
        await self.resolver.aclose()
        await self.remote.aclose()  # closes the fetcher
