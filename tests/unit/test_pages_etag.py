"""The conditional answers of the document URLs (api/pages.py): which If-None-Match headers
match an ETag (RFC 9110's weak comparison), and the format table others register into."""

from __future__ import annotations

import pytest

from twinlink.api.pages import FORMATS, Format, _etag_matches, register_format

ETAG = '"0123abcd"'


@pytest.mark.parametrize(
    "header",
    [ETAG, f"W/{ETAG}", f'"other", {ETAG}', f' "other" ,W/{ETAG} ', "*", '"other", *'],
)
def test_if_none_match_naming_the_etag_matches(header: str) -> None:
    assert _etag_matches(header, ETAG)


@pytest.mark.parametrize("header", [None, "", '"other"', "0123abcd", f"{ETAG[:-1]}", '"0123ABCD"'])
def test_if_none_match_naming_another_etag_does_not(header: str | None) -> None:
    assert not _etag_matches(header, ETAG)


def test_the_built_in_formats_cannot_be_replaced() -> None:
    before = dict(FORMATS)
    for name in ("yaml", "json", "html"):
        with pytest.raises(ValueError, match="built in"):
            register_format(name, Format("text/plain", lambda doc, slug, request: b""))
    assert before == FORMATS
