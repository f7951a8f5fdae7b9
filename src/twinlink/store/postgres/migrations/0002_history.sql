-- Time series. One row of `samples` is one value of one signal, in a typed column (vi, vf,
-- vb or vj, by `kind`), so SQL aggregates numbers and int64 stays exact.
-- The table is partitioned by time (history/partitions.py makes the ranges as batches need
-- them); retention drops whole partitions.

-- A twin's streams, and each stream's signals with the summary /streams shows (kept by the
-- writer in the transaction of each batch, so it never has to scan the samples).
CREATE TABLE streams (
    id      bigint GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
    twin_id bigint NOT NULL,
    name    text   NOT NULL,
    UNIQUE (twin_id, name)
);

CREATE TABLE series (
    id        bigint GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
    stream_id bigint NOT NULL REFERENCES streams (id) ON DELETE CASCADE,
    signal    text   NOT NULL,
    n         bigint NOT NULL DEFAULT 0,  -- values stored
    first_t   bigint,                     -- their first and last time, ns
    last_t    bigint,
    kinds     text   NOT NULL DEFAULT '', -- the kinds of its values: some of i, f, b, j
    UNIQUE (stream_id, signal)
);

-- kind: i (int64, vi), f (float64, vf), b (bool, vb), j (JSON text, vj: strings, and the
-- values of a batch that mixed text with numbers, whose numbers are in vf too). As in the
-- SQLite backend, the values of one signal in one batch share a kind: ints mixed with
-- floats are floats.
-- batch and pos are the order of arrival: samples at equal times keep it.
CREATE TABLE samples (
    stream_id bigint           NOT NULL,
    series_id bigint           NOT NULL,
    t         bigint           NOT NULL,
    batch     bigint           NOT NULL,
    pos       integer          NOT NULL,
    kind      text             NOT NULL,
    vi        bigint,
    vf        double precision,
    vb        boolean,
    vj        text
) PARTITION BY RANGE (t);
CREATE INDEX samples_by_stream_time ON samples (stream_id, t, series_id);

CREATE SEQUENCE batch_ids;

-- The newest value of each series (by time; of equal times, the later arrival).
CREATE TABLE latest (
    series_id bigint PRIMARY KEY REFERENCES series (id) ON DELETE CASCADE,
    t         bigint NOT NULL,
    batch     bigint NOT NULL,
    value     text   NOT NULL   -- JSON, as the value was sent
);

-- Batches already stored, by device and sequence number: a resent batch is stored once.
CREATE TABLE ingested (
    device_id bigint NOT NULL,
    seq       bigint NOT NULL,
    at_ns     bigint NOT NULL,
    PRIMARY KEY (device_id, seq)
);
CREATE INDEX ingested_by_time ON ingested (at_ns);
