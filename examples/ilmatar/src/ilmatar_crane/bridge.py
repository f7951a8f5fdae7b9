"""The HTTP bridge over OPC UA: the paper's query wrapper that let the API gateway reach the
crane's OPC UA server. It is an ordinary OPC UA client of that server: at connect it browses the
`Ilmatar` object to learn the variables (names, units, ranges, which are writable), then answers
each REST call with real OPC UA reads and writes.

Variable names are the browse paths below `Ilmatar`, e.g. `Hoist.Position`. Every `/api/` call
needs the API key in the `X-API-Key` header.
"""

from __future__ import annotations

import asyncio
import math
import secrets
from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from typing import Any

from asyncua import ua
from asyncua.client.client import Client
from asyncua.common.node import Node
from asyncua.ua.object_ids import ObjectIds
from asyncua.ua.uaerrors import (
    BadNotWritable,
    BadOutOfRange,
    BadUserAccessDenied,
    UaError,
    UaStatusCodeError,
)
from starlette.applications import Starlette
from starlette.requests import Request
from starlette.responses import JSONResponse, Response
from starlette.routing import Route

from ilmatar_crane._http import json_body, json_error, page_routes
from ilmatar_crane.settings import OPCUA_NAMESPACE

API_KEY_HEADER = "X-API-Key"
ENDPOINTS = (
    ("GET /api/variables", "Every variable with its value, unit and timestamp."),
    ("GET /api/variables/{name}", "One variable, e.g. Hoist.Position."),
    ("PUT /api/variables/{name}", 'Write a writable variable: {"value": 0.2}.'),
    ("GET /health", "Whether the OPC UA server answers (no API key needed)."),
)
# A dropped connection, a timeout or a server-side failure: the server cannot answer now.
UNAVAILABLE = (ConnectionError, TimeoutError, asyncio.TimeoutError, UaError)
Handler = Callable[[Request], Awaitable[Response]]


@dataclass(frozen=True)
class BridgeVariable:
    name: str
    node: Node
    unit: str | None
    description: str
    writable: bool
    low: float | None = None
    high: float | None = None

    def describe(self, value: ua.DataValue) -> dict[str, Any]:
        stamp = value.SourceTimestamp or value.ServerTimestamp
        return {
            "name": self.name,
            "value": value.Value.Value if value.Value is not None else None,
            "unit": self.unit,
            "timestamp": stamp.isoformat().replace("+00:00", "Z") if stamp else None,
            "writable": self.writable,
            "range": None if self.low is None else {"low": self.low, "high": self.high},
            "description": self.description,
            "node_id": self.node.nodeid.to_string(),
        }


async def browse_variables(client: Client) -> dict[str, BridgeVariable]:
    """The variables below the `Ilmatar` object, by `<Group>.<Name>`."""
    ns = await client.get_namespace_index(OPCUA_NAMESPACE)
    crane = await client.nodes.objects.get_child(f"{ns}:Ilmatar")
    found: dict[str, BridgeVariable] = {}
    for group in await crane.get_children(nodeclassmask=ua.NodeClass.Object):
        group_name = (await group.read_browse_name()).Name
        children = await group.get_children(
            refs=ObjectIds.HasComponent, nodeclassmask=ua.NodeClass.Variable
        )
        for node in children:
            variable = await _describe_node(node, group_name)
            found[variable.name] = variable
    return found


async def _describe_node(node: Node, group_name: str) -> BridgeVariable:
    name = f"{group_name}.{(await node.read_browse_name()).Name}"
    description = (await node.read_description()).Text or ""
    writable = ua.AccessLevel.CurrentWrite in await node.get_user_access_level()
    unit: str | None = None
    low = high = None
    for prop in await node.get_properties():
        prop_name = (await prop.read_browse_name()).Name
        if prop_name == "EngineeringUnits":
            unit = (await prop.read_value()).DisplayName.Text
        elif prop_name == "EURange":
            eu_range = await prop.read_value()
            low, high = float(eu_range.Low), float(eu_range.High)
    return BridgeVariable(name, node, unit, description, writable, low, high)


class OpcUaBridge:
    def __init__(self, opcua_url: str, api_key: str) -> None:
        self.opcua_url = opcua_url
        self._api_key = api_key
        self._client = Client(opcua_url, timeout=5)
        # asyncua servers grant at most 10 minutes; asking for more only logs a warning.
        self._client.session_timeout = 600_000
        self.variables: dict[str, BridgeVariable] = {}
        routes = [
            Route("/health", self._health),
            Route("/api/variables", self._guard(self._list)),
            Route("/api/variables/{name}", self._guard(self._get)),
            Route("/api/variables/{name}", self._guard(self._put), methods=["PUT"]),
            *page_routes("Ilmatar OPC UA bridge", f"HTTP access to {opcua_url}", ENDPOINTS),
        ]
        self.app = Starlette(routes=routes)

    async def connect(self) -> None:
        await self._client.connect(auto_reconnect=True, reconnect_request_timeout=5)
        try:
            self.variables = await browse_variables(self._client)
        except BaseException:
            await self._client.disconnect()
            raise

    async def disconnect(self) -> None:
        await self._client.disconnect()

    def _guard(self, handler: Handler) -> Handler:
        async def guarded(request: Request) -> Response:
            given = request.headers.get(API_KEY_HEADER, "")
            if not secrets.compare_digest(given.encode(), self._api_key.encode()):
                what = "a wrong" if given else "no"
                return json_error(
                    401, "unauthorized", f"The request had {what} API key in {API_KEY_HEADER}."
                )
            try:
                return await handler(request)
            except UaStatusCodeError as err:
                return json_error(502, "opcua_error", f"The OPC UA server answered {err!r}.")
            except UNAVAILABLE as err:
                return json_error(503, "opcua_unavailable", f"OPC UA server: {err!r}")

        return guarded

    async def _health(self, request: Request) -> Response:
        state = self._client.get_node(ua.NodeId(ua.Int32(ObjectIds.Server_ServerStatus_State)))
        try:
            await state.read_value()
        except UNAVAILABLE as err:
            return JSONResponse({"status": "unavailable", "detail": repr(err)}, 503)
        return JSONResponse({"status": "ok", "opcua": self.opcua_url})

    def _lookup(self, request: Request) -> BridgeVariable | Response:
        name = request.path_params["name"]
        variable = self.variables.get(name)
        if variable is None:
            known = ", ".join(sorted(self.variables))
            return json_error(404, "not_found", f"No variable {name!r}; known: {known}.")
        return variable

    async def _list(self, request: Request) -> Response:
        variables = list(self.variables.values())
        values = await self._client.read_attributes([v.node for v in variables])
        return JSONResponse(
            {"variables": [v.describe(dv) for v, dv in zip(variables, values, strict=True)]}
        )

    async def _get(self, request: Request) -> Response:
        variable = self._lookup(request)
        if isinstance(variable, Response):
            return variable
        return JSONResponse(variable.describe(await variable.node.read_data_value()))

    async def _put(self, request: Request) -> Response:
        variable = self._lookup(request)
        if isinstance(variable, Response):
            return variable
        if not variable.writable:
            return json_error(422, "read_only", f"{variable.name} is a measured, read-only value.")
        body = await json_body(request)
        if isinstance(body, Response):
            return body
        value = body.get("value")
        refused = _refuse_value(variable, value)
        if refused is not None:
            return refused
        assert isinstance(value, int | float)
        try:
            await variable.node.write_value(ua.Variant(float(value), ua.VariantType.Double))
        except BadOutOfRange:
            return json_error(422, "out_of_range", f"The server refused {value} as out of range.")
        except (BadUserAccessDenied, BadNotWritable):
            return json_error(422, "read_only", f"The server refused writing {variable.name}.")
        return JSONResponse(variable.describe(await variable.node.read_data_value()))


def _refuse_value(variable: BridgeVariable, value: object) -> Response | None:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        return json_error(422, "invalid_value", 'Send {"value": <number>}.')
    low, high = variable.low, variable.high
    if (low is not None and value < low) or (high is not None and value > high):
        return json_error(
            422,
            "out_of_range",
            f"{variable.name} must be between {low} and {high} {variable.unit or ''}, got {value}.",
        )
    return None
