"""`command` ops on a live session, with a stand-in for CommandService: the answers, the
refusals, and ops running side by side within their limit."""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from typing import Any

import orjson
import pytest

from tests.unit.test_live_session import USER, FakeAuth, FakeRegistry
from twinlink.auth.rights import Principal
from twinlink.auth.service import AuthError
from twinlink.bus import MemoryBus
from twinlink.domain.commands import CommandRecord
from twinlink.domain.errors import ForbiddenError, InvalidInputError
from twinlink.domain.jsontext import int64_problem
from twinlink.live.commands import CommandOps, CommandSender
from twinlink.live.hub import LiveHub
from twinlink.live.outbox import Outbox
from twinlink.live.protocol import CommandRequest
from twinlink.live.session import LiveSession

T0 = 1_732_200_000_000_000_000
DEADLINE_S = 10.0  # for what the session is waited on to do: only a broken test waits this long


class FakeCommands:
    """Succeeds at once, except: `slow` waits for `release`, `forbidden`/`bad` are refused and
    `boom` fails unexpectedly."""

    def __init__(self) -> None:
        self.release = asyncio.Event()
        self.sent: list[dict[str, Any]] = []

    async def send(
        self,
        principal: Principal,
        slug: str,
        name: str,
        args: dict[str, Any] | None = None,
        device: str | None = None,
        timeout_s: float | None = None,
        queue: bool = False,
        wait: bool = True,
    ) -> CommandRecord:
        self.sent.append({"slug": slug, "name": name, "args": args, "device": device,
                          "timeout_s": timeout_s, "queue": queue, "wait": wait})  # fmt: skip
        if name == "slow":
            await self.release.wait()
        if name == "forbidden":
            raise ForbiddenError(f"a viewer cannot send commands; sending to {slug!r} needs ...")
        if name == "bad":
            raise InvalidInputError("the twin has no command 'bad'")
        if name == "boom":
            raise RuntimeError("a bug")
        record = CommandRecord(
            id=f"id-{name}", twin_id=7, device_id=1, device="rig", name=name, args=args or {},
            state="pending", queued=queue, sent_by="alice", created_ns=T0, expires_ns=T0 + 10**9,
        )  # fmt: skip
        if wait:
            record.finish("succeeded", {"ok": True}, None, T0 + 1000)
        return record


def make() -> tuple[LiveSession, FakeCommands, FakeAuth]:
    commands, auth = FakeCommands(), FakeAuth()
    session = LiveSession(
        "tl_good",
        Principal(user=USER),
        hub=LiveHub(MemoryBus()),
        outbox=Outbox(16),
        auth=auth,
        registry=FakeRegistry(),
        commands=commands,
    )
    return session, commands, auth


def sent(session: LiveSession) -> list[dict[str, Any]]:
    out = []
    while (message := session.outbox.take()) is not None:
        out.append(orjson.loads(message))
    return out


async def op(session: LiveSession, **fields: Any) -> None:
    await session.handle(orjson.dumps({"op": "command", "id": "c1", "twin": "rig", **fields}))


async def until(condition: Callable[[], bool]) -> None:
    """Poll the session's real state until `condition` holds (or the deadline passes)."""
    async with asyncio.timeout(DEADLINE_S):
        while not condition():
            await asyncio.sleep(0.001)  # polling the state, not waiting for it to change


async def settled(session: LiveSession) -> list[dict[str, Any]]:
    """What the session sent once its command ops have finished."""
    ops = session.commands
    assert ops is not None
    await until(lambda: len(ops) == 0)
    return sent(session)


class WatchedOps(CommandOps):
    """Command ops that tell when an op arrives while `limit` ops are under way."""

    def __init__(self, sender: CommandSender, outbox: Outbox, limit: int) -> None:
        super().__init__(sender, outbox, limit)
        self.limit = limit
        self.arrived_when_full = asyncio.Event()

    async def start(self, principal: Principal, request: CommandRequest) -> None:
        if len(self) >= self.limit:
            self.arrived_when_full.set()
        await super().start(principal, request)


async def test_a_command_is_answered_with_its_record_when_finished() -> None:
    session, commands, _ = make()
    await op(session, name="pause", args={"x": 1}, device="rig", timeout_s=5, queue=True)
    [answer] = await settled(session)
    assert answer["type"] == "command" and answer["id"] == "c1"
    assert answer["command"]["id"] == "id-pause" and answer["command"]["twin"] == "rig"
    assert answer["command"]["state"] == "succeeded" and answer["command"]["result"] == {"ok": 1}
    assert commands.sent == [{"slug": "rig", "name": "pause", "args": {"x": 1}, "device": "rig",
                              "timeout_s": 5.0, "queue": True, "wait": True}]  # fmt: skip


async def test_without_wait_the_answer_is_the_pending_command() -> None:
    session, _, _ = make()
    await op(session, name="pause", wait=False)
    [answer] = await settled(session)
    assert answer["command"]["state"] == "pending" and answer["command"]["finished"] is None


@pytest.mark.parametrize(
    ("name", "status", "text"),
    [
        ("forbidden", 403, "a viewer cannot send commands"),
        ("bad", 422, "the twin has no command 'bad'"),
        ("boom", 500, "internal error; the command may not have been sent"),
    ],
)
async def test_refusals_are_errors_with_the_http_status(name: str, status: int, text: str) -> None:
    session, _, _ = make()
    await op(session, name=name)
    [answer] = await settled(session)
    assert answer["type"] == "error" and answer["op"] == "command" and answer["id"] == "c1"
    assert answer["status"] == status and answer["message"].startswith(text)


@pytest.mark.parametrize(
    ("fields", "text"),
    [
        ({"twin": None, "name": "x"}, '"twin" must be the slug of a twin'),
        ({"name": 3}, '"name" must be the name of a command'),
        ({"name": "x", "args": [1]}, '"args" must be an object'),
        ({"name": "x", "device": 1}, '"device" must be the name of a device'),
        ({"name": "x", "timeout_s": True}, '"timeout_s" must be a number'),
        ({"name": "x", "wait": "yes"}, '"queue" and "wait" must be true or false'),
    ],
)
async def test_malformed_ops_are_refused_before_anything_is_sent(
    fields: dict[str, Any], text: str
) -> None:
    session, commands, _ = make()
    await op(session, **fields)
    [answer] = sent(session)
    assert (answer["type"], answer["op"], answer["id"], answer["status"]) == (
        "error", "command", "c1", 422,
    )  # fmt: skip
    assert answer["message"].startswith(text) and commands.sent == []


@pytest.mark.parametrize("n", [2**63, -(2**63) - 1, 2**80])
async def test_arguments_beyond_64_bits_are_refused_not_rounded(n: int) -> None:
    # orjson read 2**80 as 1.2089258196146292e+24 and the command went out with that float.
    session, commands, _ = make()
    await session.handle(
        f'{{"op": "command", "id": "c1", "twin": "rig", "name": "go", "args": {{"v": [{n}]}}}}'
    )
    [answer] = sent(session)
    assert (answer["type"], answer["op"], answer["id"], answer["status"]) == (
        "error", "command", "c1", 422,
    )  # fmt: skip
    assert answer["message"] == f"args.v[0]: {int64_problem(n)}" and commands.sent == []


async def test_arguments_at_the_64_bit_bounds_go_out_exact() -> None:
    session, commands, _ = make()
    await op(session, name="go", args={"low": -(2**63), "high": 2**63 - 1})
    await settled(session)
    assert commands.sent[0]["args"] == {"low": -(2**63), "high": 2**63 - 1}


async def test_ops_run_side_by_side() -> None:
    session, commands, _ = make()
    await op(session, id="slow", name="slow")
    await op(session, id="fast", name="pause")
    await until(lambda: len(session.outbox) > 0)  # an answer, while the slow one is held
    assert [m["id"] for m in sent(session)] == ["fast"]  # not held up by the slow one
    commands.release.set()
    assert [m["id"] for m in await settled(session)] == ["slow"]


async def test_at_most_limit_ops_are_under_way_and_then_reading_waits() -> None:
    session, commands, _ = make()
    ops = session.commands = WatchedOps(commands, session.outbox, limit=1)
    await op(session, id="a", name="slow")
    second = asyncio.create_task(op(session, id="b", name="pause"))
    await asyncio.wait_for(ops.arrived_when_full.wait(), DEADLINE_S)
    # It arrived with "a" under way: it waits for room, and reading the client waits with it.
    assert not second.done() and len(commands.sent) == 1
    commands.release.set()
    await asyncio.wait_for(second, DEADLINE_S)
    assert sorted(m["id"] for m in await settled(session)) == ["a", "b"]


async def test_each_command_checks_the_token_again() -> None:
    session, commands, auth = make()
    await op(session, name="pause")
    await settled(session)
    auth.valid = False
    with pytest.raises(AuthError):
        await op(session, name="pause")
    assert len(commands.sent) == 1


async def test_ops_under_way_end_with_the_connection() -> None:
    session, _, _ = make()
    await op(session, name="slow")
    await session.stop_commands()
    assert session.commands is not None and len(session.commands) == 0
    assert sent(session) == []


async def test_a_session_without_commands_says_so() -> None:
    session = LiveSession(
        "tl_good",
        Principal(user=USER),
        hub=LiveHub(MemoryBus()),
        outbox=Outbox(16),
        auth=FakeAuth(),
        registry=FakeRegistry(),
    )
    await op(session, name="pause")
    [answer] = sent(session)
    assert answer["message"] == "commands are not available here" and answer["id"] == "c1"
