"""The OPC UA connector against the simulated crane's real asyncua server on a free loopback
port, with the platform's real services in-process: values reach the bus and the history with
their source times, and the connector reconnects by itself when the server goes away and comes
back. Commands are in test_opcua_commands.py."""

from __future__ import annotations

from datetime import datetime, timedelta
from typing import Any

import pytest
from asyncua import ua
from asyncua.ua.status_codes import StatusCodes

from ilmatar_crane.opcua import CraneOpcUaServer
from ilmatar_crane.plant import CranePlant
from tests.conftest import free_port
from tests.integration._opcua import (
    NS,
    SIGNALS,
    Platform,
    connected,
    crane_config,
    crane_server,
    eventually,
    move,
    ns,
    running,
    stamp,
)
from tests.integration._opcua import (
    crane as crane,
)
from tests.integration._opcua import (
    crane_module as crane_module,
)
from tests.integration._opcua import (
    plant as plant,
)
from tests.integration._opcua import (
    platform as platform,
)

pytestmark = [pytest.mark.integration, pytest.mark.asyncio(loop_scope="module")]


async def test_values_reach_the_platform_with_their_source_times(
    platform: Platform, crane: CraneOpcUaServer, plant: CranePlant
) -> None:
    async with running(platform.connector(crane_config(crane.url))) as connector:
        await connected(connector)
        view = connector.status.view()
        assert (view["address"], view["monitored"]) == (crane.url, len(SIGNALS))
        # The first notification of each item is its current value, at its last change.
        start = {"bridge_position": plant.bridge.position, "running": True}
        await eventually(
            lambda: start.items() <= {k: v for s in platform.samples().values()
                                      for k, v in s.items()}.items(),
            "the initial values",
        )  # fmt: skip
        move(plant)
        at = stamp()
        await crane.publish(at=at)
        snapshot = plant.snapshot()
        moved = ("bridge_position", "trolley_position", "hoist_position", "bridge_speed")
        expected = {name: snapshot[name] for name in moved}
        await eventually(lambda: platform.samples().get(ns(at)) == expected, "the values")

    stored = await platform.services.history.samples(
        platform.twin.id, "telemetry", None, ns(at), ns(at), 10
    )
    assert [(row["time"], row["values"]) for row in stored.rows] == [(ns(at), expected)]
    status = connector.status.view()
    assert status["state"] == "stopped" and status["error_count"] == 0, status
    assert status["samples"] >= 2 and status["messages"] >= 9


async def test_nodes_the_server_does_not_have_are_errors_and_the_rest_flow(
    platform: Platform, crane: CraneOpcUaServer
) -> None:
    signals = [
        {"node": f"{NS}.Nope", "signal": "nope"},
        {"node": "/2:Ilmatar/2:Nope", "signal": "nope_too"},
        {"node": "nsu=urn:nowhere;s=Nope", "signal": "nowhere"},
        {"node": f"{NS}.Running", "signal": "running"},
    ]
    async with running(platform.connector(crane_config(crane.url, signals=signals))) as conn:
        await connected(conn)
        assert conn.status.errors["subscribe_failed"] == 3
        assert conn.status.view()["monitored"] == 1
        await eventually(lambda: len(platform.samples()) == 1, "the value of the one node")
    assert list(platform.samples().values()) == [{"running": True}]
    view = conn.status.view()  # each failing node with its reason, in the order of `signals`
    assert view["failed_nodes"] == [
        {"signal": "nope", "node": f"{NS}.Nope",
         "reason": f"the server does not monitor {NS}.Nope (BadNodeIdUnknown)"},
        {"signal": "nope_too", "node": "/2:Ilmatar/2:Nope",
         "reason": "the server has no node at /2:Ilmatar/2:Nope"},
        {"signal": "nowhere", "node": "nsu=urn:nowhere;s=Nope",
         "reason": "the server has no namespace urn:nowhere"},
    ]  # fmt: skip
    assert view["failed_nodes_more"] == 0
    assert (
        conn.status.last_error
        == "subscribe_failed: nowhere: the server has no namespace urn:nowhere"
    )


async def test_a_burst_of_changes_goes_in_few_batches(
    platform: Platform, crane: CraneOpcUaServer
) -> None:
    signals = [{**SIGNALS[0], "queue_size": 1000}]
    config = crane_config(crane.url, signals=signals, batch_window_ms=50)
    async with running(platform.connector(config)) as connector:
        await connected(connector)
        await eventually(lambda: len(platform.samples()) == 1, "the initial value")
        first = stamp()
        times = [first + timedelta(milliseconds=i) for i in range(300)]
        for i, when in enumerate(times):
            await crane.write_data_value("bridge_position", stamped(float(i), when))
        expected = {ns(when): {"bridge_position": float(i)} for i, when in enumerate(times)}
        await eventually(lambda: expected.items() <= platform.samples().items(), "300 changes")
    carrying = [b for b in platform.batches if set(b.times) & expected.keys()]
    # Batches follow the server's publishes (every 20 ms), not the 300 changes.
    assert len(carrying) < 100, [len(b) for b in carrying]


def stamped(value: Any, when: datetime, code: int = 0) -> ua.DataValue:
    """A value with its source timestamp and status code, as a PLC would give it."""
    return ua.DataValue(
        None if value is None else ua.Variant(value),
        StatusCode=ua.StatusCode(ua.UInt32(code)),
        SourceTimestamp=ua.DateTime.combine(when.date(), when.timetz()),
    )


async def test_a_bad_status_is_counted_not_stored(
    platform: Platform, crane: CraneOpcUaServer
) -> None:
    async with running(platform.connector(crane_config(crane.url))) as connector:
        await connected(connector)
        at = stamp()
        bad = stamped(None, at, StatusCodes.BadSensorFailure)
        await crane.write_data_value("bridge_speed", bad)
        await eventually(lambda: connector.status.errors["bad_status"] == 1, "the bad status")
        later = at + timedelta(milliseconds=1)
        await crane.write_data_value("bridge_speed", stamped(0.25, later))
        await eventually(lambda: ns(later) in platform.samples(), "the good value after it")
    assert ns(at) not in platform.samples()
    assert platform.samples()[ns(later)] == {"bridge_speed": 0.25}
    assert connector.status.last_error == "bad_status: bridge_speed: BadSensorFailure"


async def test_a_deadband_leaves_out_small_changes(
    platform: Platform, crane: CraneOpcUaServer
) -> None:
    signals = [{**SIGNALS[0], "deadband": 1.0, "deadband_type": "absolute"}]
    async with running(platform.connector(crane_config(crane.url, signals=signals))) as conn:
        await connected(conn)
        await eventually(lambda: len(platform.samples()) == 1, "the initial value")
        [start] = platform.samples().values()
        written = []
        for step in (0.5, 1.6, 1.9, 3.0):  # only 1.6 and 3.0 move it more than 1.0
            written.append(when := stamp())
            await crane.write_data_value(
                "bridge_position", stamped(start["bridge_position"] + step, when)
            )
        await eventually(lambda: ns(written[-1]) in platform.samples(), "the last change")
    reported = [t for t in map(ns, written) if t in platform.samples()]
    assert reported == [ns(written[1]), ns(written[3])]


# -- reconnecting ------------------------------------------------------------------------


async def test_the_connector_reconnects_when_the_server_comes_back(platform: Platform) -> None:
    plant, port = CranePlant(), free_port()
    connector = platform.connector(crane_config(f"opc.tcp://127.0.0.1:{port}/ilmatar/"))
    online = platform.services.device_hub.sessions
    async with crane_server(plant, port):
        await connector.start()
        await connected(connector)
        assert platform.device.id in online  # the device is online with the server
    try:
        # The server stopped with the `async with`: the connector notices and keeps trying.
        await eventually(lambda: connector.status.state == "reconnecting", "reconnecting")
        assert connector.status.errors["connection_lost"] == 1
        assert platform.device.id not in online
        record = await platform.command("set_bridge_speed", value=-0.1)
        assert (record.state, record.error) == ("failed", "device offline")

        async with crane_server(plant, port) as second:
            await connected(connector)
            assert platform.device.id in online
            move(plant)
            at = stamp()
            await second.publish(at=at)
            await eventually(
                lambda: (
                    platform.samples().get(ns(at), {}).get("bridge_position")
                    == plant.bridge.position
                ),
                "values from the restarted server",
            )
            record = await platform.command("set_bridge_speed", value=-0.1)
            assert record.state == "succeeded", record.error
    finally:
        await connector.stop()
    assert connector.status.errors["connect_failed"] >= 1  # attempts while it was away
