"""Per-connector figures on /metrics, read at scrape time (nothing on the hot path)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from prometheus_client.core import CounterMetricFamily, GaugeMetricFamily
from prometheus_client.metrics_core import Metric

if TYPE_CHECKING:
    from twinlink.connectors.service import ConnectorService

LABELS = ["twin", "connector", "kind"]
# Every state a connector reports, so each one's gauge is 0 or 1 and a query can alert on
# `twinlink_connector_state{state="error"} == 1`.
STATES = ("starting", "listening", "connected", "reconnecting", "error")


class ConnectorCollector:
    def __init__(self, service: ConnectorService) -> None:
        self.service = service

    def describe(self) -> list[Metric]:
        return []

    def collect(self) -> Iterator[Metric]:
        counters = {
            "messages": CounterMetricFamily(
                "twinlink_connector_messages",
                "Datagrams or notifications taken in",
                labels=LABELS,
            ),
            "samples": CounterMetricFamily(
                "twinlink_connector_samples", "Samples handed to the platform", labels=LABELS
            ),
            "rejected": CounterMetricFamily(
                "twinlink_connector_samples_rejected",
                "Samples the twin's interface refused",
                labels=LABELS,
            ),
            "commands": CounterMetricFamily(
                "twinlink_connector_commands", "Commands sent to the connector", labels=LABELS
            ),
        }
        errors = CounterMetricFamily(
            "twinlink_connector_errors", "Errors by kind", labels=[*LABELS, "error"]
        )
        state = GaugeMetricFamily(
            "twinlink_connector_state", "1 for the connector's state", labels=[*LABELS, "state"]
        )
        for connector in list(self.service.running.values()):
            device = connector.host.device
            labels = [device.twin_slug, connector.name, connector.kind]
            status = connector.status
            for key, family in counters.items():
                family.add_metric(labels, getattr(status, key))
            for kind, count in status.errors.items():
                errors.add_metric([*labels, kind], count)
            for name in STATES:
                state.add_metric([*labels, name], 1.0 if status.state == name else 0.0)
        yield from counters.values()
        yield errors
        yield state
