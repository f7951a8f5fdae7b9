"""Each processor and connector runs on exactly one node (store/leases.py, docs/scale-out.md):
the lease store's semantics on PostgreSQL (the database's clock, two holders racing for one
lease), and two `twinlink up` nodes on one database and one broker: a processor runs on one
of them, its output has each input batch once, and when that node is killed (kill -9) the
other takes the processor over and the output goes on, with the output of every batch
acknowledged while it ran nowhere (replayed from history) once; a connector likewise."""

from __future__ import annotations

import asyncio
import socket
from collections import Counter
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import asyncpg
import pytest

from tests.conftest import Server, stop_server
from tests.integration._kafka import KafkaBroker
from tests.integration._kafka import kafka as kafka
from tests.integration._live import device_twin
from tests.integration._postgres import PostgresCluster
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import postgres_dsn as postgres_dsn
from tests.integration._processors import BLUEPRINTS, T0, samples_until, watching
from tests.integration._processors import post as post_rows
from tests.integration._scale_out import Cluster, cluster
from tests.integration._util import apply, assert_problem, poll_until, twin_doc, unique
from tests.unit.test_leases import check_positions, check_semantics
from twinlink.store.leases import RENEW_S, TTL_S, new_holder
from twinlink.store.postgres.db import PostgresDatabase
from twinlink.store.postgres.leases import PostgresLeases

# The session's cluster and broker start before the module's first test, which the hygiene
# check then counts as the module's.
pytestmark = [pytest.mark.integration, pytest.mark.usefixtures("postgres_cluster", "kafka")]

# A dead node's items are taken over within TTL_S + RENEW_S of its last renewal; the rest
# is the margin of a shared, slow machine (a worker process to start, Kafka to join).
TAKEOVER_S = TTL_S + RENEW_S + 20


async def test_the_lease_store_keeps_the_semantics_on_postgres(postgres_dsn: str) -> None:
    db = PostgresDatabase(postgres_dsn)
    await db.open()
    try:
        await check_semantics(PostgresLeases(db))
        await check_positions(PostgresLeases(db))
    finally:
        await db.close()


async def test_two_holders_racing_for_free_leases_get_each_once(postgres_dsn: str) -> None:
    db = PostgresDatabase(postgres_dsn)
    await db.open()
    try:
        leases = PostgresLeases(db)
        names = [f"processor:{i}" for i in range(50)]
        holders = [new_holder() for _ in range(4)]
        got = await asyncio.gather(*(leases.acquire(names, h, 30) for h in holders))
        assert sorted(n for g in got for n in g) == sorted(names)  # each name once
        for holder, names_got in zip(holders, got, strict=True):
            assert await leases.held(holder) == names_got
    finally:
        await db.close()


async def test_expiry_is_the_databases_clock(postgres_dsn: str) -> None:
    db = PostgresDatabase(postgres_dsn)
    await db.open()
    try:
        await PostgresLeases(db).acquire(["connector:1"], "a", 30)
        conn = await asyncpg.connect(postgres_dsn)
        try:
            left = await conn.fetchval(
                "SELECT extract(epoch FROM expires_at - now()) FROM leases WHERE name = $1",
                "connector:1",
            )
        finally:
            await conn.close()
        assert 0 < float(left) <= 30
    finally:
        await db.close()


# -- two nodes --------------------------------------------------------------------------------


@pytest.fixture
def shared(postgres_cluster: PostgresCluster, kafka: KafkaBroker) -> Iterator[Cluster]:
    with cluster(postgres_cluster, kafka) as it:
        yield it


def start_node(shared: Cluster, data_dir: Path, token: str | None = None) -> Server:
    return shared.start(data_dir, token=token, TWINLINK_BLUEPRINTS_DIR=str(BLUEPRINTS))


def view(server: Server, path: str) -> dict[str, Any]:
    with server.admin as admin:
        r = admin.get(path)
    assert r.status_code == 200, r.text
    return r.json()  # type: ignore[no-any-return]


def runner(nodes: tuple[Server, ...], path: str, running: Any) -> Server:
    """The one node of `nodes` whose view of `path` says it runs it (polled until one does);
    the others say they do not."""

    def which() -> Server | None:
        found = [n for n in nodes if running(view(n, path))]
        assert len(found) <= 1, "it runs on more than one node"
        return found[0] if found else None

    node: Server = poll_until(which, f"{path} running on a node", TAKEOVER_S)
    return node


def rows(seq: int, n: int = 10) -> list[dict[str, Any]]:
    return [{"x": float(seq * 100 + i)} for i in range(n)]


def send(server: Server, device: str, seq: int) -> None:
    post_rows(server, device, seq, rows(seq), t0=T0 + seq * 10**9)


def times_of(seq: int) -> set[int]:
    return {T0 + seq * 10**9 + i * 10**6 for i in range(10)}


def test_a_processor_runs_on_one_node_and_moves_when_it_dies(
    shared: Cluster, tmp_path: Path
) -> None:
    a = start_node(shared, tmp_path / "node-a")
    b: Server | None = None
    try:
        slug, [device] = device_twin(a)
        with a.admin as admin:
            r = admin.post(f"/api/v1/twins/{slug}/processors", json={
                "name": "double", "blueprint": "expression", "output": "doubled",
                "params": {"outputs": {"y": "x * 2"}}})  # fmt: skip
        assert r.status_code == 201, r.text
        path = f"/api/v1/twins/{slug}/processors/double"
        # B starts with the processor in the database: A holds its lease, B leaves it be
        b = start_node(shared, tmp_path / "node-b", a.admin_token)
        first = runner((a, b), path, lambda v: v["state"] == "running")
        other = b if first is a else a
        assert view(other, path)["state"] == "stopped"
        assert (
            int(shared.fetchval("SELECT count(*) FROM leases WHERE name LIKE 'processor:%'")) == 1
        )

        with watching(other, slug, "doubled") as ws:
            for seq in (1, 2, 3):  # to both nodes: the one running it reads them off the bus
                send((a, b)[seq % 2], device, seq)
            got = samples_until(ws, lambda s: times_of(3) <= {x["time"] for x in s})
        seen = [x["time"] for x in got]
        assert len(seen) == len(set(seen)) == 30  # each input batch once, not once per node
        assert {x["values"]["y"] for x in got} == {2 * v["x"] for s in (1, 2, 3) for v in rows(s)}

        first.process.kill()  # kill -9: no clean stop, its lease left to expire
        first.process.wait()
        second = runner((other,), path, lambda v: v["state"] == "running")
        assert second is other
        with watching(other, slug, "doubled") as ws:
            send(other, device, 4)
            got = samples_until(ws, lambda s: times_of(4) <= {x["time"] for x in s})
        assert sorted(x["time"] for x in got) == sorted(times_of(4))  # the output goes on
    finally:
        for node in (a, b):
            if node is not None:
                stop_server(node)


def outputs(server: Server, slug: str, stream: str) -> Counter[int]:
    """How many times each output time is stored (outputs are stored by time, never merged)."""
    with server.admin as admin:
        r = admin.get(f"/api/v1/twins/{slug}/streams/{stream}/samples", params={"limit": 100_000})
    if r.status_code == 404:  # no output stored yet
        return Counter()
    assert r.status_code == 200, r.text
    assert r.json()["next_cursor"] is None
    return Counter(row["time"] for row in r.json()["rows"])


def test_a_processor_taken_over_from_a_killed_node_skips_nothing_and_repeats_nothing(
    shared: Cluster, tmp_path: Path
) -> None:
    a = start_node(shared, tmp_path / "node-a")
    b: Server | None = None
    try:
        b = start_node(shared, tmp_path / "node-b", a.admin_token)
        slug, [device] = device_twin(a)
        with a.admin as admin:
            r = admin.post(f"/api/v1/twins/{slug}/processors", json={
                "name": "double", "blueprint": "expression", "output": "doubled",
                "params": {"outputs": {"y": "x * 2"}}})  # fmt: skip
        assert r.status_code == 201, r.text
        path = f"/api/v1/twins/{slug}/processors/double"
        first = runner((a, b), path, lambda v: v["state"] == "running")
        other = b if first is a else a
        sent = [1, 2, 3]
        for seq in sent:
            send(other, device, seq)
        done = set().union(*(times_of(s) for s in sent))
        poll_until(lambda: done <= set(outputs(other, slug, "doubled")), "outputs of 1-3", 30)
        # ... and its position saved with a renewal: outputs made after it would be made again
        position = "SELECT t FROM lease_positions WHERE name LIKE 'processor:%'"
        poll_until(lambda: (shared.fetchval(position) or 0) >= max(done), "position saved", 30)

        first.process.kill()  # kill -9: its lease is left to expire, and nobody runs it
        first.process.wait()
        for seq in (4, 5):  # acknowledged before the lease expired: replayed from history
            send(other, device, seq)
            sent.append(seq)
        while view(other, path)["state"] != "running":  # and while the node takes it over
            assert len(sent) < 2000, "never taken over"
            sent.append(sent[-1] + 1)
            send(other, device, sent[-1])
        for _ in range(2):  # and live once it runs
            sent.append(sent[-1] + 1)
            send(other, device, sent[-1])

        expected = set().union(*(times_of(s) for s in sent))

        # The outputs of a node are stored in the order made, the last batch's last of all.
        def all_out() -> Counter[int] | None:
            got = outputs(other, slug, "doubled")
            return got if expected <= set(got) else None

        got = poll_until(all_out, "the output of every input batch", TAKEOVER_S)
        assert set(got) == expected  # nothing skipped
        assert [t for t, n in got.items() if n > 1] == []  # nothing made twice
        with other.admin as admin:
            r = admin.get(f"{path}/events", params={"kind": "caught_up"})
        assert r.status_code == 200, r.text
        [caught_up] = r.json()["events"]
        assert caught_up["data"]["replayed"] >= 20 and caught_up["data"]["skipped"] == 0
    finally:
        for node in (a, b):
            if node is not None:
                stop_server(node)


def free_udp_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def listening(v: dict[str, Any]) -> bool:
    return bool(v["status"]["state"] == "listening")


def test_a_connector_runs_on_one_node_moves_when_it_dies_and_stops_when_disabled(
    shared: Cluster, tmp_path: Path
) -> None:
    a = start_node(shared, tmp_path / "node-a")
    b: Server | None = None
    try:
        slug = unique("udp")
        with a.admin as admin:
            apply(admin, twin_doc(f"urn:{slug}", name="Udp", slug=slug))
            # One port for both nodes: a second node binding it too would fail (an error)
            config = {"host": "127.0.0.1", "port": free_udp_port(), "format": "json"}
            r = admin.post(
                f"/api/v1/twins/{slug}/connectors",
                json={"name": "udp", "kind": "udp", "config": config},
            )
        assert r.status_code == 201, r.text
        path = f"/api/v1/twins/{slug}/connectors/udp"
        b = start_node(shared, tmp_path / "node-b", a.admin_token)  # finds it running on A
        first = runner((a, b), path, listening)
        other = b if first is a else a
        assert view(other, path)["status"]["state"] == "stopped"

        first.process.kill()  # kill -9: its lease is left to expire
        first.process.wait()
        assert runner((other,), path, listening) is other  # taken over, the same port bound

        with other.admin as admin:  # disabled: stopped, its lease given back
            r = admin.patch(path, json={"enabled": False})
        assert r.status_code == 200, r.text
        assert view(other, path)["status"]["state"] == "stopped"
        poll_until(
            lambda: (
                shared.fetchval("SELECT count(*) FROM leases WHERE name LIKE 'connector:%'") == 0
            ),
            "the connector's lease released",
            TAKEOVER_S,
        )
    finally:
        for node in (a, b):
            if node is not None:
                stop_server(node)


def test_a_processor_follows_what_is_done_through_the_node_that_does_not_run_it(
    shared: Cluster, tmp_path: Path
) -> None:
    a = start_node(shared, tmp_path / "node-a")
    b: Server | None = None
    try:
        b = start_node(shared, tmp_path / "node-b", a.admin_token)
        slug, [device] = device_twin(a)
        with a.admin as admin:  # made through A, which takes its lease and runs it
            r = admin.post(f"/api/v1/twins/{slug}/processors", json={
                "name": "scale", "blueprint": "expression", "output": "scaled",
                "params": {"outputs": {"y": "x * 2"}}})  # fmt: skip
        assert r.status_code == 201, r.text
        path = f"/api/v1/twins/{slug}/processors/scale"
        assert runner((a, b), path, lambda v: v["state"] == "running") is a

        with b.admin as admin:  # changed through B: A applies it
            r = admin.patch(path, json={"params": {"outputs": {"y": "x * 3"}}})
        assert r.status_code == 200, r.text
        poll_until(
            lambda: view(a, path)["params"] == {"outputs": {"y": "x * 3"}},
            "the change applied on A",
            TAKEOVER_S,
        )
        assert view(b, path)["state"] == "stopped"
        with watching(b, slug, "scaled") as ws:
            send(b, device, 1)
            got = samples_until(ws, lambda s: times_of(1) <= {x["time"] for x in s})
        assert sorted(x["values"]["y"] for x in got) == sorted(3 * v["x"] for v in rows(1))

        with b.admin as admin:  # only the node running it can restart it
            assert_problem(admin.post(f"{path}/restart"), 409)
        with b.admin as admin:  # disabled through B: it stops on A, its lease given back
            assert admin.post(f"{path}/stop").status_code == 200
        poll_until(lambda: view(a, path)["state"] == "stopped", "stopped on A", TAKEOVER_S)
        poll_until(
            lambda: shared.fetchval("SELECT count(*) FROM leases") == 0, "lease released", 30
        )

        with b.admin as admin:  # enabled through B: B takes the free lease
            assert admin.post(f"{path}/start").status_code == 200
        assert runner((a, b), path, lambda v: v["state"] == "running") is b
        stop_server(b)  # a clean stop: its lease given back, A takes the processor over
        assert runner((a,), path, lambda v: v["state"] == "running") is a
        with watching(a, slug, "scaled") as ws:
            send(a, device, 2)
            got = samples_until(ws, lambda s: times_of(2) <= {x["time"] for x in s})
        assert sorted(x["time"] for x in got) == sorted(times_of(2))
    finally:
        for node in (a, b):
            if node is not None:
                stop_server(node)
