"""Where an export's links point (api/exports.export_context): the public URL, the live
WebSocket, and the MQTT broker devices publish to, as a client outside reaches them."""

from __future__ import annotations

from twinlink.api.exports import export_context
from twinlink.config import Settings


def test_the_public_url_names_every_endpoint() -> None:
    settings = Settings(public_url="https://twins.example/", mqtt_topic_prefix="plant/a")
    ctx = export_context(settings, 18830, "tingen")
    assert ctx.twin_url == "https://twins.example/twins/tingen"
    assert ctx.api_url == "https://twins.example/api/v1"
    assert ctx.ws_url == "wss://twins.example/api/v1/live"
    assert ctx.slug == "tingen"
    assert ctx.mqtt_topic_prefix == "plant/a"
    # the embedded listener on its own address and the port it got
    assert ctx.mqtt_url == "mqtt://127.0.0.1:18830"


def test_without_a_public_url_the_servers_own_address() -> None:
    ctx = export_context(Settings(host="127.0.0.1", port=8123), 1883, "rig")
    assert ctx.twin_url == "http://127.0.0.1:8123/twins/rig"
    assert ctx.ws_url == "ws://127.0.0.1:8123/api/v1/live"


def test_a_listener_on_every_address_is_named_by_the_public_urls_host() -> None:
    settings = Settings(public_url="http://plant.example:8000", mqtt_host="0.0.0.0")
    assert export_context(settings, 1883, "rig").mqtt_url == "mqtt://plant.example:1883"
    on_v6 = Settings(public_url="http://[2001:db8::1]:8000", mqtt_host="::")
    assert export_context(on_v6, 1883, "rig").mqtt_url == "mqtt://[2001:db8::1]:1883"


def test_no_mqtt_endpoint_when_off_or_not_listening() -> None:
    assert export_context(Settings(mqtt_mode="off"), 1883, "rig").mqtt_url is None
    assert export_context(Settings(mqtt_mode="embedded"), None, "rig").mqtt_url is None


def test_an_external_broker_is_where_devices_publish() -> None:
    settings = Settings(mqtt_mode="external", mqtt_broker_url="mqtts://broker.example")
    assert export_context(settings, None, "rig").mqtt_url == "mqtts://broker.example:8883"
    plain = Settings(mqtt_mode="external", mqtt_broker_url="mqtt://broker.example:1884")
    assert export_context(plain, None, "rig").mqtt_url == "mqtt://broker.example:1884"
