-- Twin and device ids are keys in history.db (another file, so no foreign key can guard
-- them). SQLite reuses the largest rowid after it is deleted; these counters make sure an id
-- is never handed out twice, so a new twin can never inherit a deleted twin's history,
-- commands or properties.
CREATE TABLE id_counters (
    name TEXT PRIMARY KEY,
    next INTEGER NOT NULL
) WITHOUT ROWID;
INSERT INTO id_counters (name, next) SELECT 'twins', COALESCE(MAX(id), 0) + 1 FROM twins;
INSERT INTO id_counters (name, next) SELECT 'devices', COALESCE(MAX(id), 0) + 1 FROM devices;
