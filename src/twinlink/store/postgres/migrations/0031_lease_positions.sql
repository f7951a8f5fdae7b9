-- Positions: how far the item of a lease got in its input (store/leases.py), so the node
-- that takes a processor over from a dead one replays from history what it had not
-- processed yet (processors/catchup.py). Written by the lease's holder with its renewals,
-- never moved back; forgotten when the item is stopped on purpose (disabled, deleted).
CREATE TABLE lease_positions (
    name     text        PRIMARY KEY,          -- the lease's: 'processor:12'
    stream   text        NOT NULL,             -- the input stream the position is in
    t        bigint      NOT NULL,             -- the newest input sample time processed, ns
    saved_at timestamptz NOT NULL DEFAULT now()
);
