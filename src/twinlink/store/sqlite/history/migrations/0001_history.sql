-- Time series live in their own file (history.db) so that telemetry writes never queue
-- behind metadata writes. One row of `blocks` holds the samples of one signal from one
-- ingested batch, column-wise: times and values as packed arrays, plus the summary
-- (count, min, max, sum, first, last) that lets aggregation skip whole blocks.

CREATE TABLE series (
    id          INTEGER PRIMARY KEY,
    twin_id     INTEGER NOT NULL,
    stream      TEXT    NOT NULL,
    signal      TEXT    NOT NULL,
    -- the longest t1 - t0 of any block, so a range query can bound its index scan
    max_span_ns INTEGER NOT NULL DEFAULT 0,
    UNIQUE (twin_id, stream, signal)
);

CREATE TABLE blocks (
    series_id INTEGER NOT NULL REFERENCES series(id) ON DELETE CASCADE,
    t0        INTEGER NOT NULL,   -- first (smallest) time, ns
    t1        INTEGER NOT NULL,   -- last (largest) time, ns
    n         INTEGER NOT NULL,
    -- i: int64, f: float64, b: bool (uint8), j: JSON list of mixed values or strings
    kind      TEXT    NOT NULL,
    vmin      REAL,               -- numeric kinds only
    vmax      REAL,
    vsum      REAL,
    first_v,                      -- value at t0 and at t1, typed by SQLite
    last_v,
    times     BLOB    NOT NULL,   -- int64 little-endian, sorted ascending
    vals      BLOB    NOT NULL
);
CREATE INDEX blocks_by_series_time ON blocks (series_id, t0);
CREATE INDEX blocks_by_end ON blocks (t1);

CREATE TABLE latest (
    series_id INTEGER PRIMARY KEY REFERENCES series(id) ON DELETE CASCADE,
    t         INTEGER NOT NULL,
    value
);

-- Batches already stored, by device and sequence number: a resent batch is stored once.
CREATE TABLE ingested (
    device_id INTEGER NOT NULL,
    seq       INTEGER NOT NULL,
    at_ns     INTEGER NOT NULL,
    PRIMARY KEY (device_id, seq)
) WITHOUT ROWID;
CREATE INDEX ingested_by_time ON ingested (at_ns);
