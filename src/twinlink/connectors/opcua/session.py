"""What an OPC UA connector does on one connected session: find the configured nodes,
subscribe the signals' nodes, and run twin commands as node writes and method calls.

Everything here lives as long as the session: node ids found by browse path or namespace URI
and the nodes' data types are looked up again after a reconnect (the server may have changed).
"""

from __future__ import annotations

import asyncio
import contextlib
import itertools
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

from asyncua import ua
from asyncua.client.client import Client
from asyncua.common.subscription import OverflowPolicy, Subscription
from asyncua.common.ua_utils import data_type_to_variant_type
from asyncua.ua.attribute_ids import AttributeIds
from asyncua.ua.object_ids import ObjectIds
from asyncua.ua.ua_binary import struct_from_binary
from asyncua.ua.uaerrors import BadNoMatch, UaStatusCodeError

from twinlink.connectors.opcua.client import status_name
from twinlink.connectors.opcua.config import (
    MethodCommand,
    OpcUaConfig,
    SignalMapping,
    WriteCommand,
    parse_node_ref,
)
from twinlink.connectors.opcua.values import ValueRefused, json_value, variant_for
from twinlink.domain.errors import TwinlinkError

# Notifications asyncua holds for the connector; past this (the platform far behind) the
# oldest are dropped.
MAX_BUFFERED = 100_000
_DEADBAND_TYPES = {"absolute": 1, "percent": 2}


class CommandFailed(TwinlinkError):
    """A command could not be carried out; the text is the command's error."""


class NodeResolver:
    """Node ids of the configured node references, found on the connected server."""

    def __init__(self, client: Client) -> None:
        self.client = client
        self._found: dict[str, ua.NodeId] = {}

    async def node_id(self, text: str) -> ua.NodeId:
        """Raises CommandFailed saying why the node cannot be found."""
        found = self._found.get(text)
        if found is None:
            found = self._found[text] = await self._find(text)
        return found

    async def _find(self, text: str) -> ua.NodeId:
        ref = parse_node_ref(text)
        if ref.browse_path is not None:
            try:
                node = await self.client.nodes.objects.get_child(ref.browse_path)
            except BadNoMatch as err:
                raise CommandFailed(f"the server has no node at {text}") from err
            return node.nodeid
        assert ref.node_id is not None
        if ref.namespace_uri is None:
            return ref.node_id
        namespaces = await self.client.get_namespace_array()
        if ref.namespace_uri not in namespaces:
            raise CommandFailed(f"the server has no namespace {ref.namespace_uri}")
        index = ua.Int16(namespaces.index(ref.namespace_uri))
        return ua.NodeId(ref.node_id.Identifier, index, ref.node_id.NodeIdType)


@dataclass(frozen=True, slots=True)
class FailedNode:
    """A signal whose node the server did not find or will not monitor, and why."""

    signal: str
    node: str
    reason: str

    def text(self) -> str:
        return f"{self.signal}: {self.reason}"


@dataclass(slots=True)
class Subscribed:
    """The session's subscription, the signal of each monitored item's client handle, and
    the signals that could not be subscribed, in the order of the configuration."""

    subscription: Subscription
    signals: dict[int, str] = field(default_factory=dict)
    failed: list[FailedNode] = field(default_factory=list)


async def subscribe(client: Client, config: OpcUaConfig, nodes: NodeResolver) -> Subscribed:
    """Create the subscription with one monitored item per signal. A node that cannot be
    found or monitored is listed in `failed` with the reason; the others go on."""
    subscription = await client.create_subscription(
        config.publishing_interval_ms,
        None,  # notifications are read from the subscription as they queue up
        queue_maxsize=MAX_BUFFERED,
        overflow=OverflowPolicy.DROP_OLDEST,
    )
    out = Subscribed(subscription)
    requests: list[tuple[SignalMapping, ua.MonitoredItemCreateRequest]] = []
    for handle, signal in enumerate(config.signals, start=1):
        try:
            node_id = await nodes.node_id(signal.node)
        except CommandFailed as err:
            out.failed.append(FailedNode(signal.signal, signal.node, str(err)))
            continue
        requests.append((signal, _monitor_request(handle, node_id, signal, config)))
    if not requests:
        return out
    results = await subscription.create_monitored_items([r for _, r in requests])
    for (signal, request), result in zip(requests, results, strict=True):
        if isinstance(result, ua.StatusCode):
            reason = f"the server does not monitor {signal.node} ({result.name})"
            out.failed.append(FailedNode(signal.signal, signal.node, reason))
        else:
            out.signals[request.RequestedParameters.ClientHandle] = signal.signal
    # In the configuration's order, whichever step refused them.
    order = {s.signal: i for i, s in enumerate(config.signals)}
    out.failed.sort(key=lambda f: order[f.signal])
    return out


def _monitor_request(
    handle: int, node_id: ua.NodeId, signal: SignalMapping, config: OpcUaConfig
) -> ua.MonitoredItemCreateRequest:
    params = ua.MonitoringParameters(
        ClientHandle=ua.UInt32(handle),
        SamplingInterval=config.sampling_ms(signal),
        QueueSize=ua.UInt32(config.queue_size(signal)),
        DiscardOldest=True,
    )
    if signal.deadband > 0:
        params.Filter = ua.DataChangeFilter(
            Trigger=ua.DataChangeTrigger.StatusValue,
            DeadbandType=ua.UInt32(_DEADBAND_TYPES[signal.deadband_type]),
            DeadbandValue=ua.Double(signal.deadband),
        )
    return ua.MonitoredItemCreateRequest(
        ItemToMonitor=ua.ReadValueId(NodeId=node_id, AttributeId=ua.UInt32(AttributeIds.Value)),
        MonitoringMode=ua.MonitoringMode.Reporting,
        RequestedParameters=params,
    )


async def send_request(client: Client, request: Any, timeout: float) -> Any:
    """Send one service request that may take `timeout` s: asyncua's own service calls
    (Node.call_method, Node.read_value) give up after request_timeout_s."""
    protocol = client.uaclient.protocol
    if protocol is None:
        raise ConnectionError("the connection to the OPC UA server is closed")
    return await protocol.send_request(request, timeout=timeout)


async def read_server_state(client: Client, timeout: float) -> None:
    """Read the server's state (Server.ServerStatus.State), waiting up to `timeout` s."""
    read = ua.ReadRequest()
    read.Parameters.NodesToRead = [
        ua.ReadValueId(
            NodeId=ua.NodeId(ua.Int32(ObjectIds.Server_ServerStatus_State)),
            AttributeId=ua.UInt32(AttributeIds.Value),
        )
    ]
    data = await send_request(client, read, timeout)
    response: ua.ReadResponse = struct_from_binary(ua.ReadResponse, data)
    response.ResponseHeader.ServiceResult.check()


class CommandRunner:
    """Twin commands as writes and method calls on the session's server.

    A method call may run as long as its command may (until the command expires), not only
    `request_timeout_s`: a machine's method (home an axis, run a cycle) often takes seconds.
    `busy_until` tells the connector's watchdog how long the server may be busy with calls,
    as a server may answer a session's requests one at a time."""

    def __init__(self, client: Client, config: OpcUaConfig, nodes: NodeResolver) -> None:
        self.client = client
        self.config = config
        self.nodes = nodes
        self._types: dict[ua.NodeId, ua.VariantType] = {}
        self._inputs: dict[ua.NodeId, list[ua.VariantType] | None] = {}
        self._calls: dict[int, float] = {}  # a call in flight -> its deadline (loop time)
        self._call_ids = itertools.count()

    def busy_until(self) -> float | None:
        """The latest deadline (loop time) of the method calls in flight, None without any."""
        return max(self._calls.values(), default=None)

    async def run(self, name: str, args: dict[str, Any], deadline: float | None = None) -> Any:
        """The command's result; raises CommandFailed with the reason it failed. `deadline`
        (loop time) is when the command expires: how long a method call may take."""
        mapping = self.config.commands[name]
        try:
            if isinstance(mapping, WriteCommand):
                return await self._write(mapping, args)
            return await self._call(mapping, args, deadline)
        except UaStatusCodeError as err:
            raise CommandFailed(f"the server refused it: {status_name(err)}") from err
        except TimeoutError as err:  # a lookup or a write: asyncua's per-request timeout
            limit = self.config.request_timeout_s
            raise CommandFailed(
                f"the server did not answer a request within {limit:g} s (request_timeout_s)"
            ) from err

    async def _write(self, mapping: WriteCommand, args: dict[str, Any]) -> Any:
        if mapping.arg not in args:
            raise CommandFailed(f"the argument {mapping.arg!r} (the value to write) is missing")
        node = self.client.get_node(await self.nodes.node_id(mapping.node))
        vtype = self._types.get(node.nodeid)
        if vtype is None:
            vtype = self._types[node.nodeid] = await node.read_data_type_as_variant_type()
        try:
            variant = variant_for(args[mapping.arg], vtype)
        except ValueRefused as err:
            raise CommandFailed(f"argument {mapping.arg!r}: {err}") from err
        await node.write_value(ua.DataValue(variant))
        return {"node": mapping.node, "value": json_value(variant.Value)}

    async def _call(
        self, mapping: MethodCommand, args: dict[str, Any], deadline: float | None
    ) -> Any:
        missing = [name for name in mapping.args if name not in args]
        if missing:
            raise CommandFailed(f"the arguments {', '.join(map(repr, missing))} are missing")
        parent = await self.nodes.node_id(mapping.object)
        method_id = await self.nodes.node_id(mapping.method)
        types = await self._input_types(method_id)
        if types is not None and len(types) != len(mapping.args):
            raise CommandFailed(
                f"the method {mapping.method} takes {len(types)} arguments and the command "
                f"maps {len(mapping.args)} ({', '.join(mapping.args) or 'none'})"
            )
        variants = []
        for index, name in enumerate(mapping.args):
            vtype = ua.VariantType.Variant if types is None else types[index]
            try:
                variants.append(variant_for(args[name], vtype))
            except ValueRefused as err:
                raise CommandFailed(f"argument {name!r}: {err}") from err
        request = ua.CallMethodRequest(ObjectId=parent, MethodId=method_id, InputArguments=variants)
        result = await self._send_call(request, mapping, deadline)
        return {"outputs": [json_value(value.Value) for value in result.OutputArguments or []]}

    async def _send_call(
        self, request: ua.CallMethodRequest, mapping: MethodCommand, deadline: float | None
    ) -> ua.CallMethodResult:
        loop = asyncio.get_running_loop()
        why = "the time the command had left (send it with a longer timeout_s)"
        if deadline is None:  # a command without an expiry: the usual request timeout
            deadline = loop.time() + self.config.request_timeout_s
            why = "request_timeout_s"
        limit = deadline - loop.time()
        if limit <= 0:
            raise CommandFailed("the command expired before the method could be called")
        call = ua.CallRequest()
        call.Parameters.MethodsToCall = [request]
        with self._in_flight(deadline):
            try:
                data = await send_request(self.client, call, limit)
            except TimeoutError as err:
                raise CommandFailed(
                    f"the server did not answer the call of {mapping.method} within "
                    f"{limit:.3g} s, {why}"
                ) from err
        response: ua.CallResponse = struct_from_binary(ua.CallResponse, data)
        response.ResponseHeader.ServiceResult.check()
        result: ua.CallMethodResult = response.Results[0]
        result.StatusCode.check()
        return result

    @contextlib.contextmanager
    def _in_flight(self, deadline: float) -> Iterator[None]:
        key = next(self._call_ids)
        self._calls[key] = deadline
        try:
            yield
        finally:
            del self._calls[key]

    async def _input_types(self, method_id: ua.NodeId) -> list[ua.VariantType] | None:
        """The method's input argument types, None when it does not declare them."""
        if method_id in self._inputs:
            return self._inputs[method_id]
        method = self.client.get_node(method_id)
        try:
            arguments = await (await method.get_child("0:InputArguments")).read_value()
        except BadNoMatch:
            arguments = []  # a method without InputArguments takes none
        except UaStatusCodeError:
            self._inputs[method_id] = None
            return None
        types = [
            await data_type_to_variant_type(self.client.get_node(arg.DataType)) for arg in arguments
        ]
        self._inputs[method_id] = types
        return types
