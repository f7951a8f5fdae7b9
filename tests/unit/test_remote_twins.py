"""The remote twins' service and the Twinbase import's reading of a site (over HTTP in
tests/integration/test_remote_twins.py): a twin's dt-id (Twinbase's autoassign placeholder
skipped), where a Twinbase twin's document is, the site recorded as the source, the index's
twins (relative URLs made absolute, entries without a URL skipped, an index without `twins`
refused), and the state shown for a copy not checked for a while."""

from __future__ import annotations

import pytest

from tests.unit._storage import Stores
from tests.unit._storage import stores as stores
from twinlink.federation.fetch import Fetcher, FetchFailed, FetchPolicy
from twinlink.federation.remote import RemoteTwins, document_url, dt_id_of
from twinlink.federation.twinbase import site_of, twins_of

SITE = "https://twinbase.example.org/base"


def test_a_twin_is_known_by_its_dt_id_else_its_id_else_its_url() -> None:
    url = f"{SITE}/crane"
    assert dt_id_of({"dt-id": " http://d-t.fi/crane ", "id": "x"}, url) == "http://d-t.fi/crane"
    assert dt_id_of({"id": "urn:crane"}, url) == "urn:crane"
    assert dt_id_of({"dt-id": "autoassign|https://dtid.org", "name": "new"}, url) == url
    assert dt_id_of({"dt-id": 42}, url) == url


def test_a_twinbase_twins_document_is_index_json_in_its_folder() -> None:
    assert document_url(f"{SITE}/crane") == f"{SITE}/crane/index.json"
    assert document_url(f"{SITE}/crane/#top") == f"{SITE}/crane/index.json"
    assert document_url(f"{SITE}/crane/index.yaml") == f"{SITE}/crane/index.yaml"
    assert site_of(f" {SITE}/index.json ") == SITE
    assert site_of(f"{SITE}/") == SITE


def test_the_index_lists_each_twin_once_with_an_absolute_url() -> None:
    index = {
        "baseurl": SITE,
        "twins": [
            {"url": f"{SITE}/crane", "name": "Ilmatar crane"},
            {"url": "room", "name": "Room"},  # relative to the index
            {"url": f"{SITE}/crane", "name": "again"},
            {"name": "no url"},
            "not an entry",
            {"url": f"{SITE}/nameless"},
        ],
    }
    assert twins_of(index, f"{SITE}/index.json") == [
        (f"{SITE}/crane", "Ilmatar crane"), (f"{SITE}/room", "Room"), (f"{SITE}/nameless", "")
    ]  # fmt: skip
    with pytest.raises(FetchFailed, match="not a Twinbase index"):
        twins_of({"dt-id": "http://d-t.fi/juuso", "name": "Juuso"}, f"{SITE}/juuso/index.json")


async def test_a_copy_not_checked_for_a_while_shows_as_stale(stores: Stores) -> None:
    now = [1_000_000_000_000]
    fetcher = Fetcher(FetchPolicy())
    remote = RemoteTwins(stores.metadata, fetcher, stale_s=60, clock=lambda: now[0])
    try:
        twin = await remote.upsert(
            url=f"{SITE}/crane", document={"dt-id": "http://d-t.fi/crane", "name": "Crane"},
            source=SITE, etag='"1"',
        )  # fmt: skip
        assert (twin.dt_id, twin.name, twin.fetched_ns) == ("http://d-t.fi/crane", "Crane", now[0])
        assert remote.state_of(twin) == "reachable"
        now[0] += 61 * 10**9
        assert remote.state_of(twin) == "stale"
        marked = await remote.mark("http://d-t.fi/crane", "gone", "answered 410")
        assert marked is not None and marked.checked_ns == now[0]
        assert remote.state_of(marked) == "gone" and marked.error == "answered 410"
        assert await remote.mark("http://d-t.fi/none", "gone") is None
        assert [t.id for t in await remote.search("CRANE")] == [twin.id]
        assert await remote.search("  ") == []
    finally:
        await remote.aclose()
