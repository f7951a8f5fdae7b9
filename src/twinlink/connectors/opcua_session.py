"""What an OPC UA connector does on one connected session: find the configured nodes,
subscribe the signals' nodes, and run twin commands as node writes and method calls.

Everything here lives as long as the session: node ids found by browse path or namespace URI
and the nodes' data types are looked up again after a reconnect (the server may have changed).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from asyncua import ua
from asyncua.client.client import Client
from asyncua.common.methods import call_method_full
from asyncua.common.subscription import OverflowPolicy, Subscription
from asyncua.common.ua_utils import data_type_to_variant_type
from asyncua.ua.attribute_ids import AttributeIds
from asyncua.ua.uaerrors import BadNoMatch, UaStatusCodeError

from twinlink.connectors.base import ConnectorStatus
from twinlink.connectors.opcua_client import status_name
from twinlink.connectors.opcua_config import (
    MethodCommand,
    OpcUaConfig,
    SignalMapping,
    WriteCommand,
    parse_node_ref,
)
from twinlink.connectors.opcua_values import ValueRefused, json_value, variant_for

# Notifications asyncua holds for the connector; past this (the platform far behind) the
# oldest are dropped.
MAX_BUFFERED = 100_000
_DEADBAND_TYPES = {"absolute": 1, "percent": 2}


class CommandFailed(Exception):
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
            except BadNoMatch:
                raise CommandFailed(f"the server has no node at {text}") from None
            return node.nodeid
        assert ref.node_id is not None
        if ref.namespace_uri is None:
            return ref.node_id
        namespaces = await self.client.get_namespace_array()
        if ref.namespace_uri not in namespaces:
            raise CommandFailed(f"the server has no namespace {ref.namespace_uri}")
        index = ua.Int16(namespaces.index(ref.namespace_uri))
        return ua.NodeId(ref.node_id.Identifier, index, ref.node_id.NodeIdType)


@dataclass(slots=True)
class Subscribed:
    """The session's subscription and the signal of each monitored item's client handle."""

    subscription: Subscription
    signals: dict[int, str] = field(default_factory=dict)


async def subscribe(
    client: Client, config: OpcUaConfig, nodes: NodeResolver, status: ConnectorStatus
) -> Subscribed:
    """Create the subscription with one monitored item per signal. A node that cannot be
    found or monitored is counted as an error (`subscribe_failed`); the others go on."""
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
            status.error("subscribe_failed", f"{signal.signal}: {err}")
            continue
        requests.append((signal, _monitor_request(handle, node_id, signal, config)))
    if not requests:
        return out
    results = await subscription.create_monitored_items([r for _, r in requests])
    for (signal, request), result in zip(requests, results, strict=True):
        if isinstance(result, ua.StatusCode):
            text = f"{signal.signal}: the server does not monitor {signal.node} ({result.name})"
            status.error("subscribe_failed", text)
        else:
            out.signals[request.RequestedParameters.ClientHandle] = signal.signal
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


class CommandRunner:
    """Twin commands as writes and method calls on the session's server."""

    def __init__(self, client: Client, config: OpcUaConfig, nodes: NodeResolver) -> None:
        self.client = client
        self.config = config
        self.nodes = nodes
        self._types: dict[ua.NodeId, ua.VariantType] = {}
        self._inputs: dict[ua.NodeId, list[ua.VariantType] | None] = {}

    async def run(self, name: str, args: dict[str, Any]) -> Any:
        """The command's result; raises CommandFailed with the reason it failed."""
        mapping = self.config.commands[name]
        try:
            if isinstance(mapping, WriteCommand):
                return await self._write(mapping, args)
            return await self._call(mapping, args)
        except UaStatusCodeError as err:
            raise CommandFailed(f"the server refused it: {status_name(err)}") from err

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
            raise CommandFailed(f"argument {mapping.arg!r}: {err}") from None
        await node.write_value(ua.DataValue(variant))
        return {"node": mapping.node, "value": json_value(variant.Value)}

    async def _call(self, mapping: MethodCommand, args: dict[str, Any]) -> Any:
        missing = [name for name in mapping.args if name not in args]
        if missing:
            raise CommandFailed(f"the arguments {', '.join(map(repr, missing))} are missing")
        parent = self.client.get_node(await self.nodes.node_id(mapping.object))
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
                raise CommandFailed(f"argument {name!r}: {err}") from None
        result = await call_method_full(parent, method_id, *variants)
        return {"outputs": [json_value(value) for value in result.OutputArguments]}

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
