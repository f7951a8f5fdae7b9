"""Prometheus metrics: HTTP requests by route template, and platform gauges."""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from typing import Any

from prometheus_client import CollectorRegistry, Counter, Gauge, Histogram
from prometheus_client.core import CounterMetricFamily, GaugeMetricFamily, Metric
from starlette.types import ASGIApp, Message, Receive, Scope, Send


class Metrics:
    def __init__(self) -> None:
        self.registry = CollectorRegistry(auto_describe=True)
        self.requests = Counter(
            "twinlink_http_requests",
            "HTTP requests handled",
            ["method", "route", "status"],
            registry=self.registry,
        )
        self.latency = Histogram(
            "twinlink_http_request_duration_seconds",
            "Time to answer an HTTP request",
            ["route"],
            registry=self.registry,
            buckets=(0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1, 2.5),
        )
        self.twins = Gauge("twinlink_twins", "Twins in the registry", registry=self.registry)
        self.users = Gauge("twinlink_users", "Users", registry=self.registry)


class MetricsMiddleware:
    """Counts and times every request, labelled by route template (never by raw path)."""

    def __init__(self, app: ASGIApp, metrics: Metrics) -> None:
        self.app = app
        self.metrics = metrics

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        start = time.perf_counter()
        status = 500

        async def _send(message: Message) -> None:
            nonlocal status
            if message["type"] == "http.response.start":
                status = message["status"]
            await send(message)

        try:
            await self.app(scope, receive, _send)
        finally:
            route = scope.get("route")
            template = getattr(route, "path", None) or "unmatched"
            self.metrics.requests.labels(scope["method"], template, str(status)).inc()
            self.metrics.latency.labels(template).observe(time.perf_counter() - start)


class DataPlaneCollector:
    """Reads the data plane's own counters at scrape time (no work on the hot path)."""

    def __init__(self, read: Callable[[], dict[str, Any]]) -> None:
        self.read = read

    def describe(self) -> list[Metric]:
        return []

    def collect(self) -> Iterator[Metric]:
        now = self.read()
        for name, help_text in (
            ("samples_accepted", "Samples stored from devices"),
            ("samples_rejected", "Samples rejected by the checks, with a reason to the device"),
            ("batches_duplicate", "Resent batches acknowledged without storing them again"),
            ("history_commits", "Group commits of the history store"),
            ("storage_full", "Writes refused because the disk is full (nothing of them stored)"),
            ("storage_io_errors", "Writes that failed with a disk I/O error (nothing stored)"),
            ("outputs_not_stored", "Processor output batches the store refused"),
        ):
            yield CounterMetricFamily(f"twinlink_{name}", help_text, value=now[name])
        yield GaugeMetricFamily(
            "twinlink_devices_connected",
            "Devices connected over the WebSocket",
            value=now["devices_connected"],
        )
