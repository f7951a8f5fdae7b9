-- The API gateway (the Data Link): settings of each twin's services and the audit log.
-- A service comes from the DT document (a feature with an apiAddress; `source` 'document',
-- its URL read from the document) or was added by API (`source` 'api', URL in `settings`).
-- `settings` is JSON without secrets; `secret` holds the credentials' secret fields,
-- encrypted with the server's key; `auth_origin` is the scheme://host:port they were set for,
-- so credentials are never sent to an address changed after they were set.
CREATE TABLE gateway_services (
    id          INTEGER PRIMARY KEY,
    twin_id     INTEGER NOT NULL REFERENCES twins(id) ON DELETE CASCADE,
    name        TEXT NOT NULL,
    source      TEXT NOT NULL,
    settings    TEXT NOT NULL,
    secret      BLOB,
    auth_origin TEXT,
    created_by  INTEGER REFERENCES users(id) ON DELETE SET NULL,
    created_ns  INTEGER NOT NULL,
    modified_ns INTEGER NOT NULL,
    UNIQUE (twin_id, name)
);

-- Every request the gateway answered on a service path. Kept without foreign keys: the
-- record of what happened outlives the twin, service or user it names.
CREATE TABLE gateway_audit (
    id          INTEGER PRIMARY KEY,
    time_ns     INTEGER NOT NULL,
    twin        TEXT NOT NULL,
    service     TEXT NOT NULL,
    caller      TEXT NOT NULL,
    method      TEXT NOT NULL,
    path        TEXT NOT NULL,
    status      INTEGER NOT NULL,
    outcome     TEXT NOT NULL,
    bytes_in    INTEGER NOT NULL,
    bytes_out   INTEGER NOT NULL,
    upstream_ms REAL,
    total_ms    REAL NOT NULL
);
CREATE INDEX gateway_audit_by_time ON gateway_audit (time_ns);
CREATE INDEX gateway_audit_by_service ON gateway_audit (twin, service, id);
