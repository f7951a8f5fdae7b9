"""Twinbase's layout at the site's root: `/index.yaml` and `/index.json` list the site's twins.

Twinbase (github.com/twinbase/twinbase) publishes one folder per twin (`<baseurl>/<folder>/`
with `index.yaml`, `index.json` and `index.html`) and, at its root, an index its workflow
writes (`.github/generate-base-yaml-json.py`): `baseurl`, `owner` (from the site's
`setup.yaml`: `owner: {dt-id: ...}`), the GitHub `repo_url` and `new_twin_url`, and
`twins: [{url, name}]` with `url = <baseurl>/<folder>`. twinlink writes the same keys except
the two GitHub links; a twin's `url` is its canonical URL (`{public_url}/twins/{slug}`), under
which `index.yaml`, `index.json` and `index.html` are served as in Twinbase.
"""

from __future__ import annotations

from typing import Any

from twinlink.auth.rights import Principal
from twinlink.domain.records import TwinRecord
from twinlink.registry.service import RegistryService

# Twins are read from the store this many at a time (by slug, as the twin list pages).
_PAGE = 1000


async def visible_twins(reg: RegistryService, caller: Principal) -> list[TwinRecord]:
    """Every twin the caller may see (some part of), in slug order. Twinbase's index has no
    pages, so neither has this one: it lists them all."""
    twins: list[TwinRecord] = []
    after: str | None = None
    while True:
        page = await reg.store.list_twins(caller.visibility, limit=_PAGE, after_slug=after)
        twins.extend(page)
        if len(page) < _PAGE:
            return twins
        after = page[-1].slug


def site_index(reg: RegistryService, owner: str, twins: list[TwinRecord]) -> dict[str, Any]:
    """The root index in Twinbase's shape. `owner` is the dt-id of whoever runs the site
    (TWINLINK_SITE_OWNER, else the public URL); a twin's `name` is its listed name (its
    public part's `name`, else its slug), never a name from a part the caller may not see."""
    return {
        "baseurl": reg.base_url,
        "owner": {"dt-id": owner or reg.base_url},
        "twins": [{"url": reg.canonical_url(t.slug), "name": t.name} for t in twins],
    }
