"""Remote twins: DT documents of other instances, kept here read-only (docs/federation.md,
"Mirroring a Twinbase site").

A document is fetched through the Fetcher (fetch.py: the SSRF guard, redirects, limits) and
kept with the validators it came with, so fetching it again costs a 304 when it has not
changed. A fetch that fails keeps the copy and says why: `gone` when the other instance
answered 404 or 410, `stale` for anything else (unreachable, too slow, not a document).
"""

from __future__ import annotations

import builtins
import time
from collections.abc import Callable
from typing import Any

from twinlink.domain.errors import NotFoundError
from twinlink.domain.remote import FROM_RELATION, RemoteTwin
from twinlink.federation.fetch import Fetched, Fetcher, FetchFailed
from twinlink.store.remote import RemoteTwinStore

_GONE = {404, 410}
# Twinbase's placeholder in a document whose dt-id its workflow has not filled in yet.
_PLACEHOLDER = "autoassign"


def dt_id_of(document: dict[str, Any], url: str) -> str:
    """The twin's dt-id (its `id` in Aalto's form), else the URL it was fetched from."""
    for key in ("dt-id", "id"):
        value = document.get(key)
        if isinstance(value, str) and value.strip() and not value.startswith(_PLACEHOLDER):
            return value.strip()
    return url


def document_url(url: str) -> str:
    """Where a Twinbase twin's document is: index.json in its hosting-iri's folder (as
    Twinbase's dtweb client reads it); a twinlink twin serves the same there."""
    if url.endswith((".json", ".yaml")):
        return url
    return url.split("#", 1)[0].rstrip("/") + "/index.json"


class RemoteTwins:
    """The remote twins of this instance: read, fetched again, searched, deleted."""

    def __init__(
        self,
        store: RemoteTwinStore,
        fetcher: Fetcher,
        stale_s: float = 3600.0,
        clock: Callable[[], int] = time.time_ns,
    ) -> None:
        self.store = store
        self.fetcher = fetcher  # shared: its pool, and the peers' tokens (federation/peers.py)
        self.stale_ns = int(stale_s * 1e9)
        self._clock = clock

    async def aclose(self) -> None:
        """Close the fetcher (its connections)."""
        await self.fetcher.aclose()

    # -- reading ------------------------------------------------------------------------------

    async def get(self, remote_id: int) -> RemoteTwin:
        twin = await self.store.get_remote_twin(remote_id)
        if twin is None:
            raise NotFoundError(f"no remote twin {remote_id}: GET /api/v1/remote-twins lists them")
        return twin

    async def get_by_dt_id(self, dt_id: str) -> RemoteTwin | None:
        return await self.store.get_remote_twin_by_dt_id(dt_id)

    async def get_by_url(self, url: str) -> RemoteTwin | None:
        return await self.store.get_remote_twin_by_url(url)

    async def list(self, q: str | None = None) -> list[RemoteTwin]:
        return await self.store.list_remote_twins(q or None)

    async def search(self, q: str) -> builtins.list[RemoteTwin]:
        """Those whose name, dt-id, URL or document text holds `q` (any case)."""
        return await self.store.list_remote_twins(q) if q.strip() else []

    def state_of(self, twin: RemoteTwin) -> str:
        """The state to show: a `reachable` twin not checked for TWINLINK_FEDERATION_STALE_S
        is `stale` (its copy may be out of date)."""
        if twin.state == "reachable" and self._clock() - twin.checked_ns > self.stale_ns:
            return "stale"
        return twin.state

    # -- writing ------------------------------------------------------------------------------

    async def upsert(
        self,
        *,
        url: str,
        document: dict[str, Any],
        source: str = FROM_RELATION,
        etag: str | None = None,
        last_modified: str | None = None,
    ) -> RemoteTwin:
        """Keep `document`, fetched from `url` now, as the remote twin of its dt-id."""
        now = self._clock()
        name = document.get("name")
        twin = RemoteTwin(
            id=0, dt_id=dt_id_of(document, url), url=url,
            name=name if isinstance(name, str) else "", document=document, source=source,
            fetched_ns=now, checked_ns=now, etag=etag, last_modified=last_modified,
        )  # fmt: skip
        return await self.store.put_remote_twin(twin)

    async def mark(self, dt_id: str, state: str, error: str = "") -> RemoteTwin | None:
        """Record a check of the twin of `dt_id`: its state and why (None if unknown)."""
        twin = await self.store.get_remote_twin_by_dt_id(dt_id)
        if twin is None:
            return None
        twin.state, twin.error, twin.checked_ns = state, error, self._clock()
        return await self.store.put_remote_twin(twin)

    async def fetch(self, url: str, source: str = FROM_RELATION) -> RemoteTwin:
        """Fetch the twin whose hosting-iri is `url` (again: with the validators of the copy
        kept) and keep it. A failure marks a kept copy stale or gone and is raised."""
        known = await self.store.get_remote_twin_by_url(url)
        if known is not None and source == FROM_RELATION:
            source = known.source  # a relation followed to an imported twin: still the site's
        try:
            got = await self.fetcher.fetch_document(
                document_url(url) if source != FROM_RELATION else url,
                etag=known.etag if known else None,
                last_modified=known.last_modified if known else None,
            )
        except FetchFailed as err:
            if known is not None:
                gone = err.remote_status in _GONE
                await self.mark(known.dt_id, "gone" if gone else "stale", str(err))
            raise
        return await self._keep(url, source, known, got)

    async def _keep(
        self, url: str, source: str, known: RemoteTwin | None, got: Fetched
    ) -> RemoteTwin:
        if got.not_modified and known is not None:
            known.state, known.error, known.checked_ns = "reachable", "", self._clock()
            known.source = source  # an import takes over a twin a relation found
            return await self.store.put_remote_twin(known)
        if got.document is None:  # a 304 to a request without validators: ask in full
            raise FetchFailed(f"{url!r} answered 304 Not Modified to a plain GET")
        if known is not None and dt_id_of(got.document, url) != known.dt_id:
            await self.store.delete_remote_twin(known.id)  # its dt-id changed: one row
        return await self.upsert(
            url=url, document=got.document, source=source, etag=got.etag,
            last_modified=got.last_modified,
        )  # fmt: skip

    async def refresh(self, remote_id: int) -> RemoteTwin:
        """Fetch the twin again from where it was found."""
        twin = await self.get(remote_id)
        return await self.fetch(twin.url, twin.source)

    async def delete(self, remote_id: int) -> None:
        if not await self.store.delete_remote_twin(remote_id):
            raise NotFoundError(f"no remote twin {remote_id}: GET /api/v1/remote-twins lists them")
