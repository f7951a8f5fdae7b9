"""The crane's OPC UA server, standing in for the one wired to Ilmatar's PLC.

Address space (namespace `OPCUA_NAMESPACE`, string node ids `Ilmatar.<Group>.<Name>`):

    Objects/Ilmatar/Bridge/{Position, Speed, SpeedSetpoint, Distance}
    Objects/Ilmatar/Trolley/{Position, Speed, SpeedSetpoint, Distance}
    Objects/Ilmatar/Hoist/{Position, Speed, SpeedSetpoint, Distance}
    Objects/Ilmatar/Hook/Load
    Objects/Ilmatar/Running                          (Boolean, read-only)
    Objects/Ilmatar/{Start(), Stop(), SetSpeeds(Bridge, Trolley, Hoist)}   (methods)

Every group variable is a Double with an `EngineeringUnits` property (UNECE units). Only the
`SpeedSetpoint` variables are writable; they also carry an `EURange`, and a write outside it is
refused with BadOutOfRange. Measured values are refreshed from the plant on every `publish()`.

`Stop()` halts the crane: every set-point goes to zero and stays there (set-point writes and
`SetSpeeds` are refused with BadInvalidState, the autopilot is held off) until `Start()`. Both
answer whether the crane was running before the call.

By default security is None with anonymous sessions: a loopback demo, like the rest of the crane
services. `OpcUaAccess` asks for username/password sessions or signed/encrypted endpoints
instead (the OPC UA connector's tests use it).
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from asyncua import ua
from asyncua.common.node import Node
from asyncua.crypto.permission_rules import User, UserRole
from asyncua.server.address_space import NodeData
from asyncua.server.internal_server import InternalServer
from asyncua.server.server import Server
from asyncua.server.user_managers import UserManager
from asyncua.ua.attribute_ids import AttributeIds
from asyncua.ua.status_codes import StatusCodes
from asyncua.ua.uaerrors import UaStatusCodeError

from ilmatar_crane._http import url_host
from ilmatar_crane.plant import AXES, CranePlant
from ilmatar_crane.settings import OPCUA_NAMESPACE, OPCUA_PATH
from ilmatar_crane.signals import SIGNALS, Signal, axis_of

log = logging.getLogger(__name__)

UNECE_UNITS_URI = "http://www.opcfoundation.org/UA/units/un/cefact"
UNECE_CODES = {"m": "MTR", "m/s": "MTS", "kg": "KGM"}
Setter = Callable[[NodeData, AttributeIds, ua.DataValue], None]
SECURE_POLICIES = [
    ua.SecurityPolicyType.Basic256Sha256_SignAndEncrypt,
    ua.SecurityPolicyType.Basic256Sha256_Sign,
]


@dataclass(frozen=True)
class OpcUaAccess:
    """Who may open a session. The default is the demo's: anonymous, security None.

    `users` (name -> password) replaces anonymous sessions by username/password ones. A
    `certificate` with its `private_key` (PEM or DER files) replaces the open endpoint by
    Basic256Sha256 ones (Sign and SignAndEncrypt); client certificates are not checked."""

    users: Mapping[str, str] | None = None
    certificate: Path | None = None
    private_key: Path | None = None


class _PasswordUsers(UserManager):
    """asyncua's user manager: a session needs one of the given username/password pairs."""

    def __init__(self, users: Mapping[str, str]) -> None:
        self.users = dict(users)

    def get_user(
        self,
        iserver: InternalServer,
        username: str | None = None,
        password: str | None = None,
        certificate: Any = None,
    ) -> User | None:
        if username is not None and self.users.get(username) == password:
            return User(role=UserRole.User, name=username)
        return None


def node_id(name: str, namespace: int) -> ua.NodeId:
    return ua.NodeId(ua.String(name), ua.Int16(namespace))


def status_error(code: int) -> UaStatusCodeError:
    # asyncua leaves the exception's __init__ untyped.
    return UaStatusCodeError(code)  # type: ignore[no-untyped-call]


def status(code: int) -> ua.StatusCode:
    return ua.StatusCode(ua.UInt32(code))


def argument(name: str, vtype: ua.VariantType) -> ua.Argument:
    """A method argument's description (its InputArguments/OutputArguments entry)."""
    return ua.Argument(Name=ua.String(name), DataType=ua.NodeId(ua.Int32(vtype.value)))


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
    def __init__(self, plant: CranePlant, access: OpcUaAccess | None = None) -> None:
        self._plant = plant
        self._access = access or OpcUaAccess()
        self._server = Server()
        self._namespace = 0
        self._nodes: dict[str, ua.NodeId] = {}  # by signal name
        self._published_setpoints: dict[str, float] = {}
        self._running_id = ua.NodeId()
        self.running = True  # False between Stop() and Start()
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
        await self._set_access()
        self._namespace = await server.register_namespace(OPCUA_NAMESPACE)
        await self._build_address_space()
        await self.publish()
        await server.start()
        assert server.bserver is not None  # set by start()
        self.port = server.bserver.port  # the real one when port was 0

    async def stop(self) -> None:
        await self._server.stop()

    async def _set_access(self) -> None:
        server, access = self._server, self._access
        if access.users is None:
            server.set_identity_tokens([ua.AnonymousIdentityToken])
        else:
            server.set_identity_tokens([ua.UserNameIdentityToken])
            server.iserver.set_user_manager(_PasswordUsers(access.users))
        if access.certificate is None or access.private_key is None:
            server.set_security_policy([ua.SecurityPolicyType.NoSecurity])
            return
        await server.load_certificate(access.certificate)
        await server.load_private_key(access.private_key)
        server.set_security_policy(SECURE_POLICIES)

    async def _build_address_space(self) -> None:
        ns = self._namespace
        crane = await self._server.nodes.objects.add_object(
            node_id("Ilmatar", ns), ua.QualifiedName("Ilmatar", ns)
        )
        await self._add_controls(crane)
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
                if not self.running:
                    raise status_error(StatusCodes.BadInvalidState)
                try:
                    self._plant.set_speed_setpoint(axis, new)
                except ValueError as err:
                    raise status_error(StatusCodes.BadOutOfRange) from err
            node.attributes[attr].value = value
            node.attributes[attr].value_callback = None

        return setter

    async def publish(self, at: datetime | None = None) -> None:
        """Copy the plant's values into the address space (subscribers see the changes), with
        `at` (default: now) as their source and server timestamps."""
        now = ua.DateTime.now(UTC) if at is None else ua.DateTime.combine(at.date(), at.timetz())
        if not self.running:  # held at zero, and the autopilot kept away, until Start()
            for axis in AXES:
                self._plant.set_speed_setpoint(axis, 0.0)
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

    async def write_data_value(self, name: str, data: ua.DataValue) -> None:
        """Write a measured variable (by historian name) as given: for tests that need a bad
        status code or a timestamp of their own."""
        await self._server.write_attribute_value(self._nodes[name], data)

    # -- Running, Start(), Stop(), SetSpeeds() -----------------------------------------------

    async def _add_controls(self, crane: Node) -> None:
        ns = self._namespace
        self._running_id = node_id("Ilmatar.Running", ns)
        await crane.add_variable(
            self._running_id, ua.QualifiedName("Running", ns), True, ua.VariantType.Boolean
        )
        was_running = argument("WasRunning", ua.VariantType.Boolean)
        for name, method in (("Start", self._start_method), ("Stop", self._stop_method)):
            await crane.add_method(
                node_id(f"Ilmatar.{name}", ns), ua.QualifiedName(name, ns), method, [],
                [was_running],
            )  # fmt: skip
        speeds = [argument(axis.capitalize(), ua.VariantType.Double) for axis in AXES]
        await crane.add_method(
            node_id("Ilmatar.SetSpeeds", ns), ua.QualifiedName("SetSpeeds", ns),
            self._set_speeds_method, speeds, [],
        )  # fmt: skip

    async def _set_running(self, running: bool) -> list[ua.Variant]:
        was_running, self.running = self.running, running
        if not running:
            for axis in AXES:
                self._plant.set_speed_setpoint(axis, 0.0)
        value = ua.DataValue(ua.Variant(running, ua.VariantType.Boolean))
        await self._server.write_attribute_value(self._running_id, value)
        return [ua.Variant(was_running, ua.VariantType.Boolean)]

    async def _start_method(self, parent: ua.NodeId) -> list[ua.Variant]:
        return await self._set_running(True)

    async def _stop_method(self, parent: ua.NodeId) -> list[ua.Variant]:
        return await self._set_running(False)

    async def _set_speeds_method(
        self, parent: ua.NodeId, *args: ua.Variant
    ) -> ua.StatusCode | list[ua.Variant]:
        # asyncua does not check the arguments against InputArguments: the method does.
        if len(args) != len(AXES):
            too_few = len(args) < len(AXES)
            return status(
                StatusCodes.BadArgumentsMissing if too_few else StatusCodes.BadTooManyArguments
            )
        speeds = dict(zip(AXES, (arg.Value for arg in args), strict=True))
        if not all(isinstance(speed, float) for speed in speeds.values()):
            return status(StatusCodes.BadTypeMismatch)
        if not self.running:
            return status(StatusCodes.BadInvalidState)
        for axis, speed in speeds.items():  # all or nothing
            if not abs(speed) <= self._plant.axis(axis).limits.max_speed:
                return status(StatusCodes.BadOutOfRange)
        for axis, speed in speeds.items():
            self._plant.set_speed_setpoint(axis, speed)
        return []
