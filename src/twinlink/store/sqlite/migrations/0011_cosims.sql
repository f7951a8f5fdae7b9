-- Co-simulations made through the API (cosim/service.py): a system read from an uploaded
-- file, its files in data_dir/cosims/<id>/, and its latest run. `fmus` maps each FMU
-- reference of the system to its file in that folder (JSON), `system` is the system's view
-- made once at create (JSON), `result_columns` the latest run's result columns (JSON list).
-- `node` is the node that runs (ran) it: a server starting again fails the runs it left.
CREATE TABLE cosims (
    id          INTEGER PRIMARY KEY,
    name        TEXT NOT NULL,
    owner_id    INTEGER REFERENCES users(id) ON DELETE SET NULL,
    twin        TEXT,
    prefix      TEXT NOT NULL DEFAULT '',
    stream      TEXT NOT NULL,
    mode        TEXT NOT NULL,
    factor      REAL NOT NULL DEFAULT 1.0,
    state       TEXT NOT NULL,
    format      TEXT NOT NULL,
    document    TEXT NOT NULL,
    fmus        TEXT NOT NULL DEFAULT '{}',
    system      TEXT NOT NULL DEFAULT '{}',
    result_columns TEXT NOT NULL DEFAULT '[]',
    row_count   INTEGER NOT NULL DEFAULT 0,
    progress    REAL NOT NULL DEFAULT 0,
    sim_time    REAL,
    message     TEXT NOT NULL DEFAULT '',
    created_ns  INTEGER NOT NULL,
    started_ns  INTEGER,
    ended_ns    INTEGER,
    node        TEXT
);
CREATE INDEX cosims_running ON cosims (state) WHERE state = 'running';
INSERT INTO id_counters (name, next) VALUES ('cosims', 1);
