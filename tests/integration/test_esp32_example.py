"""The ESP32 example (examples/esp32-mqtt/): its C++ host tests pass under AddressSanitizer
and UndefinedBehaviorSanitizer, and the messages its C++ code builds and reads are the ones
the platform's own MQTT code (topics.py, payloads.py, the sample and property checks) takes
and sends, so the example cannot drift from the scheme.

`make build` in the example builds the test programs once per session into a temporary folder;
`wire_check` prints what the C++ code formats and parses what it is given.
"""

from __future__ import annotations

import random
import re
import secrets
import shutil
import subprocess
import time
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import orjson
import pytest
import yaml

from twinlink.commands.rules import check_reported, rules_from_interface
from twinlink.domain.samples import OPEN_SCHEMA, read_batch, schema_from_interface
from twinlink.domain.slug import SLUG
from twinlink.ingest.mqtt.bridge import DeviceBridge, Receipt
from twinlink.ingest.mqtt.payloads import (
    read_object,
    read_telemetry,
    reported_message,
    result_message,
)
from twinlink.ingest.mqtt.status import MqttStatus
from twinlink.ingest.mqtt.topics import (
    COMMAND_ID,
    DELIVERED,
    REPORTED,
    RESULT,
    STATUS,
    STREAM,
    TELEMETRY,
    DeviceTopics,
    TopicScheme,
    valid_filter,
)
from twinlink.registry.devices import DEVICE_NAME

pytestmark = pytest.mark.integration

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "esp32-mqtt"
TWIN, DEVICE = "tingen", "esp32"
COMMAND = "pX3k9Qw2ZbT7cV1a"  # the id wire_check answers
ANGLE, FORCE = "Cantilever_Angle_radians", "Input_F_in"


@dataclass(frozen=True)
class Built:
    tests: Path
    wire_check: Path

    def run(self, *args: str, stdin: str = "") -> list[str]:
        done = subprocess.run(
            [str(self.wire_check), *args], input=stdin, capture_output=True, text=True,
            timeout=60, check=False,
        )  # fmt: skip
        assert done.returncode == 0, done.stderr
        return done.stdout.splitlines()


@pytest.fixture(scope="session")
def built(tmp_path_factory: pytest.TempPathFactory) -> Built:
    for tool in ("make", "g++"):  # `make setup` installs gcc; g++ is the Debian package g++
        assert shutil.which(tool), f"the ESP32 example's host build needs {tool}"
    build = tmp_path_factory.mktemp("esp32-mqtt")
    done = subprocess.run(
        ["make", "-C", str(EXAMPLE), f"BUILD={build}", "build"],
        capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    return Built(build / "test_twinlink_mqtt", build / "wire_check")


@pytest.fixture(scope="module")
def tingen_interface() -> dict[str, Any]:
    document = yaml.safe_load((ROOT / "examples" / "tingen" / "tingen.yaml").read_text())
    interface: dict[str, Any] = document["interface"]
    return interface


def test_the_host_tests_pass(built: Built) -> None:
    done = subprocess.run(
        [str(built.tests)], capture_output=True, text=True, timeout=120, check=False
    )
    assert done.returncode == 0, done.stderr
    assert "checks passed" in done.stdout


# -- what the board sends -------------------------------------------------------------------


def emitted(built: Built, prefix: str) -> dict[str, list[tuple[str, bytes]]]:
    messages: dict[str, list[tuple[str, bytes]]] = {}
    for line in built.run("emit", prefix, TWIN, DEVICE):
        kind, topic, payload = line.split("\t")
        messages.setdefault(kind, []).append((topic, payload.encode()))
    return messages


def samples(payload: bytes, topic_stream: str | None, schema: Any) -> Any:
    """The samples as the platform stores them: read from MQTT, then checked one by one."""
    batch = read_telemetry(payload, topic_stream)
    read = read_batch(batch.message(1), schema, time.time_ns())
    assert read.rejected == []
    return read


@pytest.mark.parametrize("prefix", ["twinlink", "plant/hall-2"])
def test_the_platform_reads_what_the_board_sends(
    built: Built, prefix: str, tingen_interface: dict[str, Any]
) -> None:
    scheme = TopicScheme(prefix)
    messages = emitted(built, prefix)
    assert set(messages) == {
        "telemetry", "telemetry-mixed", "telemetry-batch", "telemetry-untimed",
        "telemetry-stream", "delivered", "succeeded", "succeeded-empty", "failed", "reported",
        "status", "subscribe",
    }  # fmt: skip

    def one(kind: str, route_kind: str, detail: str | None = None) -> bytes:
        [(topic, payload)] = messages[kind]
        route = scheme.route(topic)
        assert (route.twin, route.device, route.kind, route.detail) == (
            TWIN, DEVICE, route_kind, detail
        )  # fmt: skip
        return payload

    tingen = schema_from_interface(tingen_interface)
    read = samples(one("telemetry", TELEMETRY), None, tingen)
    assert (read.values, read.server_timed) == ([{ANGLE: 0.123, FORCE: 1.1931}], 1)
    read = samples(one("telemetry-batch", TELEMETRY), None, tingen)
    assert read.times == [(1732200000123 + 10 * i) * 1_000_000 for i in range(3)]
    assert read.values == [{ANGLE: 0.0, FORCE: 0.0}, {ANGLE: 0.1, FORCE: 0.97},
                           {ANGLE: 0.2, FORCE: 1.94}]  # fmt: skip
    read = samples(one("telemetry-untimed", TELEMETRY), None, tingen)
    assert (read.values, read.server_timed) == ([{ANGLE: 0.123, FORCE: 1.1931}], 1)
    read = samples(one("telemetry-mixed", TELEMETRY), None, OPEN_SCHEMA)
    assert read.values == [{"flag": True, "label": 'say "hi" ä\n', "tiny": 1e-300}]
    batch = read_telemetry(one("telemetry-stream", TELEMETRY, "esp32"), "esp32")
    assert batch.message(1)["stream"] == "esp32"

    assert read_object(one("delivered", DELIVERED, COMMAND), "delivered") == {}
    assert result_message(COMMAND, one("succeeded", RESULT, COMMAND)) == {
        "type": "result", "id": COMMAND, "status": "succeeded", "result": {"sample_rate": 50},
    }  # fmt: skip
    assert result_message(COMMAND, one("succeeded-empty", RESULT, COMMAND)) == {
        "type": "result", "id": COMMAND, "status": "succeeded",
    }  # fmt: skip
    assert result_message(COMMAND, one("failed", RESULT, COMMAND)) == {
        "type": "result", "id": COMMAND, "status": "failed",
        "error": 'value "500" is not 1..100\n',
    }  # fmt: skip
    reported = reported_message(one("reported", REPORTED), 1)
    assert reported["properties"] == {"sample_rate": 20, "paused": False, "device_id": DEVICE}
    check_reported(rules_from_interface(tingen_interface), reported["properties"])
    assert one("status", STATUS) == b"online"

    topics = DeviceTopics(scheme, TWIN, DEVICE)
    filters = [topic for topic, _ in messages["subscribe"]]
    assert filters == [f"{topics.base}/commands/+", topics.desired, topics.errors, topics.acks]
    assert all(valid_filter(f) and topics.reachable(f) for f in filters)


# -- what the board receives ----------------------------------------------------------------


class Recorder:
    """The `Outlet` of a device that has subscribed to everything: keeps what is published."""

    def __init__(self) -> None:
        self.published: list[tuple[str, bytes]] = []

    def deliverable(self, topic: str) -> bool:
        return True

    def publish(self, topic: str, payload: bytes, qos: int, retain: bool = False) -> None:
        self.published.append((topic, payload))

    def acknowledge(self, receipts: Iterable[Receipt], reason: int) -> None:
        pass

    async def drain(self) -> None:
        pass

    def fail(self, text: str) -> None:
        pass

    def session_closed(self, code: int, reason: str) -> None:
        pass


async def sent_by_the_platform(messages: list[dict[str, Any]]) -> list[tuple[str, bytes]]:
    """What the platform's MQTT bridge publishes for these protocol messages to the device."""
    outlet = Recorder()
    topics = DeviceTopics(TopicScheme("twinlink"), TWIN, DEVICE)
    bridge = DeviceBridge(outlet, topics, MqttStatus("embedded"), retain_desired=False)
    for message in messages:
        await bridge.send_text(orjson.dumps(message).decode())
    return outlet.published


def parsed(built: Built, kind: str, published: list[tuple[str, bytes]]) -> list[dict[str, Any]]:
    stdin = "".join(f"{kind}\t{topic}\t{payload.hex()}\n" for topic, payload in published)
    lines = built.run("parse", "twinlink", TWIN, DEVICE, stdin=stdin)
    return [orjson.loads(line) for line in lines]


def command(name: str, args: dict[str, Any]) -> dict[str, Any]:
    expires = time.time_ns() + 10**10
    return {"type": "command", "id": secrets.token_urlsafe(12), "name": name, "args": args,
            "expires": expires}  # fmt: skip


async def test_the_board_reads_the_platforms_commands(built: Built) -> None:
    commands = [
        command("set_sample_rate", {"value": 50}),
        command("set_sample_rate", {"value": 12.5}),
        command("set_sample_rate", {"value": -1e-3}),
        command("set_sample_rate", {"value": "fast"}),
        command("pause", {}),
        command("start", {"mode": {"value": 1, "list": [1, [2, {}]]}, "value": 7}),
        command('säätö "x"', {"value": True}),
    ]
    published = await sent_by_the_platform(commands)
    answers = parsed(built, "command", published)
    assert len(answers) == len(commands)
    for sent, answer in zip(commands, answers, strict=True):
        value = sent["args"].get("value")
        number = isinstance(value, int | float) and not isinstance(value, bool)
        expected = {"ok": True, "id": sent["id"], "name_hex": sent["name"].encode().hex()}
        assert answer == (expected | {"value": value} if number else expected)


async def test_the_board_reads_the_desired_properties(built: Built) -> None:
    published = await sent_by_the_platform([
        {"type": "welcome", "device": DEVICE, "twin": TWIN, "server_time": 1,
         "desired": {"filter_k": 0.85, "sample_rate": 20}, "desired_version": 3},
        {"type": "desired", "properties": {"sample_rate": 12.5}, "version": 4},
        {"type": "desired", "properties": {"filter_k": 0.5}, "version": 5},
    ])  # fmt: skip
    assert {topic for topic, _ in published} == {f"twinlink/{TWIN}/{DEVICE}/properties/desired"}
    answers = parsed(built, "desired", published)
    assert answers == [{"ok": True, "value": 20}, {"ok": True, "value": 12.5}, {"ok": False}]


def expected_reading(payload: bytes) -> dict[str, Any]:
    """What a correct reader of a command makes of a payload, by orjson (the platform's JSON)."""
    refused = {"ok": False, "id": COMMAND}
    try:
        body = orjson.loads(payload)
    except orjson.JSONDecodeError:
        return refused
    name = body.get("name") if isinstance(body, dict) else None
    if not isinstance(name, str) or not name or "\0" in name or len(name.encode()) > 63:
        return refused
    if body.get("id", COMMAND) != COMMAND:
        return refused
    args = body.get("args")
    value = args.get("value") if isinstance(args, dict) else None
    reading = {"ok": True, "id": COMMAND, "name_hex": name.encode().hex()}
    if isinstance(value, int | float) and not isinstance(value, bool):
        reading["value"] = value
    return reading


def mangled(seed: int, count: int) -> list[bytes]:
    """Commands with a few random edits: mostly broken JSON, some still valid."""
    rng = random.Random(seed)
    base = orjson.dumps({"id": COMMAND, "name": "set_sample_rate", "args": {"value": 50},
                         "expires": 1732200010123000000})  # fmt: skip
    alphabet = b'{}[]":,\\/ \t\nu0123456789abdefEnlrstx+-.\x01\x7f\xc3\xa4\xed\xa0\xff'
    out = []
    for _ in range(count):
        data = bytearray(base)
        for _ in range(rng.randint(1, 4)):
            at, byte = rng.randrange(len(data)), rng.choice(alphabet)
            match rng.randrange(3):
                case 0:
                    data[at] = byte
                case 1:
                    data.insert(at, byte)
                case _:
                    del data[at]
        out.append(bytes(data))
    return out


def test_the_board_reads_json_as_the_platform_does(built: Built) -> None:
    """The C++ reader accepts exactly what orjson accepts, and reads the same name and value."""
    payloads = mangled(seed=7, count=3000)
    topic = f"twinlink/{TWIN}/{DEVICE}/commands/{COMMAND}"
    answers = parsed(built, "command", [(topic, p) for p in payloads])
    differ = [
        (payload, answer)
        for payload, answer in zip(payloads, answers, strict=True)
        if {k: v for k, v in answer.items() if k != "error"} != expected_reading(payload)
    ]
    assert differ == []
    assert 0 < sum(answer["ok"] for answer in answers) < len(answers)


def test_names_are_checked_as_the_platform_checks_them(built: Built) -> None:
    names = ["tingen", "pump-7", "a", "-a", "a-", "A", "a_b", "a.b", "a:b", "_a", "0", "", "é",
             "a/b", "a+b", "a#", "x" * 63, "x" * 64, "x" * 65, "pX3k9Qw2ZbT7cV1a", "a b",
             "tingenSAP", "esp32.rig:1", "Z-_9", "a\tb", "a--b", "9-9"]  # fmt: skip
    rules = {"twin": SLUG, "device": DEVICE_NAME, "command_id": COMMAND_ID, "stream": STREAM}
    cases = [(kind, name) for kind in rules for name in names]
    stdin = "".join(f"{kind}\t{name.encode().hex()}\n" for kind, name in cases)
    answers = built.run("names", stdin=stdin)
    expected = ["1" if re.fullmatch(rules[kind], name) else "0" for kind, name in cases]
    assert list(zip(cases, answers, strict=True)) == list(zip(cases, expected, strict=True))
