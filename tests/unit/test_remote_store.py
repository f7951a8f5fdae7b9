"""The remote twins' table through the RemoteTwinStore protocol: a twin stored with its own id
and read back whole (its document too), found by dt-id and by URL, written over by dt-id (its
id kept, one row however often it is fetched), listed by name and searched in its text (a `%`
or `_` in the query taken literally), and deleted.

Runs on SQLite here and on PostgreSQL in tests/integration/test_remote_store_postgres.py."""

from __future__ import annotations

from tests.unit._storage import Stores
from tests.unit._storage import stores as stores
from twinlink.domain.remote import RemoteTwin

SITE = "https://twinbase.example.org"


def _remote(name: str, folder: str, **changes: object) -> RemoteTwin:
    twin = RemoteTwin(
        id=0, dt_id=f"https://dtid.org/{folder}", url=f"{SITE}/{folder}", name=name,
        document={"dt-id": f"https://dtid.org/{folder}", "name": name,
                  "description": f"{name} in hall 3", "owner": {"name": "Aalto-yliopisto"}},
        source=SITE, fetched_ns=5, checked_ns=5, etag='W/"1"',
        last_modified="Wed, 25 Nov 2026 10:00:00 GMT",
    )  # fmt: skip
    for key, value in changes.items():
        setattr(twin, key, value)
    return twin


async def test_a_remote_twin_is_stored_and_read_back_whole(stores: Stores) -> None:
    store = stores.metadata
    crane = await store.put_remote_twin(_remote("Crane", "crane"))
    room = await store.put_remote_twin(_remote("Room", "room", etag=None, last_modified=None))
    assert 0 < crane.id < room.id
    assert await store.get_remote_twin(crane.id) == crane
    assert await store.get_remote_twin_by_dt_id("https://dtid.org/room") == room
    assert await store.get_remote_twin_by_url(f"{SITE}/crane") == crane
    got = await store.get_remote_twin(room.id)
    assert got is not None and got.document["owner"] == {"name": "Aalto-yliopisto"}
    assert (got.etag, got.last_modified) == (None, None)
    assert await store.get_remote_twin(room.id + 100) is None
    assert await store.get_remote_twin_by_dt_id("https://dtid.org/none") is None
    assert await store.get_remote_twin_by_url(f"{SITE}/none") is None


async def test_fetching_again_writes_over_the_row_of_its_dt_id(stores: Stores) -> None:
    store = stores.metadata
    first = await store.put_remote_twin(_remote("Crane", "crane"))
    again = _remote("Crane 2", "crane", fetched_ns=9, checked_ns=9, state="stale",
                    error="timed out", etag=None, source="relation")  # fmt: skip
    again.document["name"] = "Crane 2"
    await store.put_remote_twin(again)
    assert again.id == first.id
    assert await store.get_remote_twin(first.id) == again
    assert [t.id for t in await store.list_remote_twins()] == [first.id]


async def test_remote_twins_list_by_name_and_search_their_text(stores: Stores) -> None:
    store = stores.metadata
    room = await store.put_remote_twin(_remote("Room", "room"))
    crane = await store.put_remote_twin(_remote("Crane", "crane"))
    odd = await store.put_remote_twin(_remote("50%_off", "odd"))
    assert [t.id for t in await store.list_remote_twins()] == [odd.id, crane.id, room.id]
    assert [t.id for t in await store.list_remote_twins(limit=1)] == [odd.id]
    assert [t.id for t in await store.list_remote_twins("CRANE")] == [crane.id]  # the name
    assert [t.id for t in await store.list_remote_twins("hall 3")] == [odd.id, crane.id, room.id]
    assert [t.id for t in await store.list_remote_twins("dtid.org/room")] == [room.id]
    assert [t.id for t in await store.list_remote_twins("%_")] == [odd.id]  # taken literally
    assert await store.list_remote_twins("nowhere") == []
    assert await store.delete_remote_twin(room.id)
    assert not await store.delete_remote_twin(room.id)
    assert [t.id for t in await store.list_remote_twins()] == [odd.id, crane.id]
