-- Processors: blueprints run beside a twin's live data, each in its own worker process.
-- `spec` is the processor's JSON configuration (source, output, inputs, params, rates, limits);
-- `enabled` says whether it runs (it is started again when the server starts).
CREATE TABLE processors (
    id          INTEGER PRIMARY KEY,
    twin_id     INTEGER NOT NULL REFERENCES twins(id) ON DELETE CASCADE,
    name        TEXT NOT NULL,
    blueprint   TEXT NOT NULL,
    spec        TEXT NOT NULL,
    enabled     INTEGER NOT NULL DEFAULT 1,
    created_by  INTEGER REFERENCES users(id) ON DELETE SET NULL,
    created_ns  INTEGER NOT NULL,
    modified_ns INTEGER NOT NULL,
    UNIQUE (twin_id, name)
);

-- What happened to a processor: started, stopped, crashed (with its cause), restarted,
-- memory limit, alarms raised by trigger blueprints. Pruned to the newest rows per processor.
CREATE TABLE processor_events (
    id           INTEGER PRIMARY KEY,
    processor_id INTEGER NOT NULL REFERENCES processors(id) ON DELETE CASCADE,
    time_ns      INTEGER NOT NULL,
    kind         TEXT NOT NULL,
    message      TEXT NOT NULL,
    data         TEXT NOT NULL DEFAULT '{}'
);
CREATE INDEX processor_events_by_processor ON processor_events (processor_id, id);

-- FMUs uploaded to a twin; the file itself is in the data dir under fmus/<twin id>/<name>.
CREATE TABLE fmus (
    id          INTEGER PRIMARY KEY,
    twin_id     INTEGER NOT NULL REFERENCES twins(id) ON DELETE CASCADE,
    name        TEXT NOT NULL,
    sha256      TEXT NOT NULL,
    size        INTEGER NOT NULL,
    info        TEXT NOT NULL,
    uploaded_by INTEGER REFERENCES users(id) ON DELETE SET NULL,
    uploaded_ns INTEGER NOT NULL,
    UNIQUE (twin_id, name)
);

INSERT INTO id_counters (name, next) VALUES ('processors', 1);
