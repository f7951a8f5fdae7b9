-- Users, API tokens, twins with their privacy parts, per-twin roles and relations.
CREATE TABLE users (
    id            INTEGER PRIMARY KEY,
    username      TEXT NOT NULL UNIQUE COLLATE NOCASE,
    password_hash TEXT,
    is_admin      INTEGER NOT NULL DEFAULT 0,
    groups_json   TEXT NOT NULL DEFAULT '[]',
    disabled      INTEGER NOT NULL DEFAULT 0,
    created_ns    INTEGER NOT NULL
);

CREATE TABLE api_tokens (
    id           INTEGER PRIMARY KEY,
    user_id      INTEGER NOT NULL REFERENCES users(id) ON DELETE CASCADE,
    name         TEXT NOT NULL,
    token_hash   BLOB NOT NULL UNIQUE,
    prefix       TEXT NOT NULL,
    kind         TEXT NOT NULL DEFAULT 'api',
    created_ns   INTEGER NOT NULL,
    expires_ns   INTEGER,
    last_used_ns INTEGER,
    revoked_ns   INTEGER
);
CREATE INDEX api_tokens_user ON api_tokens(user_id);

CREATE TABLE twins (
    id          INTEGER PRIMARY KEY,
    slug        TEXT NOT NULL UNIQUE,
    dt_id       TEXT NOT NULL UNIQUE,
    name        TEXT NOT NULL,
    created_ns  INTEGER NOT NULL,
    modified_ns INTEGER NOT NULL
);

CREATE TABLE twin_parts (
    twin_id INTEGER NOT NULL REFERENCES twins(id) ON DELETE CASCADE,
    privacy TEXT NOT NULL,
    body    TEXT NOT NULL,
    PRIMARY KEY (twin_id, privacy)
) WITHOUT ROWID;

CREATE TABLE twin_roles (
    twin_id INTEGER NOT NULL REFERENCES twins(id) ON DELETE CASCADE,
    user_id INTEGER NOT NULL REFERENCES users(id) ON DELETE CASCADE,
    role    TEXT NOT NULL CHECK (role IN ('owner', 'editor', 'viewer')),
    PRIMARY KEY (twin_id, user_id)
) WITHOUT ROWID;
CREATE INDEX twin_roles_user ON twin_roles(user_id);

-- source is the parent of target ('parent'), or source < target are siblings ('sibling').
-- An edge exists while any twin's document declares it; declared_by is that twin's id.
CREATE TABLE relations (
    source      TEXT NOT NULL,
    kind        TEXT NOT NULL CHECK (kind IN ('parent', 'sibling')),
    target      TEXT NOT NULL,
    declared_by TEXT NOT NULL,
    privacy     TEXT NOT NULL,
    PRIMARY KEY (source, kind, target, declared_by)
) WITHOUT ROWID;
CREATE INDEX relations_target ON relations(target, kind);
CREATE INDEX relations_declared_by ON relations(declared_by);
