-- The library (issue 16): reusable assets, each (scope, kind, name), with immutable versions
-- named by the digest of their manifest, tags that point at versions, and holds that keep a
-- version in use (by a processor, a deployment) from being deleted. A version's `files` is its
-- manifest as JSON ([{path, sha256, size, executable}]); the files themselves are blobs in the
-- data dir, kept while some version lists them. `created_by` is a user name, kept for display
-- when the user is gone.
CREATE TABLE library_assets (
    id          INTEGER PRIMARY KEY,
    scope       TEXT NOT NULL,
    kind        TEXT NOT NULL,
    name        TEXT NOT NULL,
    description TEXT NOT NULL DEFAULT '',
    keywords    TEXT NOT NULL DEFAULT '[]',
    licence     TEXT NOT NULL DEFAULT '',
    author      TEXT NOT NULL DEFAULT '',
    created_by  TEXT,
    created_ns  INTEGER NOT NULL,
    updated_ns  INTEGER NOT NULL,
    UNIQUE (scope, kind, name)
);
CREATE TABLE library_versions (
    asset_id    INTEGER NOT NULL REFERENCES library_assets(id) ON DELETE CASCADE,
    digest      TEXT NOT NULL,
    files       TEXT NOT NULL,
    size        INTEGER NOT NULL,
    meta        TEXT NOT NULL DEFAULT '{}',
    created_by  TEXT,
    created_ns  INTEGER NOT NULL,
    PRIMARY KEY (asset_id, digest)
);
CREATE TABLE library_tags (
    asset_id    INTEGER NOT NULL,
    tag         TEXT NOT NULL,
    digest      TEXT NOT NULL,
    updated_ns  INTEGER NOT NULL,
    PRIMARY KEY (asset_id, tag),
    FOREIGN KEY (asset_id, digest) REFERENCES library_versions(asset_id, digest) ON DELETE CASCADE
);
CREATE TABLE library_holds (
    asset_id    INTEGER NOT NULL,
    digest      TEXT NOT NULL,
    holder      TEXT NOT NULL,
    PRIMARY KEY (asset_id, digest, holder),
    FOREIGN KEY (asset_id, digest) REFERENCES library_versions(asset_id, digest) ON DELETE CASCADE
);
CREATE INDEX library_holds_by_holder ON library_holds (holder);
INSERT INTO id_counters (name, next) VALUES ('library_assets', 1);
