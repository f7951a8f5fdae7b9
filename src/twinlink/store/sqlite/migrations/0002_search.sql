-- Full-text search.
--
-- search_twins ranks and counts: one document per (twin, privacy part) holding the part's
-- twin name, feature names, keywords, descriptions and other text. Its rowid is
-- twin_id * 32 + slot, slot 0 being the public part, so the twin and whether the part is
-- public follow from the rowid without a lookup.
CREATE VIRTUAL TABLE search_twins USING fts5(
    name, features, keywords, description, extra,
    tokenize="unicode61 remove_diacritics 2",
    prefix='2 3'
);
INSERT INTO search_twins(search_twins, rank) VALUES ('rank', 'bm25(10.0, 6.0, 5.0, 2.0, 1.0)');

CREATE TABLE search_parts (
    id      INTEGER PRIMARY KEY,  -- the search_twins rowid
    twin_id INTEGER NOT NULL REFERENCES twins(id) ON DELETE CASCADE,
    privacy TEXT NOT NULL
);
CREATE INDEX search_parts_twin ON search_parts(twin_id);
-- A reader's non-public parts are found from here without scanning every part.
CREATE INDEX search_parts_privacy ON search_parts(privacy, twin_id);

-- search_rows/search_fts say which feature matched and give snippets: one row per
-- (twin, privacy part, feature), the twin's own fields forming a row with no feature.
CREATE TABLE search_rows (
    id       INTEGER PRIMARY KEY,  -- the search_fts rowid
    twin_id  INTEGER NOT NULL REFERENCES twins(id) ON DELETE CASCADE,
    privacy  TEXT NOT NULL,
    feature  TEXT
);
CREATE INDEX search_rows_twin ON search_rows(twin_id);

CREATE VIRTUAL TABLE search_fts USING fts5(
    name, description, keywords, extra,
    tokenize="unicode61 remove_diacritics 2",
    prefix='2 3'
);

CREATE TABLE search_keywords (
    row_id  INTEGER NOT NULL REFERENCES search_rows(id) ON DELETE CASCADE,
    keyword TEXT NOT NULL COLLATE NOCASE
);
CREATE INDEX search_keywords_kw ON search_keywords(keyword, row_id);
CREATE INDEX search_keywords_row ON search_keywords(row_id);
