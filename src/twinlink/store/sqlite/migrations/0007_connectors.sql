-- Connectors: the platform reaching out to devices that cannot run the SDK (a UDP datasource,
-- an OPC UA server). Each speaks for one device of its twin and goes with it. `settings` is
-- the connector's JSON configuration without secrets; `secret` holds its secret fields
-- (passwords, keys), encrypted with the server's key; `enabled` says whether it runs (it is
-- started again when the server starts).
CREATE TABLE connectors (
    id          INTEGER PRIMARY KEY,
    twin_id     INTEGER NOT NULL REFERENCES twins(id) ON DELETE CASCADE,
    device_id   INTEGER NOT NULL REFERENCES devices(id) ON DELETE CASCADE,
    name        TEXT NOT NULL,
    kind        TEXT NOT NULL,
    settings    TEXT NOT NULL,
    secret      BLOB,
    enabled     INTEGER NOT NULL DEFAULT 1,
    created_by  INTEGER REFERENCES users(id) ON DELETE SET NULL,
    created_ns  INTEGER NOT NULL,
    modified_ns INTEGER NOT NULL,
    UNIQUE (twin_id, name)
);
CREATE INDEX connectors_by_device ON connectors (device_id);
INSERT INTO id_counters (name, next) VALUES ('connectors', 1);
