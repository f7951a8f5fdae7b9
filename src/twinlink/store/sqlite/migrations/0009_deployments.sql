-- Deployments (DTaaS): twin packages brought to life (deploy/). `journal` is the JSON list of
-- what the deployment made, in order ({type, name, spec}); `secrets` its device tokens, sealed
-- with the server's key. The twin and what it holds are its own tables' rows: a deployment
-- names them, it does not own their rows (terminate keeps the twin). A name is taken by one
-- live deployment at a time; terminated and failed ones stay as a record.
CREATE TABLE deployments (
    id          INTEGER PRIMARY KEY,
    name        TEXT NOT NULL,
    package     TEXT NOT NULL,
    package_ref TEXT NOT NULL,
    parameters  TEXT NOT NULL DEFAULT '{}',
    state       TEXT NOT NULL,
    twin        TEXT NOT NULL,
    journal     TEXT NOT NULL DEFAULT '[]',
    secrets     BLOB,
    created_by  INTEGER REFERENCES users(id) ON DELETE SET NULL,
    created_ns  INTEGER NOT NULL,
    updated_ns  INTEGER NOT NULL,
    error       TEXT
);
CREATE UNIQUE INDEX deployments_live_name ON deployments (name)
    WHERE state NOT IN ('terminated', 'failed');
CREATE INDEX deployments_by_name ON deployments (name, id);
INSERT INTO id_counters (name, next) VALUES ('deployments', 1);
