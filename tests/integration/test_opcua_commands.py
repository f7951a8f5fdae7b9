"""Twin commands through the OPC UA connector, sent with the platform's real CommandService to
the simulated crane's real asyncua server: node writes (the value converted to the node's data
type) and method calls (arguments in order), and the reasons a command fails."""

from __future__ import annotations

from typing import Any

import pytest
from asyncua.client.client import Client

from ilmatar_crane.opcua import CraneOpcUaServer
from ilmatar_crane.plant import AXES, CranePlant
from tests.integration._opcua import (
    NS,
    Platform,
    connected,
    crane_config,
    running,
)
from tests.integration._opcua import crane as crane
from tests.integration._opcua import crane_module as crane_module
from tests.integration._opcua import plant as plant
from tests.integration._opcua import platform as platform

pytestmark = [pytest.mark.integration, pytest.mark.asyncio(loop_scope="module")]


async def read_node(url: str, node_id: str) -> Any:
    async with Client(url) as client:
        return await client.get_node(node_id).read_value()


async def test_twin_commands_write_nodes_and_call_methods(
    platform: Platform, crane: CraneOpcUaServer, plant: CranePlant
) -> None:
    async with running(platform.connector(crane_config(crane.url))) as connector:
        await connected(connector)
        record = await platform.command("set_bridge_speed", value=0.2)
        written = {"node": f"{NS}.Bridge.SpeedSetpoint", "value": 0.2}
        assert (record.state, record.result) == ("succeeded", written), record.error
        assert await read_node(crane.url, f"{NS}.Bridge.SpeedSetpoint") == 0.2
        record = await platform.command("set_hoist_speed", speed=0)  # an int becomes a Double
        assert record.state == "succeeded", record.error
        assert plant.hoist.setpoint == 0.0

        record = await platform.command("stop")
        assert (record.state, record.result) == ("succeeded", {"outputs": [True]}), record.error
        assert await read_node(crane.url, f"{NS}.Running") is False
        assert plant.bridge.setpoint == 0.0
        refused = await platform.command("set_bridge_speed", value=0.1)
        assert refused.state == "failed" and "BadInvalidState" in str(refused.error)
        record = await platform.command("start")
        assert (record.state, record.result) == ("succeeded", {"outputs": [False]}), record.error

        record = await platform.command("set_speeds", b=0.1, t=-0.2, h=0)
        assert record.state == "succeeded", record.error
        assert (plant.bridge.setpoint, plant.trolley.setpoint, plant.hoist.setpoint) == (
            0.1, -0.2, 0.0)  # fmt: skip
    assert connector.status.commands == 6


@pytest.mark.parametrize(
    ("name", "args", "reason"),
    [
        ("explode", {}, "no command 'explode' in this OPC UA connector; it knows: "
                        "set_bridge_speed, set_hoist_speed, set_speeds, start, stop"),
        ("set_bridge_speed", {"value": 0.9}, "the server refused it: BadOutOfRange"),
        ("set_bridge_speed", {"value": "fast"},
         "argument 'value': 'fast' is not a number (Double expected)"),
        ("set_bridge_speed", {}, "the argument 'value' (the value to write) is missing"),
        ("set_speeds", {"b": 0.1, "t": 0.1}, "the arguments 'h' are missing"),
    ],
)  # fmt: skip
async def test_a_command_that_cannot_be_carried_out_fails_with_the_reason(
    platform: Platform,
    crane: CraneOpcUaServer,
    plant: CranePlant,
    name: str,
    args: dict[str, Any],
    reason: str,
) -> None:
    async with running(platform.connector(crane_config(crane.url))) as connector:
        await connected(connector)
        record = await platform.command(name, **args)
    assert (record.state, record.error) == ("failed", reason)
    assert connector.status.errors["command_failed"] == 1
    assert [plant.axis(axis).setpoint for axis in AXES] == [0.0, 0.0, 0.0]
