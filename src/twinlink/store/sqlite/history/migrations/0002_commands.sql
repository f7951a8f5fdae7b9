-- Commands and device properties live beside telemetry in history.db, so their writes share
-- the group commits of the data plane (one fsync for many commands and batches).

-- The command log. Live state is kept in memory by the command service; every change of
-- state is written here within one group commit. `args` and `result` are JSON text.
CREATE TABLE commands (
    id           TEXT    PRIMARY KEY,
    twin_id      INTEGER NOT NULL,
    device_id    INTEGER NOT NULL,
    device       TEXT    NOT NULL,   -- the device's name when the command was sent
    name         TEXT    NOT NULL,
    args         TEXT    NOT NULL,
    -- pending | delivered | succeeded | failed | expired
    state        TEXT    NOT NULL,
    queued       INTEGER NOT NULL,   -- 1: kept for an offline device, sent when it connects
    sent_by      TEXT,               -- the user name of the sender
    created_ns   INTEGER NOT NULL,
    expires_ns   INTEGER NOT NULL,
    delivered_ns INTEGER,
    finished_ns  INTEGER,
    result       TEXT,
    error        TEXT,
    late_status  TEXT                -- a result that came after expiry: succeeded | failed
) WITHOUT ROWID;
CREATE INDEX commands_by_twin ON commands (twin_id, created_ns);
CREATE INDEX commands_open ON commands (state) WHERE state IN ('pending', 'delivered');

-- Reported (by the device) and desired (by people) values of device properties, one row per
-- device and property name. A NULL value means "none": not reported yet, or not desired.
CREATE TABLE device_properties (
    device_id   INTEGER NOT NULL,
    name        TEXT    NOT NULL,
    reported    TEXT,                -- JSON value
    reported_ns INTEGER,
    desired     TEXT,                -- JSON value
    desired_ns  INTEGER,
    PRIMARY KEY (device_id, name)
) WITHOUT ROWID;

-- The version of each device's desired properties, raised by every desired change.
-- `device_created_ns` tells a device apart from a later one that got the same id.
CREATE TABLE device_property_versions (
    device_id         INTEGER PRIMARY KEY,
    twin_id           INTEGER NOT NULL,
    device_created_ns INTEGER NOT NULL,
    version           INTEGER NOT NULL
);
CREATE INDEX device_property_versions_by_twin ON device_property_versions (twin_id);
