-- Small batches (fewer than 8 samples, store/sqlite/history/staging.py) wait here, one row a
-- batch, until the writer moves them into column blocks in bulk: one insert per batch
-- instead of a block (and its index entries) per signal. `body` holds the batch's columns as
-- JSON: [[series id, signal, [times], [values]], ...]. No reader reads this table: a read of
-- a twin moves that twin's rows into blocks first.
CREATE TABLE staged (
    id      INTEGER PRIMARY KEY,
    twin_id INTEGER NOT NULL,
    stream  TEXT    NOT NULL,
    body    BLOB    NOT NULL
);
CREATE INDEX staged_by_twin ON staged (twin_id);
