"""Relations across instances (docs/federation.md "Relations across instances"): a relation,
owner or manufacturer whose dt-id no local twin has, and that is an http(s) URL, names a
twin of another instance. It is shown as a remote twin node from the cache of remote twins
(remote.py), fetched through the Fetcher (the SSRF guard, redirects, limits) when missing or
old.

A page never waits on another instance for longer than the fetch timeout: what is missing is
fetched in the background, and a page waits for those fetches at most `wait_s`; a fetch that
takes longer finishes for the next page. Only the nodes of the local graph are resolved, not
the remote twins' own relations, so a cycle between instances costs one fetch per link.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import time
from collections import OrderedDict
from collections.abc import Iterator
from datetime import UTC, datetime
from typing import Any

from twinlink.domain.remote import RemoteTwin
from twinlink.federation.guard import FetchFailed, FetchRefused
from twinlink.federation.remote import RemoteTwins

log = logging.getLogger("twinlink.federation")
# Fetches running at once in the background, all pages together.
MAX_RUNNING = 8
# Failures of references never fetched, remembered (newest kept) so a dead link is not
# fetched again on every page within the stale time.
MAX_FAILURES = 1024


def is_remote_ref(ref: str) -> bool:
    return ref.startswith(("http://", "https://"))


def _iso(ns: int) -> str | None:
    if not ns:
        return None
    return (
        datetime.fromtimestamp(ns / 1e9, UTC).isoformat(timespec="seconds").replace("+00:00", "Z")
    )


class Resolver:
    """Resolves relation targets to remote twins; one per process."""

    def __init__(self, remote: RemoteTwins, stale_s: float, wait_s: float) -> None:
        self.remote = remote
        self.stale_ns = int(stale_s * 1e9)
        self.wait_s = wait_s
        self._running: dict[str, asyncio.Task[None]] = {}
        self._limit = asyncio.Semaphore(MAX_RUNNING)
        # ref -> (state, error, checked_ns) of references that have no row (never fetched).
        self._failures: OrderedDict[str, tuple[str, str, int]] = OrderedDict()
        self._closed = False

    async def aclose(self) -> None:
        self._closed = True
        tasks = list(self._running.values())
        for task in tasks:
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)

    async def cached(self, ref: str) -> RemoteTwin | None:
        return await self.remote.get_by_url(ref) or await self.remote.get_by_dt_id(ref)

    async def resolve(self, ref: str) -> dict[str, Any]:
        """Fetch `ref` now (with the kept copy's validators) and return its node summary:
        `{"id", "remote": {...}}`. FetchRefused when the guard will not fetch it."""
        await self._fetch(ref)
        return {"id": ref, **await self._summary(ref)}

    async def decorate(self, tree: dict[str, Any]) -> dict[str, Any]:
        """Give every node of a relation tree (RegistryService.traverse) that is not a local
        twin and whose id is an http(s) URL its `remote` summary, fetching what is missing
        or older than the stale time (waiting at most `wait_s` for those fetches)."""
        nodes = [n for n in _walk(tree) if n.get("registered") is False and is_remote_ref(n["id"])]
        waiting = [t for n in nodes if (t := await self._refresh_if_needed(n["id"])) is not None]
        if waiting:
            # shield: a page that stops waiting leaves the fetch running for the next one.
            await asyncio.wait([asyncio.shield(t) for t in waiting], timeout=self.wait_s)
        for node in nodes:
            node.update(await self._summary(node["id"]))
        return tree

    async def summaries(self, refs: list[str]) -> dict[str, dict[str, Any]]:
        """The `remote` summary of each http(s) reference in `refs` (as `decorate`)."""
        nodes: list[dict[str, Any]] = [{"id": r, "registered": False} for r in dict.fromkeys(refs)]
        await self.decorate({"id": "", "nodes": nodes})
        return {str(n["id"]): n["remote"] for n in nodes if "remote" in n}

    async def _summary(self, ref: str) -> dict[str, Any]:
        twin = await self.cached(ref)
        if twin is not None:
            return {
                "remote": {
                    "url": twin.url,
                    "name": twin.name,
                    "state": self.remote.state_of(twin),
                    "fetched_at": _iso(twin.fetched_ns),
                    "remote_id": twin.id,
                }
            }
        failure = self._failures.get(ref)
        state = failure[0] if failure else "pending"
        return {"remote": {"url": ref, "name": "", "state": state, "fetched_at": None}}

    async def _refresh_if_needed(self, ref: str) -> asyncio.Task[None] | None:
        if ref in self._running:
            return self._running[ref]
        twin = await self.cached(ref)
        now = time.time_ns()
        if twin is not None:
            checked = twin.checked_ns
        else:
            failure = self._failures.get(ref)
            checked = failure[2] if failure else 0
        if checked and now - checked <= self.stale_ns:
            return None
        if self._closed:
            return None
        task = asyncio.create_task(self._background(ref), name=f"federation resolve {ref}")
        self._running[ref] = task
        task.add_done_callback(lambda _t: self._running.pop(ref, None))
        return task

    async def _background(self, ref: str) -> None:
        async with self._limit:
            with contextlib.suppress(FetchFailed, FetchRefused):
                await self._fetch(ref)

    async def _fetch(self, ref: str) -> None:
        known = await self.cached(ref)
        try:
            await self.remote.fetch(known.url if known else ref)
        except FetchRefused as err:
            self._remember(ref, "refused", str(err))
            log.info("a relation to another instance is refused: %s", err)
            raise
        except FetchFailed as err:
            if known is None:
                gone = err.remote_status in (404, 410)
                self._remember(ref, "gone" if gone else "stale", str(err))
            log.info("a relation to another instance cannot be read: %s", err)
            raise
        self._failures.pop(ref, None)

    def _remember(self, ref: str, state: str, error: str) -> None:
        self._failures[ref] = (state, error, time.time_ns())
        self._failures.move_to_end(ref)
        while len(self._failures) > MAX_FAILURES:
            self._failures.popitem(last=False)


def document_refs(doc: dict[str, Any]) -> list[str]:
    """The http(s) dt-ids a document names: its relations' targets, and its owner and
    manufacturer when given as a dt-id (text, or a mapping's `dt-id` or `id`)."""
    found: list[str] = []
    for relation in doc.get("relations") or ():
        if isinstance(relation, dict):
            found.append(str(relation.get("id") or relation.get("dt-id") or ""))
    for key in ("owner", "manufacturer"):
        value = doc.get(key)
        if isinstance(value, dict):
            value = value.get("dt-id") or value.get("id")
        if isinstance(value, str):
            found.append(value)
    return [r for r in dict.fromkeys(found) if is_remote_ref(r)]


def _walk(node: dict[str, Any]) -> Iterator[dict[str, Any]]:
    yield node
    for child in node.get("nodes", ()):
        yield from _walk(child)
