"""Documents read from twinlink and applied again: what to store, what to recognise, and the
one case to refuse.

`GET /twins/{slug}` answers a reader's view: the parts they may see merged, plus what the
platform fills in (the four timestamps, the id, `hosting-iri`, relations from the graph).
Applying that view again must change nothing, so a part that equals the view some reader
gets (for a set of levels ending at the part's own) is recognised and the stored part kept.

A view merged from several parts is not a part, though: stored as the most private of them,
it would copy every public feature into the private part. A changed view is recognised by
the platform's timestamps it carries while the twin has parts more public than its level, and
refused with how to change a part instead.
"""

from __future__ import annotations

from collections.abc import Iterator
from itertools import combinations
from typing import Any

from twinlink.domain.document import PLATFORM_KEYS, is_placeholder
from twinlink.domain.errors import DocumentError
from twinlink.domain.merge import level_order
from twinlink.domain.records import Edge, TwinRecord
from twinlink.domain.yamlsource import SourceDocument
from twinlink.registry.views import (
    RelationKey,
    declared_entries,
    relation_entries,
    relation_key,
    render_document,
)

# Keys of a view that come from the platform, not from the parts as written.
_FILLED_IN = (*PLATFORM_KEYS, "relations", "id", "dt-id")
# Below this many more public levels every combination is tried; above, the readers' usual
# ones (the part alone, with the public part, with all of them).
_ALL_COMBINATIONS_UP_TO = 6


def as_stored(body: dict[str, Any], dt_id: str, canonical_urls: set[str]) -> dict[str, Any]:
    """A part as it is kept: Twinbase's `dt-id: autoassign|...` becomes the id the twin got, and
    a `hosting-iri` that is the twin's own address here is left out: it is what the reader's
    document shows when none is given, and it follows the twin when the slug changes."""
    out = dict(body)
    if is_placeholder(out.get("dt-id")):
        out["dt-id"] = dt_id
    if out.get("hosting-iri") in canonical_urls:
        del out["hosting-iri"]
    return out


def is_view_of(
    body: dict[str, Any],
    level: str,
    stored: dict[str, dict[str, Any]],
    twin: TwinRecord,
    canonical_url: str,
    edges: list[Edge],
) -> bool:
    """Whether `body` (as validated, for `level`) is the document some reader of `twin` gets:
    the stored parts of a set of levels ending at `level`, merged and filled in. Its relations
    must be relations the graph has, and hold every relation those parts write."""
    graph = {relation_key(e) for e in relation_entries(twin.dt_id, edges, "id")}
    for levels in _reader_levels(stored, level):
        parts = {lv: stored[lv] for lv in levels}
        view = render_document(twin, parts, [], canonical_url)
        if _content(body, twin.dt_id) == _content(view, twin.dt_id) and _same_relations(
            body.get("relations"), declared_entries(parts), graph
        ):
            return True
    return False


def refuse_merged_view(
    source: SourceDocument, level: str, stored: dict[str, dict[str, Any]], slug: str
) -> None:
    """Raise DocumentError (422) when `source`, applied as the `level` part, looks like a view
    merged from it and more public parts: it carries the platform's timestamps (every view
    does, a part as stored never), and the twin has parts more public than `level`."""
    stamps = [key for key in PLATFORM_KEYS if key in source.data]
    more_public = sorted(
        (lv for lv in stored if level_order(lv) < level_order(level)), key=level_order
    )
    if not stamps or not more_public:
        return
    raise DocumentError(
        "The document is a twin's merged view, not one part; nothing was stored.",
        [
            source.problem(
                "this looks like the document a reader gets, merged from this twin's "
                f"{_and([*more_public, level])} parts: it carries the platform's timestamps "
                f"({', '.join(stamps)}). Stored as the {level!r} part it would copy what the "
                f"{_and(more_public)} {'parts hold' if len(more_public) > 1 else 'part holds'} "
                "into it. "
                f"Change each part on its own (GET /api/v1/twins/{slug}/parts/{{level}} gives "
                "one as stored), or leave out the timestamps to store this document as the "
                f"{level!r} part.",
                ("privacy",),
            )
        ],
    )


def _and(names: list[str]) -> str:
    return names[0] if len(names) == 1 else f"{', '.join(names[:-1])} and {names[-1]}"


def _reader_levels(stored: dict[str, dict[str, Any]], level: str) -> Iterator[list[str]]:
    if level not in stored:
        return
    lower = sorted((lv for lv in stored if level_order(lv) < level_order(level)), key=level_order)
    if len(lower) <= _ALL_COMBINATIONS_UP_TO:
        for n in range(len(lower) + 1):
            for chosen in combinations(lower, n):
                yield [*chosen, level]
        return
    yield [level]
    if "public" in lower:
        yield ["public", level]
    yield [*lower, level]


def _content(doc: dict[str, Any], dt_id: str) -> dict[str, Any] | None:
    """The document without what the platform fills in; None when it names another twin."""
    if any(doc.get(key) not in (None, dt_id) for key in ("id", "dt-id")):
        return None
    return {k: v for k, v in doc.items() if k not in _FILLED_IN}


def _same_relations(
    given: Any, declared: dict[RelationKey, dict[str, Any]], graph: set[RelationKey | None]
) -> bool:
    """`given` names only relations of the graph, each the parts write as they write it, and
    misses none the parts write."""
    if given is None:
        return not declared
    if not isinstance(given, list):
        return False
    keys = set()
    for entry in given:
        key = relation_key(entry)
        if key is None or key not in graph:
            return False
        written = declared.get(key)
        if written is not None and entry != written:
            return False
        if written is None and set(entry) - {"relationType", "id", "dt-id"}:
            return False
        keys.add(key)
    return keys >= set(declared)
