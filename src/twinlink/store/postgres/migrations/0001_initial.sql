-- Commands and device properties, as in the SQLite backend's history.db (its migration
-- 0002): the same columns, typed for PostgreSQL. Times are integer ns since the epoch.

-- The command log. Live state is kept in memory by the command service; every change of
-- state is written here. `args` and `result` are JSON text, stored as written (jsonb would
-- reorder keys and drop duplicates; the API answers what was sent).
CREATE TABLE commands (
    id           text    PRIMARY KEY,
    twin_id      bigint  NOT NULL,
    device_id    bigint  NOT NULL,
    device       text    NOT NULL,   -- the device's name when the command was sent
    name         text    NOT NULL,
    args         text    NOT NULL,
    -- pending | delivered | succeeded | failed | expired
    state        text    NOT NULL,
    queued       boolean NOT NULL,   -- kept for an offline device, sent when it connects
    sent_by      text,               -- the user name of the sender
    created_ns   bigint  NOT NULL,
    expires_ns   bigint  NOT NULL,
    delivered_ns bigint,
    finished_ns  bigint,
    result       text,
    error        text,
    late_status  text                -- a result that came after expiry: succeeded | failed
);
CREATE INDEX commands_by_twin ON commands (twin_id, created_ns);
CREATE INDEX commands_open ON commands (created_ns) WHERE state IN ('pending', 'delivered');

-- Reported (by the device) and desired (by people) values of device properties, one row per
-- device and property name. A NULL value means "none": not reported yet, or not desired.
CREATE TABLE device_properties (
    device_id   bigint NOT NULL,
    name        text   NOT NULL,
    reported    text,                -- JSON value
    reported_ns bigint,
    desired     text,                -- JSON value
    desired_ns  bigint,
    PRIMARY KEY (device_id, name)
);

-- The version of each device's desired properties, raised by every desired change.
-- `device_created_ns` tells a device apart from a later one that got the same id.
CREATE TABLE device_property_versions (
    device_id         bigint PRIMARY KEY,
    twin_id           bigint NOT NULL,
    device_created_ns bigint NOT NULL,
    version           bigint NOT NULL
);
CREATE INDEX device_property_versions_by_twin ON device_property_versions (twin_id);
