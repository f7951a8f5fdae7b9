"""Device properties: desired values reach the device as a delta, reported values show up."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from tests.conftest import Server
from tests.integration._device import FakeDevice, admin_client, make_twin
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._util import assert_problem, make_user, unique

pytestmark = pytest.mark.integration

INTERFACE = {
    "properties": [
        {"name": "sample_rate", "type": "number", "min": 1, "max": 100, "writable": True},
        {"name": "filter_k", "type": "number", "min": 0, "max": 1, "writable": True},
        {"name": "mode", "type": "string", "writable": True},
        {"name": "paused", "type": "bool"},
    ]
}


def _desired_url(slug: str, device: str = "rig") -> str:
    return f"/api/v1/twins/{slug}/devices/{device}/properties/desired"


async def test_desired_changes_reach_the_device_as_the_delta(server: Server) -> None:
    slug, tokens = make_twin(server, INTERFACE)
    async with FakeDevice(server, tokens["rig"]) as device, admin_client(server) as client:
        assert (device.welcome["desired"], device.welcome["desired_version"]) == ({}, 0)
        r = await client.patch(_desired_url(slug), json={"sample_rate": 50, "filter_k": 0.9})
        assert r.status_code == 200, r.text
        assert r.json()["version"] == 1 and r.json()["delta"] == {
            "sample_rate": 50,
            "filter_k": 0.9,
        }
        sent = await device.next("desired")
        assert sent == {"type": "desired", "properties": {"sample_rate": 50, "filter_k": 0.9},
                        "version": 1}  # fmt: skip

        await device.send({"type": "reported", "properties": {"sample_rate": 50, "paused": False}})
        ack = await device.next("reported_ack")
        assert ack == {"type": "reported_ack", "version": 1, "desired": {"filter_k": 0.9}}
        shown = (await client.get(f"/api/v1/twins/{slug}/devices/rig/properties")).json()
        assert shown["reported"]["sample_rate"]["value"] == 50
        assert shown["reported"]["paused"]["value"] is False and shown["reported"]["paused"]["time"]
        assert shown["desired"]["filter_k"]["value"] == 0.9
        assert (shown["delta"], shown["version"]) == ({"filter_k": 0.9}, 1)

        r = await client.patch(_desired_url(slug), json={"filter_k": None, "sample_rate": 50})
        assert r.json()["version"] == 2 and "filter_k" not in r.json()["desired"]
        assert await device.next("desired") == {"type": "desired", "properties": {}, "version": 2}
        same = await client.patch(_desired_url(slug), json={"sample_rate": 50})
        assert same.json()["version"] == 2  # nothing changed, no new version


async def test_a_device_that_connects_gets_the_delta_in_its_welcome(server: Server) -> None:
    slug, tokens = make_twin(server, INTERFACE)
    with server.admin as admin:
        r = admin.patch(_desired_url(slug), json={"mode": "eco", "sample_rate": 20})
        assert r.status_code == 200, r.text
    async with FakeDevice(server, tokens["rig"]) as device:
        assert device.welcome["desired"] == {"mode": "eco", "sample_rate": 20}
        assert device.welcome["desired_version"] == 1


async def test_reported_values_are_checked_against_the_interface(server: Server) -> None:
    slug, tokens = make_twin(server, INTERFACE)
    async with FakeDevice(server, tokens["rig"]) as device:
        await device.send({"type": "reported", "properties": {"paused": "yes"}})
        assert "'paused': \"yes\" is not a bool" in (await device.next("error"))["message"]
        await device.send({"type": "reported", "properties": {"colour": "red"}})
        assert "not a property of this twin" in (await device.next("error"))["message"]
        await device.send({"type": "reported", "properties": {}})
        assert "at least one" in (await device.next("error"))["message"]
    with server.admin as admin:
        shown = admin.get(f"/api/v1/twins/{slug}/devices/rig/properties").json()
    assert shown["reported"] == {}


def test_desired_values_are_checked_against_the_interface(server: Server) -> None:
    slug, _ = make_twin(server, INTERFACE)
    cases: list[tuple[Any, str]] = [
        ({"colour": "red"}, "no property 'colour'"),
        ({"paused": True}, "'paused' is not writable"),
        ({"sample_rate": 500}, "500 is above the maximum 100"),
        ({"sample_rate": "fast"}, "is not a number"),
        ({"mode": ["a"]}, "is not a number, bool or string"),
        ({}, "a JSON object of property name -> value"),
    ]
    with server.admin as admin:
        for body, reason in cases:
            r = admin.patch(_desired_url(slug), json=body)
            assert reason in assert_problem(r, 422)["detail"], body
        assert_problem(admin.patch(_desired_url(slug), json=[1]), 422)
        assert_problem(admin.patch(_desired_url(slug, "nope"), json={"mode": "x"}), 404)
        shown = admin.get(f"/api/v1/twins/{slug}/devices/rig/properties").json()
    assert shown == {"device": "rig", "reported": {}, "desired": {}, "delta": {}, "version": 0}


def test_a_twin_without_declared_properties_takes_any_plain_value(server: Server) -> None:
    slug, _ = make_twin(server)
    with server.admin as admin:
        r = admin.patch(_desired_url(slug), json={"anything": "goes", "n": 3})
        assert r.status_code == 200 and r.json()["delta"] == {"anything": "goes", "n": 3}
        assert_problem(admin.patch(_desired_url(slug), json={"deep": {"a": 1}}), 422)


def test_devices_without_a_websocket_use_http(server: Server) -> None:
    slug, tokens = make_twin(server, INTERFACE)
    with server.admin as admin:
        admin.patch(_desired_url(slug), json={"sample_rate": 10, "mode": "eco"})
    with server.client(tokens["rig"]) as device:
        r = device.post("/api/v1/device/properties", json={"properties": {"sample_rate": 10}})
        assert r.status_code == 200, r.text
        assert r.json() == {"version": 1, "desired": {"mode": "eco"}}
        mine = device.get("/api/v1/device/properties").json()
        assert mine["delta"] == {"mode": "eco"} and mine["reported"]["sample_rate"]["value"] == 10
        assert_problem(device.post("/api/v1/device/properties", json={"properties": 5}), 422)
        assert_problem(device.get(f"/api/v1/twins/{slug}/devices/rig/properties"), 401)
    with server.admin as person:
        assert_problem(person.get("/api/v1/device/properties"), 401)
        assert_problem(person.post("/api/v1/device/properties", json={"properties": {}}), 401)


def test_viewers_read_properties_and_editors_change_them(server: Server) -> None:
    slug, _ = make_twin(server, INTERFACE)
    viewer = unique("viewer")
    token = make_user(server, viewer)
    with server.admin as admin:
        r = admin.put(f"/api/v1/twins/{slug}/roles/{viewer}", json={"role": "viewer"})
        assert r.status_code == 200, r.text
    with server.client(token) as c:
        assert c.get(f"/api/v1/twins/{slug}/devices/rig/properties").status_code == 200
        assert_problem(c.patch(_desired_url(slug), json={"mode": "x"}), 403)


def test_cli_shows_and_sets_properties(server: Server, tmp_path: Path) -> None:
    slug, _ = make_twin(server, INTERFACE)
    env = {
        **os.environ,
        "TWINLINK_URL": server.url,
        "TWINLINK_TOKEN": server.admin_token,
        "XDG_CONFIG_HOME": str(tmp_path),
    }

    def cli(*args: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [sys.executable, "-m", "twinlink", "properties", *args], env=env,
            capture_output=True, text=True, timeout=60, stdin=subprocess.DEVNULL,
        )  # fmt: skip

    done = cli("set", slug, "rig", "sample_rate=25", "mode=eco")
    assert done.returncode == 0, done.stderr
    assert "25*" in done.stdout and '"eco"*' in done.stdout and "version 1" in done.stdout
    shown = cli("show", slug, "rig")
    assert shown.returncode == 0 and shown.stdout == done.stdout
    refused = cli("set", slug, "rig", "paused=true")
    assert refused.returncode == 1 and "not writable" in refused.stderr
