"""Writing the search index of a twin (tables: migrations/0020_search.sql), and the text
search queries that read it.

Documents and queries are given to PostgreSQL in its literal tsvector and tsquery syntax,
made here from the words `snippets.words` splits: no text search configuration or parser of
the server's is involved, so a word is what it is for the SQLite backend's unicode61
tokenizer (no stemming, no URL or e-mail tokens, case and diacritics folded).
"""

from __future__ import annotations

from twinlink.domain.merge import level_order
from twinlink.domain.records import SearchRow
from twinlink.store.postgres.db import Connection
from twinlink.store.snippets import words

# Keywords are kept apart by a line break, so the facets can be read back as whole keywords.
KEYWORD_SEP = "\n"
# A document's weights (ts_rank takes them as {D, C, B, A}): the SQLite backend's bm25
# weights, name 10, feature names 6, keywords 5, descriptions 2, and `extra` 1 beside.
DOC_WEIGHTS = "{0.2, 0.5, 0.6, 1.0}"
EXTRA_WEIGHT = 0.1
_MAX_LEXEME_BYTES = 2046  # PostgreSQL refuses a longer word; such a word is not indexed
_MAX_POSITION = 16383  # PostgreSQL keeps positions up to this
_MAX_POSITIONS = 256  # and this many positions of one word
# A tsvector may not pass 1 MiB; past this estimate of its size, new words are left out
# (a part whose text holds some 100 000 different words), instead of the write failing.
_MAX_TSVECTOR_BYTES = 1_000_000


def tsvector(fields: list[tuple[str, str]]) -> str:
    """A tsvector literal of (text, weight letter) fields, words numbered in order."""
    found: dict[str, list[str]] = {}
    size = 0
    position = 0
    for text, weight in fields:
        for word in words(text):
            position = min(position + 1, _MAX_POSITION)
            positions = found.get(word)
            if positions is None:
                length = len(word.encode())
                if length > _MAX_LEXEME_BYTES or size + length > _MAX_TSVECTOR_BYTES:
                    continue
                size += length + 8  # the word's entry and its count of positions
                positions = found[word] = []
            if len(positions) < _MAX_POSITIONS:
                positions.append(f"{position}{weight}")
                size += 2
        position = min(position + 1, _MAX_POSITION)  # no phrase across two fields
    return " ".join(f"{_quoted(w)}:{','.join(p)}" for w, p in found.items())


def term_query(term: str, prefix: bool, weights: str = "") -> str | None:
    """One query word as a tsquery literal: a phrase of its words (`a_b` is `a <-> b`), the
    last one a prefix when `prefix` and the word has two letters or more (one letter as a
    prefix would match nearly everything). None when it holds no word at all ("_"), or one
    too long to be indexed (PostgreSQL keeps words of up to 2 046 bytes)."""
    found = words(term)
    if not found or any(len(w.encode()) > _MAX_LEXEME_BYTES for w in found):
        return None  # no word, or one too long to be in the index: it matches nothing
    star = "*" if prefix and len(term) > 1 else ""
    lexemes = [f"{_quoted(w)}:{weights}" if weights else _quoted(w) for w in found]
    last = found[-1]
    lexemes[-1] = f"{_quoted(last)}:{star}{weights}" if star or weights else _quoted(last)
    return "(" + " <-> ".join(lexemes) + ")"


def _quoted(word: str) -> str:
    return "'" + word.replace("\\", "\\\\").replace("'", "''") + "'"


async def write_search_rows(conn: Connection, twin_id: int, rows: list[SearchRow]) -> None:
    """Replace the twin's index by `rows`: one search_rows row each (with its keywords), and
    one search_parts document per privacy part."""
    await conn.execute("DELETE FROM search_rows WHERE twin_id = $1", twin_id)
    await conn.execute("DELETE FROM search_parts WHERE twin_id = $1", twin_id)
    if not rows:
        return
    # Ids taken first, so each row's keywords go with it whatever order the insert takes.
    ids = [
        r[0]
        for r in await conn.fetch(
            "SELECT nextval(pg_get_serial_sequence('search_rows', 'id'))"
            " FROM generate_series(1, $1)",
            len(rows),
        )
    ]
    await conn.executemany(
        "INSERT INTO search_rows (id, twin_id, privacy, feature, name, description, keywords,"
        " extra) VALUES ($1, $2, $3, $4, $5, $6, $7, $8)",
        [
            (row_id, twin_id, r.privacy, r.feature, r.name, r.description,
             KEYWORD_SEP.join(r.keywords), r.extra)
            for row_id, r in zip(ids, rows, strict=True)
        ],
    )  # fmt: skip
    await conn.executemany(
        "INSERT INTO search_keywords (row_id, keyword) VALUES ($1, $2)",
        [
            (row_id, k)
            for row_id, row in zip(ids, rows, strict=True)
            for k in dict.fromkeys(row.keywords)
        ],
    )
    await conn.executemany(
        "INSERT INTO search_parts (twin_id, privacy, doc, extra, keywords)"
        " VALUES ($1, $2, $3::tsvector, $4::tsvector, $5)",
        [(twin_id, level, *_document(part)) for level, part in _parts(rows).items()],
    )


def _parts(rows: list[SearchRow]) -> dict[str, list[SearchRow]]:
    parts: dict[str, list[SearchRow]] = {}
    for level in sorted({r.privacy for r in rows}, key=level_order):
        parts[level] = [r for r in rows if r.privacy == level]
    return parts


def _document(rows: list[SearchRow]) -> tuple[str, str, str]:
    """The (doc, extra, keywords) of one privacy part."""
    sep = KEYWORD_SEP
    names = sep.join(r.name for r in rows if r.feature is None)
    features = sep.join(r.name for r in rows if r.feature is not None)
    keywords = sep.join(sep.join(r.keywords) for r in rows)
    descriptions = sep.join(r.description for r in rows)
    doc = tsvector([(names, "A"), (features, "B"), (keywords, "C"), (descriptions, "D")])
    return doc, tsvector([(sep.join(r.extra for r in rows), "D")]), keywords
