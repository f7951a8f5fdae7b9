"""A live session's ops, with the real hub and MemoryBus and stand-ins for auth and registry."""

from __future__ import annotations

from typing import Any

import orjson
import pytest

from twinlink.auth.rights import Principal
from twinlink.auth.service import AuthError
from twinlink.bus import MemoryBus, samples_subject
from twinlink.domain.errors import NotFoundError
from twinlink.domain.jsontext import int64_problem
from twinlink.domain.records import TwinRecord, User
from twinlink.domain.samples import SampleBatch
from twinlink.live import protocol
from twinlink.live.hub import LiveHub
from twinlink.live.outbox import Outbox
from twinlink.live.session import LiveSession

T0 = 1_732_200_000_000_000_000
USER = User(id=1, username="alice", is_admin=False, groups=[], created_ns=0)


class FakeAuth:
    def __init__(self) -> None:
        self.valid = True
        self.calls = 0

    async def authenticate(self, token: str) -> Principal:
        self.calls += 1
        if not self.valid or token != "tl_good":
            raise AuthError("the token has been revoked")
        return Principal(user=USER, token_id=1)


class FakeRegistry:
    def __init__(self) -> None:
        self.visible = {"rig": TwinRecord(7, "rig", "urn:rig", "Rig", 0, 0, "public")}

    async def require_twin(self, principal: Principal, slug: str) -> tuple[TwinRecord, str | None]:
        twin = self.visible.get(slug)
        if twin is None:
            raise NotFoundError(f"no twin {slug!r}")
        return twin, "viewer"

    async def require_role(
        self, principal: Principal, slug: str, needed: str, what: str
    ) -> TwinRecord:
        return (await self.require_twin(principal, slug))[0]


async def latest(twin_id: int, stream: str, signals: frozenset[str] | None) -> dict[str, Any]:
    return {"x": {"time": T0, "value": 1.0}}


def make(
    latest_reader: Any = latest,
) -> tuple[LiveSession, MemoryBus, LiveHub, FakeAuth, FakeRegistry]:
    bus, auth, registry = MemoryBus(), FakeAuth(), FakeRegistry()
    hub = LiveHub(bus)
    session = LiveSession(
        "tl_good",
        Principal(user=USER),
        hub=hub,
        outbox=Outbox(16),
        auth=auth,
        registry=registry,
        latest=latest_reader,
    )
    return session, bus, hub, auth, registry


def sent(session: LiveSession) -> list[dict[str, Any]]:
    out = []
    while (message := session.outbox.take()) is not None:
        out.append(orjson.loads(message))
    return out


def publish(bus: MemoryBus, x: float = 1.0) -> None:
    batch = SampleBatch(7, "rig", "telemetry", [T0], [{"x": x, "y": 2.0}], received_ns=T0)
    bus.publish_now(samples_subject(7, "telemetry"), batch)


async def op(session: LiveSession, **message: Any) -> None:
    await session.handle(orjson.dumps(message).decode())


async def test_subscribe_answers_with_latest_then_streams_the_filtered_samples() -> None:
    session, bus, hub, auth, _ = make()
    await op(session, op="subscribe", id="a", twin="rig", signals=["x"], max_rate=10)
    publish(bus)
    subscribed, samples = sent(session)
    assert subscribed == {
        "type": "subscribed",
        "id": "a",
        "twin": "rig",
        "stream": "telemetry",
        "signals": ["x"],
        "max_rate": 10.0,
        "latest": {"x": {"time": T0, "value": 1.0}},
    }
    assert samples["sub"] == "a" and samples["samples"] == [{"time": T0, "values": {"x": 1.0}}]
    assert hub.watchers(7, "telemetry") == 1 and auth.calls == 1


async def test_unsubscribe_stops_delivery_and_leaves_the_hub() -> None:
    session, bus, hub, _, _ = make()
    await op(session, op="subscribe", id="a", twin="rig")
    publish(bus)  # queued, then discarded by the unsubscribe
    await op(session, op="unsubscribe", id="a")
    publish(bus)
    assert [m["type"] for m in sent(session)] == ["subscribed", "unsubscribed"]
    assert hub.streams == 0
    await op(session, op="unsubscribe", id="a")
    assert sent(session)[0]["message"] == "no subscription 'a'"


@pytest.mark.parametrize(
    ("raw", "expected"),
    [
        ("{not json", "the message is not JSON"),
        ("[1, 2]", 'a message is a JSON object with an "op"'),
        (
            '{"op": "dance"}',
            "unknown op 'dance'; expected one of subscribe, unsubscribe, command, ping",
        ),
        ('{"op": "subscribe", "twin": "rig"}', '"id" must be a string of 1 to 64 characters'),
        ('{"op": "subscribe", "id": "a"}', '"twin" must be the slug of a twin'),
        ('{"op": "subscribe", "id": "a", "twin": "rig", "stream": "Bad!"}', '"stream" must'),
        ('{"op": "subscribe", "id": "a", "twin": "rig", "signals": []}', '"signals" must'),
        ('{"op": "subscribe", "id": "a", "twin": "rig", "signals": [3]}', "signal name 3"),
        ('{"op": "subscribe", "id": "a", "twin": "rig", "max_rate": 0}', '"max_rate" must'),
        ('{"op": "subscribe", "id": "a", "twin": "rig", "max_rate": true}', '"max_rate" must'),
        ('{"op": "subscribe", "id": "a", "twin": "ghost"}', "no twin 'ghost'"),
        ('{"op": "auth", "token": "tl_good"}', "already authenticated"),
        (
            '{"op": "subscribe", "id": "a", "twin": "rig", "max_rate": 1e400}',
            "the message is not JSON: a number is out of range",
        ),
        ('{"op": "ping", "id": NaN}', "the message is not JSON: JSON is malformed"),
        (f'{{"op": "ping", "id": {2**64}}}', f"id: {int64_problem(2**64)}"),
        (
            f'{{"op": "subscribe", "id": "a", "twin": "rig", "max_rate": {10**400}}}',
            f"max_rate: {int64_problem(10**400)}",
        ),
        ("x" * (protocol.MAX_CLIENT_MESSAGE + 1), "a message holds at most"),
        ("é" * 40_000, "a message holds at most"),  # 40 000 characters, 80 000 bytes
    ],
)
async def test_bad_messages_are_answered_with_an_error(raw: str, expected: str) -> None:
    session, _, hub, _, _ = make()
    await session.handle(raw)
    [answer] = sent(session)
    assert answer["type"] == "error" and answer["message"].startswith(expected), answer
    assert hub.streams == 0 and not session.subs


async def test_an_id_in_use_and_the_subscription_limit_are_refused() -> None:
    session, _, _, _, _ = make()
    for i in range(protocol.MAX_SUBSCRIPTIONS):
        await op(session, op="subscribe", id=f"s{i}", twin="rig")
    await op(session, op="subscribe", id="s0", twin="rig")
    await op(session, op="subscribe", id="one-more", twin="rig")
    *_, in_use, full = sent(session)
    assert (in_use["id"], in_use["message"]) == (
        "s0",
        "subscription 's0' exists; unsubscribe it first",
    )
    assert full["message"] == "a connection holds at most 100 subscriptions"


async def test_ping_is_answered_with_the_server_time() -> None:
    session, _, _, _, _ = make()
    await op(session, op="ping", id=3)
    [pong] = sent(session)
    assert pong["type"] == "pong" and pong["id"] == 3 and pong["server_time"] > T0


async def test_a_revoked_token_is_noticed_on_subscribe() -> None:
    session, _, hub, auth, _ = make()
    auth.valid = False
    with pytest.raises(AuthError):
        await op(session, op="subscribe", id="a", twin="rig")
    assert hub.streams == 0


async def test_recheck_ends_subscriptions_to_twins_no_longer_visible() -> None:
    session, _, hub, auth, registry = make()
    await op(session, op="subscribe", id="a", twin="rig")
    sent(session)
    await session.recheck()
    assert sent(session) == [] and hub.streams == 1
    del registry.visible["rig"]
    await session.recheck()
    assert sent(session) == [{"type": "unsubscribed", "id": "a", "reason": "no twin 'rig'"}]
    assert hub.streams == 0 and not session.subs
    auth.valid = False
    with pytest.raises(AuthError):
        await session.recheck()


async def test_a_failing_latest_read_still_subscribes_with_no_latest_values() -> None:
    async def broken(*_: Any) -> dict[str, Any]:
        raise RuntimeError("history is down")

    session, bus, _, _, _ = make(broken)
    await op(session, op="subscribe", id="a", twin="rig")
    publish(bus)
    subscribed, samples = sent(session)
    assert subscribed["latest"] == {} and samples["type"] == "samples"


async def test_close_leaves_the_hub() -> None:
    session, _, hub, _, _ = make()
    await op(session, op="subscribe", id="a", twin="rig")
    await op(session, op="subscribe", id="b", twin="rig", stream="events")
    session.close()
    assert hub.streams == 0 and not session.subs
