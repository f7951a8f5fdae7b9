"""Slugs: the short, URL-safe name of a twin (`/twins/{slug}`)."""

from __future__ import annotations

import re
import unicodedata
from urllib.parse import urlparse

SLUG = re.compile(r"^[a-z0-9](?:[a-z0-9-]{0,62}[a-z0-9])?$")


def slugify(text: str) -> str:
    ascii_text = unicodedata.normalize("NFKD", text).encode("ascii", "ignore").decode()
    slug = re.sub(r"[^a-z0-9]+", "-", ascii_text.lower()).strip("-")
    return slug[:64].strip("-")


def slug_for(
    explicit: str | None, hosting_iri: str | None, dt_id: str | None, name: str | None
) -> str:
    """The slug a document asks for: `slug`, else the last path segment of `hosting-iri` or the
    id, else the name."""
    if explicit:
        return explicit
    for iri in (hosting_iri, dt_id):
        if iri:
            # The last path segment of a URL; for a URN (urn:uuid:...) its last part.
            segment = urlparse(iri).path.rstrip("/").rsplit("/", 1)[-1].rsplit(":", 1)[-1]
            if slugify(segment):
                return slugify(segment)
    return slugify(name or "")
