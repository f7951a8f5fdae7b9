"""Where an exported description points: the twin's URLs on this instance.

The exporters are pure conversions; the caller (api/exports.py, the CLI) knows the public
URL and which listeners run, and hands them over in one value so every format links to the
same real endpoints.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class ExportContext:
    """The endpoints of one twin, as a client outside this instance reaches them."""

    twin_url: str  # the twin's canonical URL: {public_url}/twins/{slug}
    api_url: str  # {public_url}/api/v1
    slug: str
    mqtt_url: str | None = None  # mqtt://host:port of the embedded listener, if enabled
    ws_url: str | None = None  # ws(s)://.../api/v1/live (browser live data)
    # The first level(s) of every MQTT topic (TWINLINK_MQTT_TOPIC_PREFIX): topics are
    # {prefix}/{slug}/{device}/... (docs/mqtt.md "Topics").
    mqtt_topic_prefix: str = "twinlink"
    # Whether mqtt_url is a broker of your own (TWINLINK_MQTT_MODE=external), which delivers
    # devices' telemetry to any client it lets subscribe. The embedded listener forwards
    # nothing between clients, so its topics are the devices' alone and a TD gives no MQTT
    # form for it (docs/formats.md "WoT Thing Description").
    mqtt_external: bool = False
