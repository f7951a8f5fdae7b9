-- Full-text search over twins and their features, one row per (twin, privacy part, feature).
CREATE TABLE search_rows (
    id       INTEGER PRIMARY KEY,
    twin_id  INTEGER NOT NULL REFERENCES twins(id) ON DELETE CASCADE,
    privacy  TEXT NOT NULL,
    feature  TEXT
);
CREATE INDEX search_rows_twin ON search_rows(twin_id);

-- The FTS rowid equals search_rows.id.
CREATE VIRTUAL TABLE search_fts USING fts5(
    name, description, keywords, extra,
    tokenize="unicode61 remove_diacritics 2",
    prefix='1 2 3'
);

CREATE TABLE search_keywords (
    row_id  INTEGER NOT NULL REFERENCES search_rows(id) ON DELETE CASCADE,
    keyword TEXT NOT NULL COLLATE NOCASE
);
CREATE INDEX search_keywords_kw ON search_keywords(keyword, row_id);
CREATE INDEX search_keywords_row ON search_keywords(row_id);
