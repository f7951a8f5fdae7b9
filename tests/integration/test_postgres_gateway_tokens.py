"""The gateway's upstream tokens shared by the nodes of one PostgreSQL store (store/tokens.py,
gateway/credentials/shared.py): two nodes are two pools on one database, each with its own
credentials object, against the real test upstream's login endpoint. However many requests of
both nodes are refused at once, the upstream sees one login; a node starting later takes the
stored token; changed credentials log in again; a failed login is shared, not retried per
node; the database holds the token sealed."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator, Awaitable, Callable, Iterator
from typing import Any

import asyncpg
import pytest
from cryptography.fernet import Fernet

from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import postgres_dsn as postgres_dsn
from tests.integration._upstream import Upstream
from tests.integration._upstream import upstream as upstream  # module fixture
from twinlink.auth.vault import Vault
from twinlink.gateway.credentials import token
from twinlink.gateway.credentials.base import Headers, RefreshError
from twinlink.gateway.credentials.login import CustomLogin, CustomLoginConfig
from twinlink.gateway.credentials.shared import TokenShare
from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.postgres.tokens import PostgresTokens

pytestmark = [pytest.mark.integration, pytest.mark.usefixtures("postgres_cluster")]

SERVICE = "twin 1 service svc"


class Login(CustomLogin):
    """The custom login, with a hook run before each login (to hold it until the other node
    waits for it)."""

    before: Callable[[], Awaitable[None]] | None = None

    async def fetch(self) -> tuple[str, float | None]:
        if self.before is not None:
            await self.before()
        return await super().fetch()


@pytest.fixture(autouse=True)
def fresh_upstream(upstream: Upstream) -> Iterator[None]:
    yield
    upstream.token_endpoints_down = False
    upstream.expires_in = 3600.0


@pytest.fixture
async def nodes(postgres_dsn: str) -> AsyncIterator[list[PostgresTokens]]:
    """Three nodes' shared tokens: a pool each on the one database."""
    dbs = [PostgresDatabase(postgres_dsn) for _ in range(3)]
    for db in dbs:
        await db.open()
    try:
        yield [PostgresTokens(db) for db in dbs]
    finally:
        for db in dbs:
            await db.close()


@pytest.fixture(scope="module")
def vault() -> Vault:
    return Vault(Fernet.generate_key())  # TWINLINK_SECRET_KEY, the same on every node


def settings(upstream: Upstream, **extra: Any) -> CustomLoginConfig:
    s = upstream.secrets
    return CustomLoginConfig.model_validate(
        {
            "method": "custom_login",
            "login_url": f"{upstream.url}/_auth/login",
            "body": {"user": s.login_user, "password": s.login_password, **extra},
            "token_path": "data.token",
            "expires_in_path": "data.expires_in",
            "template": "Token {token}",
        }
    )


def node(tokens: PostgresTokens, vault: Vault, config: CustomLoginConfig) -> Login:
    credentials = Login(config)
    credentials.share = TokenShare(tokens, vault, SERVICE, config)
    return credentials


def sent(credentials: Login) -> str:
    headers: Headers = []
    credentials.apply(headers, [])
    [(name, value)] = headers
    assert name == b"authorization"
    return value.decode()


async def refused_together(credentials: list[Login], each: int) -> list[BaseException | None]:
    """`each` requests per node report the token they used as refused, all at once."""
    generations = [c.generation for c in credentials]
    calls = [c.refresh(g) for c, g in zip(credentials, generations, strict=True)] * each
    return await asyncio.gather(*calls, return_exceptions=True)


async def a_lock_waited_for(dsn: str) -> None:
    """Until a node waits for the advisory lock of a refresh (held by the other's login)."""
    conn = await asyncpg.connect(dsn)
    try:
        async with asyncio.timeout(20):
            sql = "SELECT count(*) FROM pg_locks WHERE locktype = 'advisory' AND NOT granted"
            while not await conn.fetchval(sql):
                await asyncio.sleep(0.01)  # polling the server's state, with a deadline
    finally:
        await conn.close()


async def test_two_nodes_refused_together_make_one_login(
    nodes: list[PostgresTokens], vault: Vault, upstream: Upstream
) -> None:
    config = settings(upstream)
    a, b = node(nodes[0], vault, config), node(nodes[1], vault, config)
    logins = upstream.attempts["login"]
    await a.ready()
    await b.ready()  # starts after a: takes a's token
    assert upstream.attempts["login"] == logins + 1
    assert sent(a) == sent(b) == f"Token {upstream.all_tokens[-1]}"

    upstream.revoke_all()  # both nodes' requests are refused now
    outcomes = await refused_together([a, b], each=10)
    assert outcomes == [None] * 20
    assert upstream.attempts["login"] == logins + 2  # one renewal for the 20 refusals
    assert sent(a) == sent(b) == f"Token {upstream.all_tokens[-1]}"
    assert a.refreshes + b.refreshes == 2


async def test_a_node_starting_later_logs_in_not_at_all(
    nodes: list[PostgresTokens], vault: Vault, upstream: Upstream
) -> None:
    config = settings(upstream)
    await node(nodes[0], vault, config).ready()
    logins = upstream.attempts["login"]
    later = [node(nodes[2], vault, config) for _ in range(5)]  # restarts of one node
    await asyncio.gather(*(c.ready() for c in later))
    assert upstream.attempts["login"] == logins
    assert {sent(c) for c in later} == {f"Token {upstream.all_tokens[-1]}"}


async def test_changed_credentials_log_in_again(
    nodes: list[PostgresTokens], vault: Vault, upstream: Upstream
) -> None:
    old = node(nodes[0], vault, settings(upstream))
    await old.ready()
    logins = upstream.attempts["login"]
    changed = node(nodes[1], vault, settings(upstream, tenant="other"))
    await changed.ready()
    assert upstream.attempts["login"] == logins + 1
    assert sent(changed) != sent(old)
    assert changed.share is not None and old.share is not None
    assert changed.share.fingerprint != old.share.fingerprint


async def test_a_failed_login_is_shared_by_the_nodes_that_waited_for_it(
    nodes: list[PostgresTokens], vault: Vault, upstream: Upstream, postgres_dsn: str
) -> None:
    config = settings(upstream)
    a, b = node(nodes[0], vault, config), node(nodes[1], vault, config)
    upstream.token_endpoints_down = True
    logins = upstream.attempts["login"]
    a.before = lambda: a_lock_waited_for(postgres_dsn)  # b waits for a's login

    outcomes = await asyncio.gather(*(c.ready() for c in [a, b] * 10), return_exceptions=True)
    assert all(isinstance(o, RefreshError) for o in outcomes), outcomes
    assert upstream.attempts["login"] == logins + 1
    assert "503" in str(outcomes[0]) and b.last_error == a.last_error

    a.before = None
    upstream.token_endpoints_down = False  # the next request logs in again, and works
    await b.ready()
    assert upstream.attempts["login"] == logins + 2
    assert sent(b) == f"Token {upstream.all_tokens[-1]}"


async def test_the_database_holds_the_token_sealed(
    nodes: list[PostgresTokens], vault: Vault, upstream: Upstream, postgres_dsn: str
) -> None:
    await node(nodes[0], vault, settings(upstream)).ready()
    conn = await asyncpg.connect(postgres_dsn)
    try:
        row = await conn.fetchrow("SELECT * FROM gateway_tokens WHERE service = $1", SERVICE)
    finally:
        await conn.close()
    stored = repr(dict(row)).encode() + bytes(row["sealed"])
    assert upstream.all_tokens[-1].encode() not in stored
    assert upstream.secrets.login_password.encode() not in stored
    assert vault.unseal(row["sealed"]) == {"value": f"Token {upstream.all_tokens[-1]}"}


async def test_another_secret_key_cannot_read_the_stored_token(
    nodes: list[PostgresTokens], vault: Vault, upstream: Upstream
) -> None:
    config = settings(upstream)
    await node(nodes[0], vault, config).ready()
    other = Vault(Fernet.generate_key())
    stranger = node(nodes[1], other, config)
    # Its fingerprint differs (keyed): it logs in for itself rather than fail on the row.
    logins = upstream.attempts["login"]
    await stranger.ready()
    assert upstream.attempts["login"] == logins + 1


async def test_nodes_renewing_a_due_token_together_make_one_login(
    nodes: list[PostgresTokens], vault: Vault, upstream: Upstream
) -> None:
    config = settings(upstream)
    a, b = node(nodes[0], vault, config), node(nodes[1], vault, config)
    upstream.expires_in = 1.0  # renewed 0.9 s after the login, on both nodes
    try:
        await a.ready()
        await b.ready()
    finally:
        upstream.expires_in = 3600.0  # the renewal's token lasts
    logins = upstream.attempts["login"]
    async with asyncio.timeout(20):
        while not (a.renewal_due() and b.renewal_due()):
            await asyncio.sleep(0.05)  # until the token is due on both, with a deadline
    await asyncio.gather(*(c.ready() for c in [a, b] * 10))
    assert upstream.attempts["login"] == logins + 1
    assert sent(a) == sent(b) == f"Token {upstream.all_tokens[-1]}"


async def test_a_node_that_cannot_wait_for_another_s_login_logs_in_alone(
    nodes: list[PostgresTokens],
    vault: Vault,
    upstream: Upstream,
    postgres_dsn: str,
    monkeypatch: pytest.MonkeyPatch,
    caplog: pytest.LogCaptureFixture,
) -> None:
    monkeypatch.setattr(token, "SHARED_WAIT_S", 0.2)
    credentials = node(nodes[0], vault, settings(upstream))
    stuck = await asyncpg.connect(postgres_dsn)  # another node's login that never ends
    try:
        async with stuck.transaction():
            await stuck.execute(
                "SELECT pg_advisory_xact_lock(hashtextextended('gateway_tokens:' || $1, 0))",
                SERVICE,
            )
            logins = upstream.attempts["login"]
            await credentials.ready()
    finally:
        await stuck.close()
    assert upstream.attempts["login"] == logins + 1
    assert sent(credentials) == f"Token {upstream.all_tokens[-1]}"
    [record] = [r for r in caplog.records if getattr(r, "event", "") == "token_not_shared"]
    assert "did not finish within 0.2 s" in record.getMessage()
