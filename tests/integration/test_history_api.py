"""The history API and `twinlink history` against a real server, with data sent by a device
over HTTP ingest: rights, range queries, aggregates, downsampling, export, bad parameters,
retention and the deletion of a twin's history."""

from __future__ import annotations

import contextlib
import csv
import io
import json
import os
import signal
import sqlite3
import subprocess
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import httpx
import orjson
import pytest

from tests.conftest import Server, restart_server, start_server, stop_server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._live import twin_id
from tests.integration._util import apply, assert_problem, make_user, twin_doc, unique

pytestmark = pytest.mark.integration

S = 10**9
HOUR = 3600 * S
# The start of the seeded hour: two hours ago, on a whole second.
T0 = (time.time_ns() - 2 * HOUR) // S * S
ROUTES = [
    "",
    "/telemetry/latest",
    "/telemetry/samples",
    "/telemetry/aggregate",
    "/telemetry/downsample",
    "/telemetry/export",
]


@dataclass
class World:
    slug: str  # a twin with a group part only; the viewer has a role, the stranger none
    public_slug: str  # a twin with a public part; nobody but the admin has a role
    viewer: str
    stranger: str
    device: str
    twin_id: int


def post_batch(server: Server, token: str, seq: int, rows: list[dict[str, Any]], **kw: Any) -> None:
    with server.client(token) as device:
        r = device.post("/api/v1/device/samples", json={"seq": seq, "samples": rows, **kw})
    assert r.status_code == 200, r.text
    assert r.json()["accepted"] == len(rows), r.text


def add_device(server: Server, slug: str) -> str:
    with server.admin as admin:
        r = admin.post(f"/api/v1/twins/{slug}/devices", json={"name": "rig"})
    assert r.status_code == 201, r.text
    return str(r.json()["token"])


@pytest.fixture(scope="module")
def world(server: Server) -> World:
    slug, public_slug = unique("hist"), unique("hist-pub")
    viewer_name, viewer = unique("viewer"), ""
    viewer = make_user(server, viewer_name)
    stranger = make_user(server, unique("stranger"))
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Rig", slug=slug, privacy="group-x"))
        apply(admin, twin_doc(f"urn:{public_slug}", name="Public rig", slug=public_slug))
        r = admin.put(f"/api/v1/twins/{slug}/roles/{viewer_name}", json={"role": "viewer"})
        assert r.status_code == 200, r.text
    device = add_device(server, slug)
    # one hour at 10 Hz: x (float) and n (int) in every sample, mode (text) every 10 s
    for minute in range(60):
        rows = []
        for i in range(600):
            t = T0 + minute * 60 * S + i * S // 10
            values: dict[str, Any] = {"x": round((i % 100) / 10, 1), "n": minute * 600 + i}
            if i % 100 == 0:
                values["mode"] = "run" if minute % 2 else "idle"
            rows.append({"time": t, "values": values})
        post_batch(server, device, minute, rows)
    post_batch(server, add_device(server, public_slug), 1, [{"values": {"x": 1.0}}])
    return World(slug, public_slug, viewer, stranger, device, twin_id(server, slug))


def get(server: Server, token: str, world: World, route: str, **params: Any) -> Any:
    with server.client(token) as c:
        return c.get(f"/api/v1/twins/{world.slug}/streams{route}", params=params)


def ok(server: Server, token: str, world: World, route: str, **params: Any) -> Any:
    r = get(server, token, world, route, **params)
    assert r.status_code == 200, r.text
    return r.json()


# -- rights ------------------------------------------------------------------------------


def test_viewers_read_others_do_not(server: Server, world: World) -> None:
    for route in ROUTES:
        assert get(server, world.viewer, world, route).status_code == 200, route
        hidden = assert_problem(get(server, world.stranger, world, route), 404)
        assert world.slug in hidden["detail"]
        with server.client() as anon:
            assert_problem(anon.get(f"/api/v1/twins/{world.slug}/streams{route}"), 401)
        with server.client(world.stranger) as c:
            public = c.get(f"/api/v1/twins/{world.public_slug}/streams{route}")
        assert "needs a role" in assert_problem(public, 403)["detail"]
        with server.client(world.device) as device:  # a device token is not a user token
            assert_problem(device.get(f"/api/v1/twins/{world.slug}/streams{route}"), 401)


# -- reads -------------------------------------------------------------------------------


def test_streams_and_latest(server: Server, world: World) -> None:
    [stream] = ok(server, world.viewer, world, "")["streams"]
    assert (stream["name"], stream["samples"]) == ("telemetry", 36_000)
    assert stream["values"] == stream["count"] == 36_000 * 2 + 360
    assert {s["name"]: s["values"] for s in stream["signals"]} == {
        "mode": 360,
        "n": 36_000,
        "x": 36_000,
    }
    kinds = {s["name"]: (s["kind"], s["count"]) for s in stream["signals"]}
    assert kinds == {"mode": ("string", 360), "n": ("integer", 36_000), "x": ("number", 36_000)}
    assert (stream["first"], stream["last"]) == (T0, T0 + HOUR - S // 10)
    latest = ok(server, world.viewer, world, "/telemetry/latest", signals="n,mode")["values"]
    assert latest == {
        "mode": {"time": T0 + 59 * 60 * S + 50 * S, "value": "run"},
        "n": {"time": T0 + HOUR - S // 10, "value": 35_999},
    }


def test_samples_page_through_a_range(server: Server, world: World) -> None:
    # from 0.05 s into the third minute, in ISO 8601
    start = time.strftime("%Y-%m-%dT%H:%M:%S", time.gmtime((T0 + 120 * S) // S)) + ".05Z"
    params: dict[str, Any] = {"signals": "n,mode", "start": start, "end": T0 + 130 * S, "limit": 40}
    rows, pages = [], 0
    while True:
        answer = ok(server, world.viewer, world, "/telemetry/samples", **params)
        rows.extend(answer["rows"])
        pages += 1
        if answer["next_cursor"] is None:
            break
        params["cursor"] = answer["next_cursor"]
    assert pages == 3 and answer["start"] == T0 + 120 * S + S // 20
    assert [r["values"]["n"] for r in rows] == list(range(1201, 1301))
    assert rows[-1] == {"time": T0 + 130 * S, "values": {"n": 1300, "mode": "idle"}}
    before = time.time_ns()
    relative = ok(server, world.viewer, world, "/telemetry/samples", start="-90m", limit=5)
    first = relative["rows"][0]["time"]
    assert before - 90 * 60 * S <= first <= time.time_ns() - 90 * 60 * S + S // 10


def test_aggregate_over_minutes(server: Server, world: World) -> None:
    answer = ok(
        server,
        world.viewer,
        world,
        "/telemetry/aggregate",
        bucket="1m",
        fn="count,min,max,avg,first,last,sum",
        signals="x,n",
    )
    assert answer["bucket"] == "1m" and answer["skipped"] == []
    rows = answer["rows"]
    assert len(rows) in (60, 61)  # the hour need not start on a whole minute
    total = sum(r["values"]["n"]["count"] for r in rows)
    assert total == 36_000
    assert sum(r["values"]["n"]["sum"] for r in rows) == sum(range(36_000))  # integers, exact
    assert {type(r["values"]["n"][fn]) for r in rows for fn in ("min", "first", "last")} == {int}
    assert all(r["time"] % (60 * S) == 0 for r in rows)
    assert max(r["values"]["x"]["max"] for r in rows) == 9.9
    everything = ok(server, world.viewer, world, "/telemetry/aggregate", bucket="1d")
    assert everything["skipped"] == ["mode"]


def test_downsample_keeps_the_shape(server: Server, world: World) -> None:
    for method in ("minmax", "lttb"):
        answer = ok(
            server,
            world.viewer,
            world,
            "/telemetry/downsample",
            points=500,
            method=method,
            signals="x",
            start=T0,
            end=T0 + HOUR,
        )
        x = answer["signals"]["x"]
        assert len(x["time"]) == len(x["value"]) and 2 < len(x["time"]) <= 500
        assert x["time"] == sorted(x["time"])
        assert max(x["value"]) == 9.9 and min(x["value"]) == 0.0
    assert ok(server, world.viewer, world, "/telemetry/downsample")["skipped"] == ["mode"]


def test_export_streams_the_whole_range(server: Server, world: World) -> None:
    r = get(server, world.viewer, world, "/telemetry/export", signals="n,x,mode")
    assert r.status_code == 200
    assert r.headers["content-type"].startswith("text/csv")
    assert r.headers["content-disposition"] == f'attachment; filename="{world.slug}-telemetry.csv"'
    table = list(csv.reader(io.StringIO(r.text)))
    assert table[0] == ["time", "n", "x", "mode"]
    assert len(table) == 36_001
    assert [int(row[1]) for row in table[1:]] == list(range(36_000))
    assert table[1][0].endswith(".000000000Z") and table[101][3] == "idle" and table[2][3] == ""
    lines = get(server, world.viewer, world, "/telemetry/export", format="jsonl", signals="n")
    assert lines.headers["content-disposition"].endswith('-telemetry.jsonl"')
    objects = [orjson.loads(line) for line in lines.content.splitlines()]
    assert objects[0] == {"time": T0, "values": {"n": 0}} and len(objects) == 36_000


def test_integer_values_past_2_53_come_back_exact(server: Server) -> None:
    slug = unique("ns-values")
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Clock", slug=slug))
    big = 1682921346513461498  # float64 makes it 1.6829213465134615e+18
    values = [big + i % 7 - 3 for i in range(50)]
    start = T0 // HOUR * HOUR  # all 50 seconds in the one bucket the aggregate reads
    rows = [{"time": start + i * S, "values": {"t": v}} for i, v in enumerate(values)]
    post_batch(server, add_device(server, slug), 1, rows)
    with server.admin as admin:
        base = f"/api/v1/twins/{slug}/streams/telemetry"
        params = {"bucket": "1h", "fn": "min,max,first,last,sum", "start": start}
        agg = json.loads(admin.get(f"{base}/aggregate", params=params).content)  # big ints
        down = orjson.loads(admin.get(f"{base}/downsample", params={"points": 10}).content)
    assert agg["rows"][0]["values"]["t"] == {
        "min": min(values),
        "max": max(values),
        "first": values[0],
        "last": values[-1],
        "sum": sum(values),  # past 64 bits, and still exact
    }
    assert set(down["signals"]["t"]["value"]) <= set(values)
    assert min(values) in down["signals"]["t"]["value"]


# -- bad parameters ----------------------------------------------------------------------


@pytest.mark.parametrize(
    ("route", "params", "words"),
    [
        ("/telemetry/samples", {"start": "yesterday"}, "`start`"),
        ("/telemetry/samples", {"end": "1732200000"}, "seconds or milliseconds"),
        ("/telemetry/samples", {"start": "now", "end": "-1h"}, "swap them"),
        ("/telemetry/samples", {"limit": 0}, "limit"),
        ("/telemetry/samples", {"cursor": "abc"}, "next_cursor"),
        ("/telemetry/samples", {"signals": "x,1y"}, "not a signal name"),
        ("/telemetry/aggregate", {"bucket": "1 minute"}, "ms, s, m, h"),
        ("/telemetry/aggregate", {"fn": "mean"}, "avg, min, max"),
        ("/telemetry/aggregate", {"bucket": "1ns"}, "widen `bucket`"),
        ("/telemetry/aggregate", {"signals": "mode"}, "holds text"),
        ("/telemetry/downsample", {"method": "m4"}, "minmax, lttb"),
        ("/telemetry/downsample", {"points": 1}, "points"),
        ("/telemetry/downsample", {"signals": "x,mode"}, "holds text"),
        ("/telemetry/export", {"format": "xml"}, "csv, jsonl, json"),
        ("/telemetry/export", {"time": "unix"}, "iso, ns"),
    ],
)
def test_bad_parameters_are_422_with_a_message(
    server: Server, world: World, route: str, params: dict[str, Any], words: str
) -> None:
    body = assert_problem(get(server, world.viewer, world, route, **params), 422)
    assert words in body["detail"], body["detail"]


def test_unknown_streams_and_signals_are_404_naming_what_exists(
    server: Server, world: World
) -> None:
    body = assert_problem(get(server, world.viewer, world, "/imu/samples"), 404)
    assert "streams: telemetry" in body["detail"]
    body = assert_problem(get(server, world.viewer, world, "/telemetry/export", signals="y"), 404)
    assert "signals: mode, n, x" in body["detail"]


# -- the CLI -----------------------------------------------------------------------------


def test_cli(server: Server, world: World, tmp_path: Path) -> None:
    env = {
        **os.environ,
        "TWINLINK_URL": server.url,
        "TWINLINK_TOKEN": world.viewer,
        "XDG_CONFIG_HOME": str(tmp_path),
    }

    def cli(*args: str) -> subprocess.CompletedProcess[str]:
        run = subprocess.run(
            [sys.executable, "-m", "twinlink", "history", *args],
            env=env,
            capture_output=True,
            text=True,
            timeout=120,
            stdin=subprocess.DEVNULL,
        )
        assert "Traceback" not in run.stderr
        return run

    streams = cli("streams", world.slug)
    assert streams.returncode == 0, streams.stderr
    assert streams.stdout.split("\n")[0].split()[:4] == ["STREAM", "SIGNAL", "KIND", "VALUES"]
    assert "telemetry: 36000 samples, 72360 values" in streams.stdout
    latest = cli("latest", world.slug)
    assert "35999" in latest.stdout and "run" in latest.stdout
    show = cli("show", world.slug, "telemetry", "-s", "n", "--start", str(T0), "-n", "3")
    assert show.returncode == 0 and show.stdout.split("\n")[0].split() == ["TIME", "n"]
    assert len(show.stdout.strip().splitlines()) == 4 and "--cursor" in show.stderr
    as_json = orjson.loads(cli("show", world.slug, "telemetry", "-n", "2", "--json").stdout)
    assert len(as_json["rows"]) == 2
    out = tmp_path / "n.csv"
    export = cli("export", world.slug, "telemetry", "-s", "n", "-o", str(out))
    assert export.returncode == 0, export.stderr
    assert len(out.read_text().splitlines()) == 36_001
    bad = cli("export", world.slug, "telemetry", "--start", "soon", "-o", str(tmp_path / "x"))
    assert bad.returncode == 1 and "`start`" in bad.stderr
    assert not (tmp_path / "x").exists() and not (tmp_path / "x.part").exists()


# -- deletion ----------------------------------------------------------------------------


def history_rows(data_dir: Path, sql: str, *args: Any) -> list[Any]:
    conn = sqlite3.connect(f"file:{data_dir / 'history.db'}?mode=ro", uri=True)
    try:
        return conn.execute(sql, args).fetchall()
    finally:
        conn.close()


def test_deleting_a_twin_deletes_its_history(server: Server) -> None:
    slug = unique("doomed")
    with server.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Doomed", slug=slug))
    post_batch(server, add_device(server, slug), 1, [{"values": {"x": 1.0, "y": 2}}])
    tid = twin_id(server, slug)
    count = "SELECT count(*) FROM series WHERE twin_id = ?"
    assert history_rows(server.data_dir, count, tid) == [(2,)]
    with server.admin as admin:
        assert admin.delete(f"/api/v1/twins/{slug}").status_code == 200
    deadline = time.monotonic() + 30
    while history_rows(server.data_dir, count, tid) != [(0,)]:
        assert time.monotonic() < deadline, "the twin's history is still there"
        time.sleep(0.05)


def test_retention_deletes_old_history(tmp_path: Path) -> None:
    srv = start_server(tmp_path / "data")
    try:
        slug = unique("old")
        with srv.admin as admin:
            apply(admin, twin_doc(f"urn:{slug}", name="Old rig", slug=slug))
        token = add_device(srv, slug)
        now = time.time_ns()
        post_batch(
            srv,
            token,
            1,
            [{"time": now - 10 * 86_400 * S + i, "values": {"x": 1}} for i in range(3)],
        )
        post_batch(srv, token, 2, [{"time": now - i * S, "values": {"x": 2}} for i in range(3)])
    finally:
        stop_server(srv)
    srv = restart_server(srv, {"TWINLINK_HISTORY_RETENTION_DAYS": "2"})
    try:
        deadline = time.monotonic() + 30
        while True:  # the first round runs at start
            with srv.admin as admin:
                r = admin.get(f"/api/v1/twins/{slug}/streams/telemetry/samples")
            assert r.status_code == 200, r.text
            if [row["values"]["x"] for row in r.json()["rows"]] == [2, 2, 2]:
                break
            assert time.monotonic() < deadline, r.text
            time.sleep(0.05)
    finally:
        stop_server(srv)


# -- budgets and stopping ----------------------------------------------------------------


def test_reads_over_their_budget_say_what_to_narrow(tmp_path: Path) -> None:
    srv = start_server(
        tmp_path / "data",
        {
            "TWINLINK_HISTORY_QUERY_TIMEOUT_S": "1e-9",  # every query is over its time
            "TWINLINK_HISTORY_EXPORT_TIMEOUT_S": "1e-9",
            "TWINLINK_HISTORY_QUERY_MAX_VALUES": "5",
        },
    )
    try:
        slug = unique("budget")
        with srv.admin as admin:
            apply(admin, twin_doc(f"urn:{slug}", name="Budget", slug=slug))
        rows = [{"time": T0 + i * S, "values": {"a": i, "b": i / 2}} for i in range(100)]
        post_batch(srv, add_device(srv, slug), 1, rows)
        base = f"/api/v1/twins/{slug}/streams/telemetry"
        with srv.admin as admin:
            slow = assert_problem(admin.get(f"{base}/samples"), 503)["detail"]
            assert "TWINLINK_HISTORY_QUERY_TIMEOUT_S" in slow and "narrow `start`/`end`" in slow
            big = assert_problem(admin.get(f"{base}/aggregate", params={"bucket": "1s"}), 422)
            assert "would hold 200 values; at most 5" in big["detail"]
            got = b""
            with admin.stream("GET", f"{base}/export", params={"format": "jsonl"}) as r:
                assert r.status_code == 200
                with pytest.raises(httpx.RemoteProtocolError):  # the body never ends
                    for chunk in r.iter_bytes():
                        got += chunk
        error = orjson.loads(got.splitlines()[-1])["error"]
        assert "TWINLINK_HISTORY_EXPORT_TIMEOUT_S" in error
        cli = subprocess.run(
            [sys.executable, "-m", "twinlink", "history", "export", slug, "telemetry",
             "-o", str(tmp_path / "cut.csv")],
            env={**os.environ, "TWINLINK_URL": srv.url, "TWINLINK_TOKEN": srv.admin_token,
                 "XDG_CONFIG_HOME": str(tmp_path)},
            capture_output=True, text=True, timeout=60, stdin=subprocess.DEVNULL,
        )  # fmt: skip
        assert cli.returncode != 0 and not list(tmp_path.glob("cut.csv*")), cli.stderr
        assert "unhandled error" not in srv.log()
    finally:
        stop_server(srv)


def seed_blocks(data_dir: Path, tid: int, signals: int, rows: int) -> None:
    """Store `signals` float signals of `rows` samples (10 ms apart, in blocks of 10 000 as
    a fast device's batches) straight into history.db of a stopped server."""
    from twinlink.store.sqlite.history.codec import INSERT_BLOCK, block_row, encode

    conn = sqlite3.connect(data_dir / "history.db")
    try:
        with conn:
            for k in range(signals):
                sid = conn.execute(
                    "INSERT INTO series (twin_id, stream, signal, max_span_ns) VALUES (?, ?, ?, ?)",
                    (tid, "telemetry", f"s{k}", 10_000 * S // 100),
                ).lastrowid
                assert sid is not None
                for b in range(0, rows, 10_000):
                    times = [T0 + i * S // 100 for i in range(b, b + 10_000)]
                    values = [float(i % 977) + k for i in range(b, b + 10_000)]
                    conn.execute(INSERT_BLOCK, block_row(sid, encode(f"s{k}", times, values)))
    finally:
        conn.close()


def test_a_stop_does_not_wait_for_reads(tmp_path: Path) -> None:
    srv = start_server(tmp_path / "data")
    slug = unique("stop")
    with srv.admin as admin:
        apply(admin, twin_doc(f"urn:{slug}", name="Stop", slug=slug))
    tid = twin_id(srv, slug)
    stop_server(srv)
    seed_blocks(srv.data_dir, tid, signals=20, rows=200_000)  # 4 million values, ~70 MB of CSV
    srv = restart_server(srv)
    base = f"/api/v1/twins/{slug}/streams/telemetry"
    clients: list[httpx.Client] = []
    try:
        for _ in range(3):  # exports that stream, and whose clients then stop reading
            client = srv.admin
            clients.append(client)
            r = client.send(client.build_request("GET", f"{base}/export"), stream=True)
            assert r.status_code == 200
            assert next(r.iter_raw()).startswith(b"time,s0,")

        def aggregate() -> None:  # a long aggregate in flight as well
            with contextlib.suppress(httpx.HTTPError), srv.admin as client:
                client.get(f"{base}/aggregate", params={"bucket": "100ms", "fn": "avg,max"})

        threading.Thread(target=aggregate, daemon=True).start()
        srv.process.send_signal(signal.SIGTERM)
        # A bound on a hang, not a measurement: the stop must not wait for the reads.
        srv.process.wait(timeout=10)
    finally:
        for client in clients:
            client.close()
        stop_server(srv)
    assert "Traceback" not in srv.log(), srv.log()[-3000:]
