-- Remote twins (federation/remote.py): DT documents fetched from other instances (a Twinbase
-- site imported, or a relation followed), kept read-only. One row per dt-id; `document` is the
-- document as fetched (JSON text), `url` where it was fetched (its hosting-iri), `source` the
-- site imported or 'relation'. `etag` and `last_modified` are the validators of the last 200,
-- sent again so an unchanged document costs a 304; `state` is reachable, stale or gone.
CREATE TABLE remote_twins (
    id            INTEGER PRIMARY KEY,
    dt_id         TEXT NOT NULL UNIQUE,
    url           TEXT NOT NULL,
    name          TEXT NOT NULL DEFAULT '',
    document      TEXT NOT NULL DEFAULT '{}',
    source        TEXT NOT NULL,
    fetched_ns    INTEGER NOT NULL,
    checked_ns    INTEGER NOT NULL,
    etag          TEXT,
    last_modified TEXT,
    state         TEXT NOT NULL DEFAULT 'reachable',
    error         TEXT NOT NULL DEFAULT ''
);
CREATE INDEX remote_twins_url ON remote_twins (url);
INSERT INTO id_counters (name, next) VALUES ('remote_twins', 1);
