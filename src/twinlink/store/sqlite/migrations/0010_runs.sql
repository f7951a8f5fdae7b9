-- Lifecycle runs (DTaaS, deploy/runs.py): one row per run of a deployment's phase script,
-- kept for good (as their logs, data_dir/runs/<id>.log). `deployment` and `twin` are as they
-- were at the run's start: the deployment may be gone since. `node` is the node that runs
-- (ran) it; a queued run without one waits for a node with its `runner_tags` (a JSON list),
-- which claims it. `token_id` is its scoped token, revoked when it ends.
CREATE TABLE runs (
    id            INTEGER PRIMARY KEY,
    deployment_id INTEGER NOT NULL,
    deployment    TEXT NOT NULL,
    twin          TEXT NOT NULL,
    phase         TEXT NOT NULL,
    state         TEXT NOT NULL,
    started_by    INTEGER REFERENCES users(id) ON DELETE SET NULL,
    owner_id      INTEGER REFERENCES users(id) ON DELETE SET NULL,
    created_ns    INTEGER NOT NULL,
    timeout_s     INTEGER NOT NULL DEFAULT 0,
    memory_mb     INTEGER NOT NULL DEFAULT 0,
    runner_tags   TEXT NOT NULL DEFAULT '[]',
    exit_code     INTEGER,
    started_ns    INTEGER,
    ended_ns      INTEGER,
    node          TEXT,
    pid           INTEGER,
    error         TEXT,
    token_id      INTEGER
);
CREATE INDEX runs_by_deployment ON runs (deployment_id, id);
CREATE INDEX runs_active ON runs (state) WHERE state IN ('queued', 'running');
INSERT INTO id_counters (name, next) VALUES ('runs', 1);

-- A scoped token (auth/scopes.py) reaches only what its scope allows: a run's is
-- `twin:<slug>`. NULL: an ordinary token.
ALTER TABLE api_tokens ADD COLUMN scope TEXT;
