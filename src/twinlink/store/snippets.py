"""Words as the search index sees them, and snippets of the text that matched, for every
backend (SQLite's FTS5 index, PostgreSQL's tsvectors), so that both find and show the same: a
word is a run of letters and digits, compared in lower case without diacritics (unicode61
with remove_diacritics 2). Snippets are cut here
from the stored text, escaped, with the matches in <mark>: PostgreSQL's ts_headline would
mark words by its own parser's rules, and would have to run once per row.
"""

from __future__ import annotations

import html
import re
import unicodedata

_WORD = re.compile(r"[^\W_]+")  # unicode61: letters and digits; "_" and the rest separate
_TOKEN = re.compile(r"\w+", re.UNICODE)
_SNIPPET_TOKENS = 10


def fold(text: str) -> str:
    """Lower case without diacritics, as the unicode61 tokenizer compares words."""
    decomposed = unicodedata.normalize("NFKD", text.lower())
    return "".join(ch for ch in decomposed if not unicodedata.combining(ch))


def words(text: str) -> list[str]:
    """The words of `text` as the index stores them."""
    return _WORD.findall(fold(text))


class Highlighter:
    """Finds the query's words in stored text the way the search matches them (a prefix in
    names, keywords and descriptions, whole in the other text; one letter always whole), and
    cuts a snippet: about ten words around the first match, matches in <mark>, the rest
    escaped."""

    def __init__(self, terms: list[str]) -> None:
        long_terms = [t for t in terms if len(t) > 1]
        short_terms = [t for t in terms if len(t) == 1]
        parts = []
        if long_terms:
            parts.append(rf"(?:{'|'.join(map(_escaped, long_terms))})\w*")
        if short_terms:
            parts.append(rf"(?:{'|'.join(map(_escaped, short_terms))})\b")
        self.prefixed = re.compile(rf"\b(?:{'|'.join(parts)})", re.IGNORECASE)
        self.whole = re.compile(rf"\b(?:{'|'.join(map(_escaped, terms))})\b", re.IGNORECASE)

    def snippet(self, prefixed: list[str], whole: str) -> str | None:
        """`prefixed` texts match a word as a prefix, `whole` only as the whole word. None
        when nothing matches."""
        for text in prefixed:
            found = _spans(self.prefixed, text)
            if found:
                return _cut(text, found)
        found = _spans(self.whole, whole)
        return _cut(whole, found) if found else None


def _escaped(term: str) -> str:
    return re.escape(fold(term))


def _spans(pattern: re.Pattern[str], text: str) -> list[tuple[int, int]]:
    if not text:
        return []
    # Diacritics: match a folded copy when positions carry over to the original.
    haystack = text
    if not text.isascii():
        folded = fold(text)
        haystack = folded if len(folded) == len(text) else text
    return [(m.start(), m.end()) for m in pattern.finditer(haystack)]


def _cut(text: str, spans: list[tuple[int, int]]) -> str:
    """The text around the first span, about ten words, spans marked, the rest escaped."""
    tokens = list(_TOKEN.finditer(text))
    first_word = next(i for i, w in enumerate(tokens) if w.end() > spans[0][0])
    lo = max(0, first_word - 3)
    hi = min(len(tokens), lo + _SNIPPET_TOKENS)
    start, end = tokens[lo].start(), tokens[hi - 1].end()
    out, pos = [], start
    for a, b in spans:
        if a < start or b > end:
            continue
        out += [html.escape(text[pos:a]), "<mark>", html.escape(text[a:b]), "</mark>"]
        pos = b
    out.append(html.escape(text[pos:end]))
    return ("…" if start > 0 else "") + "".join(out) + ("…" if end < len(text) else "")
