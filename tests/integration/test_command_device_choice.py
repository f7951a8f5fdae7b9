"""Which device a command goes to when it names none: the README's own sequence (add a device
to Tingen, then `twinlink send tingen pause`) against a real server and the simulated rig, and
each rule with its error, in the API's terms and in the CLI's."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from collections.abc import Iterator
from typing import Any

import pytest

from tests.conftest import EXAMPLES, Server
from tests.integration._device import FakeDevice, admin_client, make_twin
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._util import apply, apply_file, assert_problem, poll_until, twin_doc
from tests.integration.test_cli import Cli

pytestmark = pytest.mark.integration


@pytest.fixture(scope="module")
def cli(server: Server, tmp_path_factory: pytest.TempPathFactory) -> Cli:
    return Cli(server, tmp_path_factory.mktemp("config"))


@pytest.fixture
def rig(server: Server) -> Iterator[subprocess.Popen[bytes]]:
    """Tingen as `make demo` runs it: its document, and the simulated rig as `tingenSAP`."""
    with server.admin as admin:
        assert apply_file(admin, EXAMPLES / "tingen" / "tingen.yaml").status_code == 200
        r = admin.post("/api/v1/twins/tingen/devices", json={"name": "tingenSAP"})
        assert r.status_code == 201, r.text
        token = r.json()["token"]
    env = {**os.environ, "TWINLINK_URL": server.url, "TWINLINK_DEVICE_TOKEN": token}
    proc = subprocess.Popen(
        [sys.executable, "-m", "twinlink", "simulate", "tingen", "--rate", "20"],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    try:
        poll_until(lambda: _connected(server, "tingen", "tingenSAP"), "the rig to connect", 60)
        yield proc
    finally:
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=30)
        assert proc.returncode == 0, err.decode(errors="replace")


def _devices(server: Server, slug: str) -> dict[str, Any]:
    with server.admin as admin:
        r = admin.get(f"/api/v1/twins/{slug}/devices")
    assert r.status_code == 200, r.text
    return r.json()  # type: ignore[no-any-return]


def _connected(server: Server, slug: str, name: str) -> bool:
    return any(d["name"] == name and d["connected"] for d in _devices(server, slug)["devices"])


def test_the_readme_sequence_add_a_device_then_send_without_naming_one(
    cli: Cli, rig: subprocess.Popen[bytes]
) -> None:
    token = cli("devices", "add", "tingen", "my-pi").ok().out.strip()
    assert token.startswith("tld_")
    listed = cli("devices", "ls", "tingen").ok().out
    assert "Commands that name no device go to tingenSAP." in listed
    paused = cli("send", "tingen", "pause").ok()
    assert paused.out.split()[1] == "succeeded", paused.out
    assert '"paused": true' in paused.out  # the rig's own answer
    started = cli("send", "tingen", "start", "--json").ok()
    assert '"device": "tingenSAP"' in started.out


async def test_a_twin_without_a_default_uses_its_only_connected_device(server: Server) -> None:
    slug, tokens = make_twin(server, devices=("left", "right"))
    async with admin_client(server) as client:
        offline = await client.post(f"/api/v1/twins/{slug}/commands", json={"name": "x"})
        problem = assert_problem(offline, 422)
        assert problem["devices"] == ["left", "right"]
        assert "none of them are connected" in problem["reason"]
        assert problem["detail"] == f"{problem['reason']}; name one with `device`"
        listed = await client.get(f"/api/v1/twins/{slug}/devices")
        assert listed.json()["default_device"] is None
        async with FakeDevice(server, tokens["right"]):
            listed = await client.get(f"/api/v1/twins/{slug}/devices")
            assert listed.json()["default_device"] == "right"
            r = await client.post(f"/api/v1/twins/{slug}/commands", json={"name": "x"})
            assert r.status_code == 200, r.text
            assert (r.json()["device"], r.json()["state"]) == ("right", "succeeded")
            async with FakeDevice(server, tokens["left"]):  # two connected: name one
                both = await client.post(f"/api/v1/twins/{slug}/commands", json={"name": "x"})
                assert "2 of them are connected" in assert_problem(both, 422)["reason"]


def test_the_cli_names_its_own_option(cli: Cli, server: Server) -> None:
    slug, _ = make_twin(server, devices=("left", "right"))
    refused = cli("send", slug, "x")
    assert refused.code == 1
    assert refused.err.startswith("Error: ")
    assert "name one with --device NAME" in refused.err and "`device`" not in refused.err
    assert "several devices (left, right)" in refused.err
    named = cli("send", slug, "x", "--device", "right")
    assert named.code == 1 and "device offline" in named.err  # sent to it; nobody listens


async def test_a_declared_default_wins_over_the_only_connected_device(server: Server) -> None:
    slug, tokens = make_twin(server, {"default_device": "left"}, devices=("left", "right"))
    async with FakeDevice(server, tokens["right"]), admin_client(server) as client:
        r = await client.post(f"/api/v1/twins/{slug}/commands", json={"name": "x"})
        # Declared, it wins; offline, the command fails at once (or waits, with `queue`).
        assert (r.json()["device"], r.json()["error"]) == ("left", "device offline")
        listed = await client.get(f"/api/v1/twins/{slug}/devices")
        assert listed.json()["default_device"] == "left"


def test_a_declared_default_that_names_no_device_is_a_clear_error(server: Server) -> None:
    slug, _ = make_twin(server, {"default_device": "left"}, devices=("left", "right"))
    with server.admin as admin:
        doc = twin_doc(f"urn:{slug}", name="Rig", slug=slug, interface={"default_device": "gone"})
        apply(admin, doc)
        wrong = admin.post(f"/api/v1/twins/{slug}/commands", json={"name": "x"})
        problem = assert_problem(wrong, 422)
        assert (
            "the `default_device` its interface declares, 'gone', is not one of them"
            in (problem["detail"])
        )
        assert problem["devices"] == ["left", "right"]
        assert _devices(server, slug)["default_device"] is None
        # Naming a device needs no default.
        named = admin.post(f"/api/v1/twins/{slug}/commands", json={"name": "x", "device": "right"})
        assert named.json()["device"] == "right"


def test_the_only_device_needs_no_default(server: Server) -> None:
    slug, _ = make_twin(server, {"default_device": "the-rig"}, devices=("my-pi",))
    with server.admin as admin:
        r = admin.post(f"/api/v1/twins/{slug}/commands", json={"name": "x"})
    assert r.json()["device"] == "my-pi"
    assert _devices(server, slug)["default_device"] == "my-pi"
