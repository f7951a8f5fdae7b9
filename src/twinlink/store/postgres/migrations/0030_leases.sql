-- Leases: which node runs each processor and connector (store/leases.py). One row per item
-- that a node holds or held; `expires_at` is the database's clock (now() + the TTL), never a
-- node's, and a row past it is free for any node to take.
CREATE TABLE leases (
    name       text        PRIMARY KEY,   -- 'processor:12', 'connector:3'
    holder     text        NOT NULL,      -- the node's run: host:pid:random
    expires_at timestamptz NOT NULL
);
CREATE INDEX leases_by_holder ON leases (holder);
