"""Per-service gateway figures on /metrics, read at scrape time (nothing on the hot path)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from prometheus_client.core import (
    CounterMetricFamily,
    GaugeMetricFamily,
    HistogramMetricFamily,
)
from prometheus_client.metrics_core import Metric

from twinlink.gateway.table import BUCKETS

if TYPE_CHECKING:
    from twinlink.gateway.service import GatewayService

LABELS = ["twin", "service"]


class GatewayCollector:
    def __init__(self, gateway: GatewayService) -> None:
        self.gateway = gateway

    def describe(self) -> list[Metric]:
        return []

    def collect(self) -> Iterator[Metric]:
        requests = CounterMetricFamily(
            "twinlink_gateway_requests",
            "Requests answered on a service path, by status",
            labels=[*LABELS, "status"],
        )
        failures = CounterMetricFamily(
            "twinlink_gateway_failures",
            "Requests the gateway answered itself after trying the service, by outcome",
            labels=[*LABELS, "outcome"],
        )
        traffic = CounterMetricFamily(
            "twinlink_gateway_bytes", "Body bytes forwarded", labels=[*LABELS, "direction"]
        )
        refreshes = CounterMetricFamily(
            "twinlink_gateway_credential_refreshes",
            "Tokens fetched for a service (sign-ins and renewals)",
            labels=LABELS,
        )
        upstream = HistogramMetricFamily(
            "twinlink_gateway_upstream_seconds",
            "From sending the request to the start of the service's answer",
            labels=LABELS,
        )
        up = GaugeMetricFamily(
            "twinlink_gateway_service_up", "1 when the last health check passed", labels=LABELS
        )
        builder = self.gateway.builder
        for (twin_id, name), stats in list(builder.stats.items()):
            labels = [builder.slugs.get(twin_id, str(twin_id)), name]
            for status, count in stats.requests.items():
                requests.add_metric([*labels, str(status)], count)
            for outcome, count in stats.failures.items():
                failures.add_metric([*labels, outcome], count)
            traffic.add_metric([*labels, "in"], stats.bytes_in)
            traffic.add_metric([*labels, "out"], stats.bytes_out)
            cumulative, buckets = 0, []
            for bound, count in zip((*BUCKETS, float("inf")), stats.upstream_counts, strict=True):
                cumulative += count
                buckets.append((str(bound) if bound != float("inf") else "+Inf", cumulative))
            upstream.add_metric(labels, buckets, stats.upstream_sum_s)
            if stats.health is not None:
                up.add_metric(labels, 1.0 if stats.health.get("status") == "up" else 0.0)
        for (twin_id, name), creds in list(builder.credentials_by_service().items()):
            labels = [builder.slugs.get(twin_id, str(twin_id)), name]
            refreshes.add_metric(labels, creds.refreshes)
        audit = self.gateway.audit
        dropped = CounterMetricFamily(
            "twinlink_gateway_audit_dropped", "Audit entries that could not be written"
        )
        dropped.add_metric([], audit.dropped)
        yield from (requests, failures, traffic, refreshes, upstream, up, dropped)
