"""Leases (store/leases.py): the semantics every lease store keeps (LocalLeases here; the
same tests run on PostgreSQL in tests/integration/test_scale_out_leases.py), and Claims,
what a service keeps: the ids it holds, those no longer wanted given back, and a store that
cannot be reached costing the node its items only once their leases may have expired."""

from __future__ import annotations

import pytest

from twinlink.domain.errors import StorageError
from twinlink.store.leases import Claims, LeaseStore, LocalLeases, Position, new_holder


async def check_semantics(store: LeaseStore) -> None:
    """What any LeaseStore does (shared with the PostgreSQL tests)."""
    a, b = new_holder(), new_holder()
    assert a != b
    assert await store.acquire(["x:1", "x:2"], a, 30) == {"x:1", "x:2"}
    assert await store.acquire(["x:2", "x:3"], b, 30) == {"x:3"}  # x:2 is a's
    assert await store.acquire(["x:1", "x:2"], a, 30) == {"x:1", "x:2"}  # renewed
    assert await store.held(a) == {"x:1", "x:2"}
    await store.release(["x:2", "x:3"], a)  # x:3 is b's: left alone
    assert await store.held(a) == {"x:1"}
    assert await store.held(b) == {"x:3"}
    assert await store.acquire(["x:2"], b, 30) == {"x:2"}  # released: free for anyone
    assert await store.acquire([], a, 30) == set()
    # A lease not renewed within its TTL is free for another holder.
    assert await store.acquire(["x:9"], a, 0.0) == {"x:9"}
    assert await store.held(a) == {"x:1"}
    assert await store.acquire(["x:9"], b, 30) == {"x:9"}
    assert await store.acquire(["x:9"], a, 30) == set()


async def check_positions(store: LeaseStore) -> None:
    """Positions: saved only by the lease's holder, never moved back in one stream (shared
    with the PostgreSQL tests)."""
    a, b = new_holder(), new_holder()
    assert await store.acquire(["p:1", "p:2"], a, 30) == {"p:1", "p:2"}
    await store.save_positions({"p:1": Position("in", 100), "p:2": Position("in", 5)}, a)
    await store.save_positions({"p:1": Position("in", 999)}, b)  # not b's: left alone
    assert await store.positions(["p:1", "p:2", "p:3"]) == {
        "p:1": Position("in", 100),
        "p:2": Position("in", 5),
    }
    await store.save_positions({"p:1": Position("in", 50)}, a)  # behind: kept where it was
    await store.save_positions({"p:2": Position("other", 1)}, a)  # another stream: from there
    assert await store.positions(["p:1", "p:2"]) == {
        "p:1": Position("in", 100),
        "p:2": Position("other", 1),
    }
    await store.acquire(["p:1"], a, 0.0)  # expired: a may no longer save it
    await store.save_positions({"p:1": Position("in", 200)}, a)
    assert await store.positions(["p:1"]) == {"p:1": Position("in", 100)}
    await store.forget_positions(["p:1", "p:9"])
    assert await store.positions(["p:1", "p:2"]) == {"p:2": Position("other", 1)}


async def test_local_leases_keep_the_semantics() -> None:
    await check_semantics(LocalLeases())
    await check_positions(LocalLeases())


class Flaky(LocalLeases):
    """A store that can be made unreachable."""

    down = False

    async def acquire(self, names: list[str], holder: str, ttl_s: float) -> set[str]:
        if self.down:
            raise StorageError("the database cannot be reached")
        return await super().acquire(names, holder, ttl_s)


async def test_claims_hold_what_is_free_and_give_back_what_is_no_longer_wanted() -> None:
    store = LocalLeases()
    one = Claims(store, "processor", new_holder())
    two = Claims(store, "processor", new_holder())
    assert await one.hold([3, 1]) == {1, 3}
    assert await two.hold([1, 2, 3]) == {2}
    assert await two.claim(1) is False and await two.claim(4) is True
    assert await one.hold([3]) == {3}  # 1 disabled or deleted: released at once
    assert await two.hold([1, 2, 3, 4]) == {1, 2, 4}
    assert await store.held(two.holder) == {"processor:1", "processor:2", "processor:4"}
    await one.release_all()
    assert await two.hold([1, 2, 3, 4]) == {1, 2, 3, 4}  # a clean stop: taken over at once
    assert one.held == set()


async def test_kinds_do_not_share_leases() -> None:
    store = LocalLeases()
    holder = new_holder()
    assert await Claims(store, "processor", holder).hold([1]) == {1}
    assert await Claims(store, "connector", new_holder()).hold([1]) == {1}


async def test_an_unreachable_store_keeps_the_items_until_their_leases_may_expire(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    clock = [1000.0]
    monkeypatch.setattr("twinlink.store.leases.time.monotonic", lambda: clock[0])
    store = Flaky()
    claims = Claims(store, "connector", new_holder(), ttl_s=10, renew_s=3)
    assert await claims.hold([1, 2]) == {1, 2}
    store.down = True
    clock[0] += 3
    assert await claims.hold([1, 2]) == {1, 2}  # still well within the TTL: kept running
    assert await claims.hold([1]) == {1}  # 2 no longer wanted: stopped all the same
    clock[0] += 5  # 8 s since the last renewal: another node may take them in 2 s
    assert await claims.hold([1]) == set()
    store.down = False
    assert await claims.hold([1]) == {1}
