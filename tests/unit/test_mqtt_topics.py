"""The topic scheme: which topics a device may publish to, what each means, and which
subscription filters reach what the platform sends a device."""

from __future__ import annotations

import pytest

from twinlink.ingest.mqtt.topics import (
    DeviceTopics,
    Route,
    TopicError,
    TopicScheme,
    matches,
    valid_filter,
)

SCHEME = TopicScheme("twinlink")


@pytest.mark.parametrize(
    ("topic", "route"),
    [
        ("twinlink/tingen/rig/telemetry", Route("tingen", "rig", "telemetry")),
        ("twinlink/tingen/rig/telemetry/fast", Route("tingen", "rig", "telemetry", "fast")),
        ("twinlink/tingen/rig/commands/pX3k9Q/result", Route("tingen", "rig", "result", "pX3k9Q")),
        ("twinlink/tingen/rig/commands/pX3k9Q/delivered",
         Route("tingen", "rig", "delivered", "pX3k9Q")),
        ("twinlink/tingen/rig/properties/reported", Route("tingen", "rig", "reported")),
        ("twinlink/tingen/rig/status", Route("tingen", "rig", "status")),
    ],
)  # fmt: skip
def test_routes(topic: str, route: Route) -> None:
    assert SCHEME.route(topic) == route


@pytest.mark.parametrize(
    ("topic", "why"),
    [
        ("other/tingen/rig/telemetry", "start with twinlink/"),
        ("twinlink/tingen/telemetry", "expected twinlink/{twin}/{device}/telemetry"),
        ("twinlink/Tingen/rig/telemetry", "not a twin slug"),
        ("twinlink/tingen/rig/telemetry/Fast", "stream name"),
        ("twinlink/tingen/rig/commands/x/done", "a device publishes to"),
        ("twinlink/tingen/rig/properties/desired", "a device publishes to"),
        ("twinlink/tingen/rig/commands/a b/result", "not a command id"),
    ],
)
def test_topics_outside_the_scheme(topic: str, why: str) -> None:
    with pytest.raises(TopicError, match=why):
        SCHEME.route(topic)


def test_a_prefix_of_several_levels() -> None:
    scheme = TopicScheme("/plant/a/")
    assert scheme.route("plant/a/tingen/rig/telemetry").twin == "tingen"
    assert scheme.subscriptions()[0] == "plant/a/+/+/telemetry"


@pytest.mark.parametrize(
    ("topic_filter", "ok"),
    [("a/+/b", True), ("a/#", True), ("#", True), ("a/b#", False), ("a/#/b", False),
     ("a+/b", False), ("", False)],
)  # fmt: skip
def test_valid_filters(topic_filter: str, ok: bool) -> None:
    assert valid_filter(topic_filter) is ok


@pytest.mark.parametrize(
    ("topic_filter", "topic", "hit"),
    [("a/+/c", "a/b/c", True), ("a/#", "a", True), ("a/#", "a/b/c", True),
     ("a/+", "a/b/c", False), ("a/b", "a/b/c", False), ("+/+", "a/b", True)],
)  # fmt: skip
def test_matching(topic_filter: str, topic: str, hit: bool) -> None:
    assert matches(topic_filter.split("/"), topic.split("/")) is hit


@pytest.mark.parametrize(
    ("topic_filter", "reachable"),
    [
        ("twinlink/tingen/rig/commands/+", True),
        ("twinlink/tingen/rig/commands/abc", True),
        ("twinlink/tingen/rig/#", True),
        ("twinlink/+/rig/properties/desired", True),
        ("#", True),
        ("twinlink/tingen/rig/acks", True),
        ("twinlink/tingen/gir/commands/+", False),
        ("twinlink/tingen/rig/telemetry", False),
        ("twinlink/tingen/rig/commands/+/result", False),
    ],
)
def test_reachable_filters(topic_filter: str, reachable: bool) -> None:
    assert DeviceTopics(SCHEME, "tingen", "rig").reachable(topic_filter) is reachable
