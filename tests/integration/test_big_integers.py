"""Integers beyond 64 bits (issue 13, item 3) on every transport: refused with the one message
(`jsontext.int64_problem`) and never stored rounded to a float, as YAML documents refuse
them. A sample holding one is rejected on its own (the rest of its batch is kept); any other
message (reported or desired properties, a command's arguments or result) is refused whole,
naming the place. The bounds themselves, -2^63 and 2^63-1, are kept exact."""

from __future__ import annotations

import json
import socket
from pathlib import Path
from typing import Any

import orjson
import pytest
from websockets.sync.client import connect

from tests.conftest import Server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._live import device_socket, device_twin, receive, stored_values, ws_url
from tests.integration._mqtt import Paho, mqtt_platform, require_mosquitto
from tests.integration._util import JSON_HEADERS, assert_problem, poll_until, unique
from twinlink.domain.jsontext import int64_problem

pytestmark = pytest.mark.integration

BIG = 2**80
REFUSED = int64_problem(BIG)  # "1208925819614629174706176 does not fit in 64 bits ..."
LOW, HIGH = -(2**63), 2**63 - 1


def _batch_text(seq: int | str) -> str:
    """A batch of a sample holding BIG and one holding the int64 bounds, as raw JSON (a JSON
    library of the test would round BIG, or refuse to write it)."""
    return (
        f'{{"seq": {seq}, "samples": [{{"values": {{"a": {BIG}}}}},'
        f' {{"values": {{"a": 7, "low": {LOW}, "high": {HIGH}}}}}]}}'
    )


def _check_ack(ack: dict[str, Any]) -> None:
    assert (ack["accepted"], ack["rejected_count"]) == (1, 1), ack
    assert ack["rejected"] == [{"index": 0, "reason": f"a: {REFUSED}"}]


def test_http_telemetry_rejects_the_sample_and_keeps_the_rest(server: Server) -> None:
    slug, (token,) = device_twin(server)
    with server.client(token) as device:
        r = device.post("/api/v1/device/samples", content=_batch_text(1), headers=JSON_HEADERS)
        assert r.status_code == 200, r.text
        _check_ack(r.json())
        r = device.post("/api/v1/device/samples", content=_batch_text(BIG), headers=JSON_HEADERS)
        assert "`seq` must be an integer from 0 to 2^63-1" in assert_problem(r, 422)["detail"]
    # Never 1.2089258196146292e+24: only the good sample is stored, its bounds exact.
    assert stored_values(server, slug, "a") == [7]
    assert stored_values(server, slug, "low") == [LOW]
    assert stored_values(server, slug, "high") == [HIGH]


def test_device_websocket_refuses_each_kind_of_message_with_the_place(server: Server) -> None:
    slug, (token,) = device_twin(server)
    with device_socket(server, token) as ws:
        receive(ws, "welcome")
        ws.send(_batch_text(1).replace('{"seq"', '{"type": "samples", "seq"'))
        _check_ack(receive(ws, "ack"))
        for raw, expected in [
            (f'{{"type": "samples", "seq": {BIG}, "samples": []}}', {"message": f"seq: {REFUSED}"}),
            (
                f'{{"type": "reported", "id": "r1", "properties": {{"n": {BIG}}}}}',
                {"op": "reported", "id": "r1", "message": f"properties.n: {REFUSED}"},
            ),
            (
                f'{{"type": "reported", "id": {BIG}, "properties": {{"n": 1}}}}',
                {"op": "reported", "message": f"id: {REFUSED}"},  # not echoed: it is the one
            ),
            (
                f'{{"type": "result", "id": "c1", "status": "succeeded", "result": [{BIG}]}}',
                {"op": "result", "id": "c1", "message": f"result[0]: {REFUSED}"},
            ),
        ]:
            ws.send(raw)
            error = receive(ws, "error")
            assert error == {"type": "error", "fatal": False, **expected}, raw
        ws.send('{"type": "ping"}')
        assert receive(ws, "pong")["server_time"] > 0  # still connected
    assert stored_values(server, slug, "a") == [7]
    with server.admin as admin:
        shown = admin.get(f"/api/v1/twins/{slug}/devices/dev0/properties").json()
    assert shown["reported"] == {}


def test_http_properties_commands_and_results_name_the_place(server: Server) -> None:
    slug, (token,) = device_twin(server)
    twin = f"/api/v1/twins/{slug}"
    with server.admin as admin:
        for path, body, place in [
            (f"{twin}/devices/dev0/properties/desired", f'{{"v": {BIG}}}', "body.v"),
            (f"{twin}/commands", f'{{"name": "go", "args": {{"v": [{BIG}]}}}}', "body.args.v[0]"),
        ]:
            method = admin.patch if path.endswith("desired") else admin.post
            r = method(path, content=body, headers=JSON_HEADERS)
            assert assert_problem(r, 422)["detail"] == f"{place}: {REFUSED}"
        # At the bounds a command goes out with its arguments exact (it fails: no device).
        r = admin.post(f"{twin}/commands", json={"name": "go", "args": {"v": [LOW, HIGH]}})
        assert r.status_code == 200 and r.json()["args"] == {"v": [LOW, HIGH]}, r.text
    with server.client(token) as device:
        r = device.post(
            "/api/v1/device/properties",
            content=f'{{"properties": {{"count": {-BIG}}}}}',
            headers=JSON_HEADERS,
        )
        detail = assert_problem(r, 422)["detail"]
        assert detail == f"body.properties.count: {int64_problem(-BIG)}"
        r = device.post(
            "/api/v1/device/commands/nothing/result",
            content=f'{{"status": "succeeded", "result": {BIG}}}',
            headers=JSON_HEADERS,
        )
        assert assert_problem(r, 422)["detail"] == f"body.result: {REFUSED}"


def test_live_websocket_commands_refuse_them_not_round_them(server: Server) -> None:
    # orjson read the arguments as 1.2089258196146292e+24 and the command went out so.
    slug, _ = device_twin(server)
    headers = {"Authorization": f"Bearer {server.admin_token}"}
    with connect(ws_url(server, "/api/v1/live"), additional_headers=headers) as ws:
        receive(ws, "welcome")
        ws.send(f'{{"op": "command", "id": "c1", "twin": "{slug}", "name": "go",'
                f' "args": {{"v": {BIG}}}}}')  # fmt: skip
        error = receive(ws, "error")
        assert error == {
            "type": "error", "op": "command", "id": "c1", "status": 422,
            "message": f"args.v: {REFUSED}",
        }  # fmt: skip
    with server.admin as admin:
        assert admin.get(f"/api/v1/twins/{slug}/commands").json()["commands"] == []


def test_udp_json_datagrams_reject_the_sample(server: Server) -> None:
    slug, _ = device_twin(server)
    with server.admin as admin:
        r = admin.post(
            f"/api/v1/twins/{slug}/connectors",
            json={"name": unique("udp"), "kind": "udp", "config": {"port": 0, "format": "json"}},
        )
        assert r.status_code == 201, r.text
    made = r.json()
    port = int(made["status"]["address"].rsplit(":", 1)[1])
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.sendto(f'{{"a": {BIG}}}'.encode(), ("127.0.0.1", port))
        s.sendto(orjson.dumps({"a": 7}), ("127.0.0.1", port))

    def status() -> dict[str, Any] | None:
        with server.admin as admin:
            view = admin.get(f"/api/v1/twins/{slug}/connectors/{made['name']}").json()
        return view["status"] if view["status"]["rejected"] == 1 else None

    rejected = poll_until(status, "the connector's rejected sample")
    assert REFUSED in str(rejected["last_error"])
    poll_until(lambda: stored_values(server, slug, "a") == [7], "the good datagram stored")


async def test_mqtt_telemetry_and_reported_properties(tmp_path: Path) -> None:
    require_mosquitto()
    async with mqtt_platform(tmp_path / "data") as platform:
        device = Paho(platform.port, "rig", platform.token, 5)
        await device.connect()
        try:
            await device.subscribe(platform.topic("errors"))
            payload = f'[{{"values": {{"angle": {BIG}}}}}, {{"values": {{"angle": 2}}}}]'
            await device.publish(platform.topic("telemetry"), payload)
            error = json.loads((await device.message())[1])
            assert error["message"] == f"1 sample(s) rejected; #0: angle: {REFUSED}"
            reported = f'{{"sample_rate": {BIG}}}'
            await device.publish(platform.topic("properties/reported"), reported)
            error = json.loads((await device.message())[1])
            assert error["message"] == f"reported properties: sample_rate: {REFUSED}"
            seq = f'{{"seq": {2**64}, "samples": [{{"values": {{"angle": 3}}}}]}}'
            await device.publish(platform.topic("telemetry"), seq)
            error = json.loads((await device.message())[1])
            assert error["message"] == f"seq: {int64_problem(2**64)}"
        finally:
            await device.stop()
        assert [r["values"] for r in await platform.rows_until(1)] == [{"angle": 2}]
        props = await platform.services.properties.for_device(platform.device)
        assert props.reported == {}
