"""The OPC UA connector against servers built like asyncua's own examples (server-methods.py,
server-minimal.py, server-with-encryption.py), real asyncua servers on free loopback ports:
method calls that take seconds, a server that stops answering, a server that accepts only
client certificates it knows, and a server presenting another certificate than expected."""

from __future__ import annotations

import asyncio
import re
from collections.abc import AsyncIterator, Awaitable, Callable
from contextlib import asynccontextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
import pytest_asyncio
from asyncua import Server, ua, uamethod
from asyncua.common.node import Node
from asyncua.crypto.permission_rules import SimpleRoleRuleset
from asyncua.server.user_managers import CertificateUserManager
from asyncua.ua.object_ids import ObjectIds

from tests.integration._opcua import (
    Platform,
    connected,
    eventually,
    running,
)
from tests.integration._opcua import platform as platform
from tests.integration.test_opcua_security import SERVER_URI, write_identity
from twinlink.domain.commands import CommandRecord

pytestmark = [pytest.mark.integration, pytest.mark.asyncio(loop_scope="module")]

EXAMPLES_URI = "http://examples.freeopcua.github.io"
QUICK = {  # small intervals, so a method of seconds outlasts many watchdog checks
    "publishing_interval_ms": 20,
    "sampling_interval_ms": 0,
    "batch_window_ms": 20,
    "watchdog_interval_s": 0.1,
    "reconnect_initial_s": 0.05,
    "reconnect_max_s": 0.2,
}


@uamethod
async def multiply_async(parent: ua.NodeId, x: int, y: int) -> None:
    """As asyncua's server-methods.py: sleeps x * y seconds (the session waits for it)."""
    await asyncio.sleep(x * y)


@dataclass
class Example:
    server: Server
    port: int
    objects: Node
    variable: Node
    method: Node

    @property
    def url(self) -> str:
        return url(self.port)

    def config(self, **extra: Any) -> dict[str, Any]:
        return {
            "url": self.url,
            "signals": [{"node": self.variable.nodeid.to_string(), "signal": "my_variable"}],
            "commands": {
                "multiply_async": {
                    "object": self.objects.nodeid.to_string(),
                    "method": self.method.nodeid.to_string(),
                    "args": ["x", "y"],
                },
            },
            **QUICK,
            **extra,
        }


def url(port: int) -> str:
    return f"opc.tcp://127.0.0.1:{port}/freeopcua/server/"


@asynccontextmanager
async def example_server(
    prepare: Callable[[Server], Awaitable[None]] | None = None,
    user_manager: CertificateUserManager | None = None,
) -> AsyncIterator[Example]:
    """asyncua's example server: MyObject with MyVariable (6.7) and multiply_async(x, y)."""
    server = Server(user_manager=user_manager)  # type: ignore[arg-type]
    await server.init()
    server.set_endpoint("opc.tcp://127.0.0.1:0/freeopcua/server/")
    if prepare is not None:
        await prepare(server)
    idx = await server.register_namespace(EXAMPLES_URI)
    objects = await server.nodes.objects.add_object(idx, "MyObject")
    variable = await objects.add_variable(idx, "MyVariable", 6.7)
    int64 = ua.NodeId(ua.Int32(ObjectIds.Int64))
    x = ua.Argument(Name="x", DataType=int64, ValueRank=-1)
    y = ua.Argument(Name="y", DataType=int64, ValueRank=-1)
    method = await objects.add_method(idx, "multiply_async", multiply_async, [x, y], [])
    await server.start()
    try:
        assert server.bserver is not None
        yield Example(server, server.bserver.port, objects, variable, method)
    finally:
        await server.stop()


# asyncua's server takes seconds to start (its standard address space): one of each kind per
# module, each test with its own platform and its own values.
@pytest_asyncio.fixture(loop_scope="module", scope="module")
async def methods_server() -> AsyncIterator[Example]:
    async with example_server() as example:
        yield example


async def send(platform: Platform, name: str, timeout_s: float, **args: Any) -> CommandRecord:
    return await platform.services.commands.send(
        platform.principal, platform.twin.slug, name, args, timeout_s=timeout_s
    )


async def value_arrives(platform: Platform, example: Example, value: float) -> None:
    """A change written on the server now reaches the platform: the session serves."""
    await example.variable.write_value(value)
    await eventually(
        lambda: any(s.get("my_variable") == value for s in platform.samples().values()),
        f"my_variable = {value}",
    )


# -- method calls that take seconds (item 12) ----------------------------------------------


async def test_a_method_call_longer_than_the_request_timeout_keeps_the_session(
    platform: Platform, methods_server: Example
) -> None:
    example = methods_server
    async with running(platform.connector(example.config(request_timeout_s=1))) as connector:
        await connected(connector)
        # 3 s: thirty watchdog checks and three request timeouts, within the command's 10 s
        record = await send(platform, "multiply_async", 10, x=1, y=3)
        assert (record.state, record.result) == ("succeeded", {"outputs": []}), record.error
        assert connector.status.errors == {}, connector.status.last_error
        assert connector.status.state == "connected"
        await value_arrives(platform, example, 7.5)


async def test_a_method_call_longer_than_the_command_timeout_fails_saying_so(
    platform: Platform, methods_server: Example
) -> None:
    example = methods_server
    async with running(platform.connector(example.config(request_timeout_s=5))) as connector:
        await connected(connector)
        record = await send(platform, "multiply_async", 1, x=1, y=3)
        assert record.state == "expired"
        await eventually(lambda: connector.status.errors["command_failed"] == 1, "the answer")
        method = example.method.nodeid.to_string()
        assert re.fullmatch(
            rf"command_failed: multiply_async: the server did not answer the call of "
            rf"{re.escape(method)} within (1|0\.\d+) s, the time the command had left "
            r"\(send it with a longer timeout_s\)",
            str(connector.status.last_error),
        ), connector.status.last_error
        await value_arrives(platform, example, 8.5)  # after the server finished the call
        assert "connection_lost" not in connector.status.errors
        assert connector.status.state == "connected"


# -- a server that stops answering ----------------------------------------------------------


class FreezingProxy:
    """A TCP proxy on loopback that can stop passing bytes on without closing anything, as a
    hung server or a network dropping packets would."""

    def __init__(self, target_port: int) -> None:
        self.target_port = target_port
        self.flowing = asyncio.Event()
        self.flowing.set()
        self.port = 0
        self._server: asyncio.Server | None = None
        self._tasks: set[asyncio.Task[None]] = set()

    async def __aenter__(self) -> FreezingProxy:
        self._server = await asyncio.start_server(self._connection, "127.0.0.1", 0)
        self.port = self._server.sockets[0].getsockname()[1]
        return self

    async def __aexit__(self, *_: object) -> None:
        assert self._server is not None
        self._server.close()
        for task in list(self._tasks):
            task.cancel()
        await asyncio.gather(*self._tasks, return_exceptions=True)
        await self._server.wait_closed()

    async def _connection(
        self, client_r: asyncio.StreamReader, client_w: asyncio.StreamWriter
    ) -> None:
        task = asyncio.current_task()
        assert task is not None
        self._tasks.add(task)
        server_r, server_w = await asyncio.open_connection("127.0.0.1", self.target_port)
        try:
            await asyncio.gather(self._pump(client_r, server_w), self._pump(server_r, client_w))
        except (OSError, asyncio.IncompleteReadError):
            pass
        finally:
            for writer in (client_w, server_w):
                writer.close()
            self._tasks.discard(task)

    async def _pump(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        while data := await reader.read(65536):
            await self.flowing.wait()
            writer.write(data)
            await writer.drain()
        writer.close()


async def test_a_server_that_stops_answering_is_noticed_by_the_watchdog(
    platform: Platform, methods_server: Example
) -> None:
    example = methods_server
    async with FreezingProxy(example.port) as proxy:
        through = url(proxy.port)
        config = example.config(url=through, request_timeout_s=1)
        async with running(platform.connector(config)) as connector:
            await connected(connector)
            proxy.flowing.clear()
            await eventually(lambda: connector.status.state == "reconnecting", "reconnecting")
            assert connector.status.last_error == (
                f"connection_lost: {through}: the server did not answer the watchdog's read of its "
                "state within 1 s (request_timeout_s)"
            )
            await eventually(lambda: connector.status.errors["connect_failed"] >= 1, "an attempt")
            assert connector.status.last_error == (
                f"connect_failed: {through} did not answer within 1 s (request_timeout_s)"
            )
            proxy.flowing.set()
            await connected(connector)
            await value_arrives(platform, example, 9.5)


# -- a server that accepts only client certificates it knows (item 15) ----------------------


@pytest.fixture(scope="module")
def identities(tmp_path_factory: pytest.TempPathFactory) -> dict[str, tuple[Path, Path]]:
    folder = tmp_path_factory.mktemp("identities")
    return {
        "server": write_identity(folder, "server", SERVER_URI, server=True),
        "other-server": write_identity(folder, "other-server", SERVER_URI, server=True),
        "known": write_identity(folder, "known-client", "urn:example:known-client"),
    }


def with_encryption(
    identities: dict[str, tuple[Path, Path]],
) -> Callable[[Server], Awaitable[None]]:
    """As asyncua's server-with-encryption.py: SignAndEncrypt only, its certificate."""

    async def prepare(server: Server) -> None:
        cert, key = identities["server"]
        server.set_security_policy(
            [ua.SecurityPolicyType.Basic256Sha256_SignAndEncrypt],
            permission_ruleset=SimpleRoleRuleset(),
        )
        await server.load_certificate(str(cert))
        await server.load_private_key(str(key))

    return prepare


@pytest_asyncio.fixture(loop_scope="module", scope="module")
async def known_clients_server(
    identities: dict[str, tuple[Path, Path]],
) -> AsyncIterator[Example]:
    users = CertificateUserManager()
    await users.add_user(identities["known"][0], name="known")
    async with example_server(with_encryption(identities), users) as example:
        yield example


async def test_a_server_wanting_a_known_client_certificate_says_so(
    platform: Platform, known_clients_server: Example, identities: dict[str, tuple[Path, Path]]
) -> None:
    example = known_clients_server
    config = example.config(security_policy="Basic256Sha256", request_timeout_s=5)
    async with running(platform.connector(config)) as connector:
        await eventually(lambda: connector.status.errors["auth_failed"] >= 2, "two attempts")
        assert connector.status.state == "error"
        assert connector.status.last_error == (
            f"auth_failed: {example.url} refused an anonymous session (BadUserAccessDenied);"
            " its endpoints: Basic256Sha256 SignAndEncrypt (anonymous, user certificate, "
            "username); it accepts anonymous sessions only from client certificates it "
            "knows, and this one was generated at start: give certificate and private_key "
            "its administrator trusts, or set username and password"
        )
    cert, key = identities["known"]
    known = {**config, "certificate": str(cert), "private_key": str(key)}
    async with running(platform.connector(known)) as connector:
        await connected(connector)
        await value_arrives(platform, example, 10.5)


# -- a server presenting another certificate than expected (item 13) -----------------------


async def test_a_server_presenting_another_certificate_is_refused_and_retried(
    platform: Platform, known_clients_server: Example, identities: dict[str, tuple[Path, Path]]
) -> None:
    example = known_clients_server
    cert, key = identities["known"]
    config = example.config(
        security_policy="Basic256Sha256",
        certificate=str(cert),
        private_key=str(key),
        server_certificate=str(identities["other-server"][0]),
        request_timeout_s=5,
    )
    async with running(platform.connector(config)) as connector:
        await eventually(lambda: connector.status.errors["security"] >= 2, "two attempts")
        assert connector.status.state == "error"
        text = str(connector.status.last_error)
        assert text.startswith(
            f"security: {example.url}: server certificate does not match: the server "
            "presents 'server' (thumbprint "
        ), text
        assert f"server_certificate {identities['other-server'][0]} is 'other-server'" in text
        assert set(connector.status.errors) == {"security"}  # never a timeout
    right = {**config, "server_certificate": str(identities["server"][0])}
    async with running(platform.connector(right)) as connector:
        await connected(connector)
