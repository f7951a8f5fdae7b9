"""The crane's OPC UA server, standing in for the one wired to Ilmatar's PLC.

Address space (namespace `OPCUA_NAMESPACE`, string node ids `Ilmatar.<Group>.<Name>`):

    Objects/Ilmatar/Bridge/{Position, Speed, SpeedSetpoint, Distance}
    Objects/Ilmatar/Trolley/{Position, Speed, SpeedSetpoint, Distance}
    Objects/Ilmatar/Hoist/{Position, Speed, SpeedSetpoint, Distance}
    Objects/Ilmatar/Hook/Load

Every variable is a Double with an `EngineeringUnits` property (UNECE units). Only the
`SpeedSetpoint` variables are writable; they also carry an `EURange`, and a write outside it is
refused with BadOutOfRange. Measured values are refreshed from the plant on every `publish()`.
Security is None with anonymous sessions: a loopback demo, like the rest of the crane services.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from datetime import UTC

from asyncua import ua
from asyncua.common.node import Node
from asyncua.server.address_space import NodeData
from asyncua.server.server import Server
from asyncua.ua.attribute_ids import AttributeIds
from asyncua.ua.status_codes import StatusCodes
from asyncua.ua.uaerrors import UaStatusCodeError

from twinlink.crane._http import url_host
from twinlink.crane.plant import CranePlant
from twinlink.crane.settings import OPCUA_NAMESPACE, OPCUA_PATH
from twinlink.crane.signals import SIGNALS, Signal, axis_of

log = logging.getLogger(__name__)

UNECE_UNITS_URI = "http://www.opcfoundation.org/UA/units/un/cefact"
UNECE_CODES = {"m": "MTR", "m/s": "MTS", "kg": "KGM"}
Setter = Callable[[NodeData, AttributeIds, ua.DataValue], None]


def node_id(name: str, namespace: int) -> ua.NodeId:
    return ua.NodeId(ua.String(name), ua.Int16(namespace))


def status_error(code: int) -> UaStatusCodeError:
    # asyncua leaves the exception's __init__ untyped.
    return UaStatusCodeError(code)  # type: ignore[no-untyped-call]


def unit_information(unit: str) -> ua.EUInformation:
    # OPC UA Part 8: the UnitId of a UNECE unit is its common code's letters packed in bytes.
    code = UNECE_CODES[unit]
    unit_id = int.from_bytes(code.encode("ascii"), "big")
    return ua.EUInformation(
        NamespaceUri=UNECE_UNITS_URI,
        UnitId=unit_id,
        DisplayName=ua.LocalizedText(unit),
        Description=ua.LocalizedText(code),
    )


class CraneOpcUaServer:
    def __init__(self, plant: CranePlant) -> None:
        self._plant = plant
        self._server = Server()
        self._namespace = 0
        self._nodes: dict[str, ua.NodeId] = {}  # by signal name
        self._published_setpoints: dict[str, float] = {}
        self.host = "127.0.0.1"
        self.port = 0

    @property
    def url(self) -> str:
        return f"opc.tcp://{url_host(self.host)}:{self.port}{OPCUA_PATH}"

    async def start(self, host: str, port: int) -> None:
        self.host = host
        server = self._server
        await server.init()
        # asyncua binds to the endpoint's host, so a wildcard address stays a wildcard here.
        bind_host = f"[{host}]" if ":" in host else host
        server.set_endpoint(f"opc.tcp://{bind_host}:{port}{OPCUA_PATH}")
        server.set_server_name("Ilmatar crane (twinlink demo)")
        server.set_security_policy([ua.SecurityPolicyType.NoSecurity])
        server.set_identity_tokens([ua.AnonymousIdentityToken])
        self._namespace = await server.register_namespace(OPCUA_NAMESPACE)
        await self._build_address_space()
        await self.publish()
        await server.start()
        assert server.bserver is not None  # set by start()
        self.port = server.bserver.port  # the real one when port was 0

    async def stop(self) -> None:
        await self._server.stop()

    async def _build_address_space(self) -> None:
        ns = self._namespace
        crane = await self._server.nodes.objects.add_object(
            node_id("Ilmatar", ns), ua.QualifiedName("Ilmatar", ns)
        )
        groups: dict[str, Node] = {}
        for signal in SIGNALS:
            group_name, _ = signal.path.split(".")
            if group_name not in groups:
                groups[group_name] = await crane.add_object(
                    node_id(f"Ilmatar.{group_name}", ns), ua.QualifiedName(group_name, ns)
                )
            await self._add_variable(groups[group_name], signal)

    async def _add_variable(self, parent: Node, signal: Signal) -> None:
        ns = self._namespace
        _, name = signal.path.split(".")
        var_id = node_id(f"Ilmatar.{signal.path}", ns)
        var = await parent.add_variable(
            var_id, ua.QualifiedName(name, ns), 0.0, varianttype=ua.VariantType.Double
        )
        await var.write_attribute(
            AttributeIds.Description,
            ua.DataValue(ua.Variant(ua.LocalizedText(signal.description))),
        )
        await var.add_property(
            node_id(f"Ilmatar.{signal.path}.EngineeringUnits", ns),
            ua.QualifiedName("EngineeringUnits", 0),
            unit_information(signal.unit),
        )
        if signal.writable:
            assert signal.low is not None and signal.high is not None
            await var.add_property(
                node_id(f"Ilmatar.{signal.path}.EURange", ns),
                ua.QualifiedName("EURange", 0),
                ua.Range(Low=signal.low, High=signal.high),
            )
            await var.set_writable()
            self._server.set_attribute_value_setter(var_id, self._setpoint_setter(signal))
        self._nodes[signal.name] = var_id

    def _setpoint_setter(self, signal: Signal) -> Setter:
        axis = axis_of(signal)

        def setter(node: NodeData, attr: AttributeIds, value: ua.DataValue) -> None:
            # Called for client writes and for publish() alike; publish() only ever writes the
            # plant's own set-point back, so an unchanged value is not an operator's command.
            new = value.Value.Value if value.Value is not None else None
            if not isinstance(new, float):
                raise status_error(StatusCodes.BadTypeMismatch)
            if new != self._plant.axis(axis).setpoint:
                try:
                    self._plant.set_speed_setpoint(axis, new)
                except ValueError as err:
                    raise status_error(StatusCodes.BadOutOfRange) from err
            node.attributes[attr].value = value
            node.attributes[attr].value_callback = None

        return setter

    async def publish(self) -> None:
        """Copy the plant's values into the address space (subscribers see the changes)."""
        now = ua.DateTime.now(UTC)
        for name, value in self._plant.snapshot().items():
            signal_is_setpoint = name.endswith("_setpoint")
            if signal_is_setpoint and self._published_setpoints.get(name) == value:
                continue  # set-points change rarely; rewriting them would only spam subscribers
            data = ua.DataValue(
                ua.Variant(float(value), ua.VariantType.Double),
                SourceTimestamp=now,
                ServerTimestamp=now,
            )
            await self._server.write_attribute_value(self._nodes[name], data)
            if signal_is_setpoint:
                self._published_setpoints[name] = value
