"""The caches in front of the metadata store (twins, roles, devices, tokens), on a real SQLite
store that counts its calls: each is used, and each change empties it at once."""

from __future__ import annotations

import asyncio
from collections import Counter
from collections.abc import AsyncIterator
from pathlib import Path
from typing import Any

import pytest

from twinlink.auth import service as auth_module
from twinlink.auth.rights import Principal
from twinlink.auth.service import AuthError, AuthService
from twinlink.domain.errors import ForbiddenError, NotFoundError
from twinlink.domain.records import SearchRow, TwinRecord, TwinWrite, User
from twinlink.registry.cache import GenerationCache
from twinlink.registry.devices import DeviceService
from twinlink.registry.service import RegistryService
from twinlink.store.sqlite import SqliteStore

DEADLINE_S = 10.0  # for a held call to arrive: only a broken test waits this long


class Held:
    """A call held once it has read its answer (which may be out of date when it arrives):
    `reached` is set then, and it goes on when `release` is."""

    def __init__(self) -> None:
        self.reached, self.release = asyncio.Event(), asyncio.Event()

    async def until_reached(self) -> None:
        await asyncio.wait_for(self.reached.wait(), DEADLINE_S)


class CountingStore:
    """The store, counting each call; `hold[name]` holds the calls of `name` (Held)."""

    def __init__(self, store: SqliteStore) -> None:
        self.store = store
        self.calls: Counter[str] = Counter()
        self.hold: dict[str, Held] = {}

    def __getattr__(self, name: str) -> Any:
        method = getattr(self.store, name)

        async def call(*args: Any, **kwargs: Any) -> Any:
            self.calls[name] += 1
            answer = await method(*args, **kwargs)
            held = self.hold.get(name)
            if held is not None:
                held.reached.set()
                await held.release.wait()
            return answer

        return call


@pytest.fixture
async def store(tmp_path: Path) -> AsyncIterator[CountingStore]:
    real = SqliteStore(tmp_path)
    await real.open()
    yield CountingStore(real)
    await real.close()


async def user(store: CountingStore, name: str, created_ns: int = 1) -> User:
    return await store.store.create_user(name, None, False, [], created_ns)


async def private_twin(store: CountingStore, slug: str, owner: User) -> TwinRecord:
    """A twin only people with a role on it see (its one part is for the group `crew`)."""
    write = TwinWrite(
        slug=slug, dt_id=f"urn:{slug}", name=slug, created_ns=1, modified_ns=1,
        parts={"crew": {"name": slug}}, edges=[],
        search_rows=[SearchRow("crew", None, slug, "", [], "")], owner_user_id=owner.id,
    )  # fmt: skip
    return (await store.store.save_twins([write]))[0]


# -- GenerationCache -------------------------------------------------------------------------


def test_a_generation_cache_empties_when_the_generation_moves() -> None:
    generation = [0]
    cache: GenerationCache[str, int] = GenerationCache(lambda: generation[0], limit=2)
    cache.keep("a", 1, cache.generation())
    assert cache.get("a") == 1
    generation[0] += 1
    assert cache.get("a") is None and len(cache) == 0


def test_a_value_read_while_the_generation_moved_is_not_kept() -> None:
    generation = [0]
    cache: GenerationCache[str, int] = GenerationCache(lambda: generation[0])
    read_at = cache.generation()
    generation[0] += 1  # a change landed while the value was being read
    cache.keep("a", 1, read_at)
    assert cache.get("a") is None


def test_a_full_generation_cache_starts_again() -> None:
    cache: GenerationCache[int, int] = GenerationCache(lambda: 0, limit=2)
    for i in range(3):
        cache.keep(i, i, cache.generation())
    assert len(cache) == 1 and cache.get(2) == 2


# -- RegistryService: twins and roles --------------------------------------------------------


async def test_twins_and_roles_are_read_once(store: CountingStore) -> None:
    registry = RegistryService(store, "http://x")
    alice = await user(store, "alice")
    await private_twin(store, "rig", alice)
    for _ in range(3):
        twin, role = await registry.require_twin(Principal(alice), "rig")
        assert (twin.slug, role) == ("rig", "owner")
    assert (store.calls["get_twin"], store.calls["get_role"]) == (1, 1)


async def test_a_role_granted_or_taken_away_counts_at_once(store: CountingStore) -> None:
    registry = RegistryService(store, "http://x")
    alice, bob = await user(store, "alice"), await user(store, "bob")
    await private_twin(store, "rig", alice)
    with pytest.raises(NotFoundError):  # no role: a private twin is not admitted to exist
        await registry.require_twin(Principal(bob), "rig")
    await registry.set_role(Principal(alice), "rig", "bob", "editor")
    assert (await registry.require_twin(Principal(bob), "rig"))[1] == "editor"
    await registry.set_role(Principal(alice), "rig", "bob", "viewer")
    with pytest.raises(ForbiddenError, match="need the editor role"):
        await registry.require_role(Principal(bob), "rig", "editor", "the commands")
    await registry.set_role(Principal(alice), "rig", "bob", None)
    with pytest.raises(NotFoundError):
        await registry.require_twin(Principal(bob), "rig")


async def test_a_new_user_with_a_deleted_user_s_id_has_none_of_its_roles(
    store: CountingStore,
) -> None:
    registry = RegistryService(store, "http://x")
    alice = await user(store, "alice")
    bob = await user(store, "bob", created_ns=1)
    await private_twin(store, "rig", alice)
    await registry.set_role(Principal(alice), "rig", "bob", "editor")
    await registry.require_twin(Principal(bob), "rig")  # bob's role is cached
    assert await store.store.delete_user(bob.id)  # nothing tells the registry
    carol = await user(store, "carol", created_ns=2)
    assert carol.id == bob.id  # SQLite gives the id again
    with pytest.raises(NotFoundError):
        await registry.require_twin(Principal(carol), "rig")


async def test_a_role_read_during_a_change_is_not_kept(store: CountingStore) -> None:
    registry = RegistryService(store, "http://x")
    alice = await user(store, "alice")
    twin = await private_twin(store, "rig", alice)
    await registry.get_twin("rig")
    held = store.hold["get_role"] = Held()
    reading = asyncio.create_task(registry.require_twin(Principal(alice), "rig"))
    await held.until_reached()  # the role has been read ("owner") and is on its way
    await store.store.set_role(twin.id, alice.id, "viewer")  # a change lands meanwhile
    registry.changed()
    held.release.set()
    assert (await reading)[1] == "owner"  # the answer of a read that began before the change
    del store.hold["get_role"]
    assert (await registry.require_twin(Principal(alice), "rig"))[1] == "viewer"


async def test_device_changes_move_the_registry_generation(store: CountingStore) -> None:
    registry = RegistryService(store, "http://x")
    devices = DeviceService(store, registry)
    alice = await user(store, "alice")
    await private_twin(store, "rig", alice)
    before = registry.generation
    await devices.create(Principal(alice), "rig", "a", "")
    await devices.rotate(Principal(alice), "rig", "a")
    await devices.delete(Principal(alice), "rig", "a")
    assert registry.generation == before + 3


# -- AuthService: tokens ---------------------------------------------------------------------


async def signed_in(store: CountingStore) -> tuple[AuthService, str]:
    auth = AuthService(store, 3600)
    bob = await store.store.create_user("bob", None, False, [], 1)
    return auth, (await auth.issue_token(bob, "t", ttl_s=None)).token


async def test_a_token_is_looked_up_once(store: CountingStore) -> None:
    auth, token = await signed_in(store)
    for _ in range(3):
        principal = await auth.authenticate(token)
        assert principal.user is not None and principal.user.username == "bob"
    assert store.calls["find_token"] == 1


async def test_a_revoked_token_is_refused_at_once(store: CountingStore) -> None:
    auth, token = await signed_in(store)
    principal = await auth.authenticate(token)
    assert principal.token_id is not None
    await auth.revoke_token(principal, principal.token_id)
    with pytest.raises(AuthError, match="revoked"):
        await auth.authenticate(token)


async def test_user_changes_count_at_once(store: CountingStore) -> None:
    auth, token = await signed_in(store)
    await auth.authenticate(token)
    await auth.update_user("bob", groups=["crane-team"])
    principal = await auth.authenticate(token)
    assert principal.user is not None and principal.user.groups == ["crane-team"]
    await auth.update_user("bob", disabled=True)
    with pytest.raises(AuthError, match="disabled"):
        await auth.authenticate(token)


async def test_a_deleted_user_s_token_is_refused_at_once(store: CountingStore) -> None:
    auth, token = await signed_in(store)
    principal = await auth.authenticate(token)
    assert principal.user is not None and await auth.delete_user(principal.user)
    with pytest.raises(AuthError, match="not valid"):
        await auth.authenticate(token)


async def test_expiry_is_checked_on_every_use(
    store: CountingStore, monkeypatch: pytest.MonkeyPatch
) -> None:
    auth = AuthService(store, 3600)
    bob = await store.store.create_user("bob", None, False, [], 1)
    token = (await auth.issue_token(bob, "t", ttl_s=60)).token
    await auth.authenticate(token)
    later = auth_module.now_ns() + 61 * 1_000_000_000
    monkeypatch.setattr(auth_module, "now_ns", lambda: later)
    with pytest.raises(AuthError, match="expired"):
        await auth.authenticate(token)
    assert store.calls["find_token"] == 1  # from the cache, and still refused


async def test_cached_tokens_are_read_again_after_a_while(
    store: CountingStore, monkeypatch: pytest.MonkeyPatch
) -> None:
    auth, token = await signed_in(store)
    monkeypatch.setattr(auth_module, "TOKEN_CACHE_S", 0.0)
    await auth.authenticate(token)
    await auth.authenticate(token)
    assert store.calls["find_token"] == 2


async def test_a_token_read_during_a_revocation_is_not_kept(store: CountingStore) -> None:
    auth, token = await signed_in(store)
    held = store.hold["find_token"] = Held()
    reading = asyncio.create_task(auth.authenticate(token))
    await held.until_reached()  # the token has been read (valid) and is on its way
    principal = Principal(await store.store.get_user_by_name("bob"))
    [record] = await store.store.list_tokens(None)
    await auth.revoke_token(principal, record.id)  # lands meanwhile
    held.release.set()
    await reading  # it passes: it began before the revocation
    del store.hold["find_token"]
    with pytest.raises(AuthError, match="revoked"):
        await auth.authenticate(token)
