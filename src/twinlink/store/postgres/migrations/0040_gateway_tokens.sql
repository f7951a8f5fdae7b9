-- The gateway's upstream tokens, shared by the nodes (store/tokens.py): one row per service,
-- for the version of its credentials `fingerprint` names. `sealed` is the token encrypted by
-- the gateway (auth/vault.py), never the token itself. Times are the database's clock. The
-- last failed login is kept with its message, so the nodes that waited for it share it.
CREATE TABLE gateway_tokens (
    service     text        PRIMARY KEY,   -- 'twin 3 service weather'
    fingerprint text        NOT NULL,      -- of the credentials the token was got with
    sealed      bytea,                     -- NULL: no token (only a failure so far)
    renew_at    timestamptz,
    expires_at  timestamptz,
    failed_at   timestamptz,               -- the last failed login, if after the last token
    failure     text
);
