"""Two `twinlink up` nodes on one PostgreSQL database share a gateway service's upstream token
(docs/scale-out.md): the second node takes the token the first logged in for, and requests
refused through both nodes at once, after the upstream revoked the token, make one login
between them, not one per node."""

from __future__ import annotations

import asyncio
from collections.abc import Iterator

import httpx
import pytest

from tests.conftest import Server, stop_server
from tests.integration._gateway import add_service, echoed, new_twin, path
from tests.integration._kafka import KafkaBroker
from tests.integration._kafka import kafka as kafka
from tests.integration._postgres import PostgresCluster
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._scale_out import cluster
from tests.integration._upstream import Upstream
from tests.integration._upstream import upstream as upstream  # module fixture

pytestmark = pytest.mark.integration


@pytest.fixture(scope="module")
def nodes(
    postgres_cluster: PostgresCluster,
    kafka: KafkaBroker,
    tmp_path_factory: pytest.TempPathFactory,
) -> Iterator[tuple[Server, Server]]:
    with cluster(postgres_cluster, kafka) as shared:
        a = shared.start(tmp_path_factory.mktemp("node-a"))
        try:
            b = shared.start(tmp_path_factory.mktemp("node-b"), token=a.admin_token)
            try:
                yield a, b
            finally:
                stop_server(b)
        finally:
            stop_server(a)


async def test_nodes_refused_together_make_one_login(
    nodes: tuple[Server, Server], upstream: Upstream
) -> None:
    a, b = nodes
    s = upstream.secrets
    auth = {
        "method": "custom_login",
        "login_url": f"{upstream.url}/_auth/login",
        "body": {"user": s.login_user, "password": s.login_password},
        "token_path": "data.token",
        "expires_in_path": "data.expires_in",
        "template": "Token {token}",
    }
    slug = new_twin(a)
    with a.admin as admin:
        add_service(admin, slug, "svc", upstream.base("login"), auth=auth)
    logins = upstream.attempts["login"]
    with a.admin as admin:
        echoed(admin.get(path(slug, "svc", "echo/first")))
    with b.admin as admin:  # b takes the token a logged in for
        echoed(admin.get(path(slug, "svc", "echo/first")))
    assert upstream.attempts["login"] == logins + 1

    upstream.revoke_all()
    # All 20 are refused with the old token before any is answered: without the shared
    # token, each node would log in (and with an upstream that keeps one token per client,
    # each login would revoke the other node's).
    upstream.hold_refusals(20)
    headers = {"Authorization": f"Bearer {a.admin_token}"}
    async with (
        httpx.AsyncClient(base_url=a.url, headers=headers, timeout=30) as to_a,
        httpx.AsyncClient(base_url=b.url, headers=headers, timeout=30) as to_b,
    ):
        url = path(slug, "svc", "echo/together")
        answers = await asyncio.gather(*(c.get(url) for c in [to_a, to_b] * 10))
    assert [r.status_code for r in answers] == [200] * 20, [r.text for r in answers][:3]
    assert upstream.attempts["login"] == logins + 2  # the first, and one renewal for both
    sent = {h[1] for r in answers for h in r.json()["headers"] if h[0] == "authorization"}
    assert sent == {f"Token {upstream.all_tokens[-1]}"}
