"""Importing a Twinbase site (or another twinlink, which serves the same index) as remote
twins: `twinlink import twinbase URL`, POST /api/v1/remote-twins/import.

A Twinbase site publishes `index.json` at its root: `baseurl`, `owner` and `twins`, a list
of `{url, name}` whose `url` is each twin's hosting-iri, a folder holding the twin's
`index.json` (Twinbase's .github/generate-base-yaml-json.py writes it). The index is fetched,
then every twin's document; a twin that cannot be fetched is reported with why, the others
are kept. Importing again fetches with the validators kept, so unchanged twins cost a 304.
"""

from __future__ import annotations

import asyncio
from dataclasses import dataclass, field
from typing import Any
from urllib.parse import urljoin

from twinlink.domain.remote import RemoteTwin
from twinlink.federation.fetch import FetchFailed, FetchRefused
from twinlink.federation.remote import RemoteTwins, document_url

# Twins fetched at once: a site of hundreds is imported in a few round trips, without
# opening hundreds of connections to one host.
CONCURRENCY = 4
MAX_TWINS = 10_000


@dataclass(slots=True)
class Failure:
    url: str
    name: str
    error: str


@dataclass(slots=True)
class Imported:
    source: str  # the site, as given (without index.json and a trailing /)
    imported: list[RemoteTwin] = field(default_factory=list)
    failed: list[Failure] = field(default_factory=list)


def site_of(url: str) -> str:
    """The site's URL as it is recorded: without a trailing `/` or `/index.json`."""
    site = url.strip().split("#", 1)[0]
    for suffix in ("/index.json", "/index.yaml"):
        site = site.removesuffix(suffix)
    return site.rstrip("/")


def twins_of(index: dict[str, Any], index_url: str) -> list[tuple[str, str]]:
    """(url, name) of each twin the index lists, its URL made absolute; FetchFailed when
    the document is not a Twinbase index."""
    twins = index.get("twins")
    if not isinstance(twins, list):
        raise FetchFailed(
            f"{index_url!r} is not a Twinbase index: it has no `twins` list of {{url, name}}"
        )
    if len(twins) > MAX_TWINS:
        raise FetchFailed(f"{index_url!r} lists {len(twins)} twins, more than {MAX_TWINS}")
    found: dict[str, str] = {}
    for entry in twins:
        url = entry.get("url") if isinstance(entry, dict) else None
        if isinstance(url, str) and url.strip():
            name = entry.get("name")
            found.setdefault(urljoin(index_url, url.strip()), str(name) if name else "")
    return list(found.items())


async def import_site(remote: RemoteTwins, url: str) -> Imported:
    """Mirror the site at `url` (its root, or its index.json): every twin it lists."""
    source = site_of(url)
    index_url = document_url(source)
    got = await remote.fetcher.fetch_document(index_url)  # refused or failed: nothing to do
    assert got.document is not None  # asked without validators: never a 304
    result = Imported(source)
    gate = asyncio.Semaphore(CONCURRENCY)

    async def one(twin_url: str, name: str) -> None:
        async with gate:
            try:
                result.imported.append(await remote.fetch(twin_url, source))
            except (FetchRefused, FetchFailed) as err:  # the others are still kept
                result.failed.append(Failure(twin_url, name, err.problem_detail()))

    try:
        async with asyncio.TaskGroup() as group:
            for twin_url, name in twins_of(got.document, got.url):
                group.create_task(one(twin_url, name))
    except BaseExceptionGroup as errors:  # the store failed: its own error, not a group
        raise errors.exceptions[0] from None
    result.imported.sort(key=lambda t: (t.name, t.id))
    result.failed.sort(key=lambda f: f.url)
    return result
