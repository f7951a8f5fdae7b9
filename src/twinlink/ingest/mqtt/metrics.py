"""MQTT figures on /metrics, read at scrape time from the status (nothing on the hot path)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from prometheus_client.core import CounterMetricFamily, GaugeMetricFamily
from prometheus_client.metrics_core import Metric

if TYPE_CHECKING:
    from twinlink.ingest.mqtt.service import MqttService


class MqttCollector:
    def __init__(self, service: MqttService) -> None:
        self.service = service

    def describe(self) -> list[Metric]:
        return []

    def collect(self) -> Iterator[Metric]:
        view = self.service.view()
        if view["mode"] == "off":
            return
        clients = GaugeMetricFamily("twinlink_mqtt_clients", "Devices connected over MQTT")
        clients.add_metric([], view["clients"])
        yield clients
        for key, help_text in (
            ("connects", "MQTT connections accepted"),
            ("samples", "Samples taken in over MQTT"),
            ("sent", "Messages published to devices"),
        ):
            family = CounterMetricFamily(f"twinlink_mqtt_{key}", help_text)
            family.add_metric([], view[key])
            yield family
        for key, label, help_text in (
            ("received", "kind", "Messages from devices by kind"),
            ("refused", "reason", "Connections refused by reason"),
            ("errors", "error", "Errors by kind"),
        ):
            family = CounterMetricFamily(f"twinlink_mqtt_{key}", help_text, labels=[label])
            for name, count in view[key].items():
                family.add_metric([name], count)
            yield family
