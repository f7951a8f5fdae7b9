-- Devices: the physical (or simulated) data sources of a twin, each with its own credential.
CREATE TABLE devices (
    id           INTEGER PRIMARY KEY,
    twin_id      INTEGER NOT NULL REFERENCES twins(id) ON DELETE CASCADE,
    name         TEXT NOT NULL,
    description  TEXT NOT NULL DEFAULT '',
    token_hash   BLOB NOT NULL UNIQUE,
    prefix       TEXT NOT NULL,
    created_ns   INTEGER NOT NULL,
    last_seen_ns INTEGER,
    UNIQUE (twin_id, name)
);
