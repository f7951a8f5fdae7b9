"""Per-processor figures on /metrics, read at scrape time (nothing on the hot path)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from prometheus_client.core import CounterMetricFamily, GaugeMetricFamily
from prometheus_client.metrics_core import Metric

if TYPE_CHECKING:
    from twinlink.processors.service import ProcessorService

LABELS = ["twin", "processor", "blueprint"]


class ProcessorCollector:
    def __init__(self, service: ProcessorService) -> None:
        self.service = service

    def describe(self) -> list[Metric]:
        return []

    def collect(self) -> Iterator[Metric]:
        counters = {
            "samples_in": CounterMetricFamily(
                "twinlink_processor_samples_in", "Input samples sent to the worker", labels=LABELS
            ),
            "samples_out": CounterMetricFamily(
                "twinlink_processor_samples_out", "Output samples made", labels=LABELS
            ),
            "dropped": CounterMetricFamily(
                "twinlink_processor_samples_dropped",
                "Input samples not processed (worker down or too far behind)",
                labels=LABELS,
            ),
            "restarts": CounterMetricFamily(
                "twinlink_processor_restarts", "Workers restarted after a crash", labels=LABELS
            ),
        }
        rss = GaugeMetricFamily("twinlink_processor_rss_bytes", "Worker RSS", labels=LABELS)
        up = GaugeMetricFamily("twinlink_processor_up", "1 when the worker runs", labels=LABELS)
        quantiles = {
            "step_s": GaugeMetricFamily(
                "twinlink_processor_step_seconds",
                "Blueprint time per input sample, recent percentiles",
                labels=[*LABELS, "quantile"],
            ),
            "latency_s": GaugeMetricFamily(
                "twinlink_processor_added_latency_seconds",
                "Input on the bus to output on the bus, recent percentiles",
                labels=[*LABELS, "quantile"],
            ),
        }
        for hosted in list(self.service.hosted.values()):
            record, sup = hosted.record, hosted.supervisor
            labels = [record.twin_slug, record.name, record.blueprint]
            stats = sup.stats
            for key, family in counters.items():
                family.add_metric(labels, getattr(stats, key))
            rss.add_metric(labels, stats.rss_bytes)
            up.add_metric(labels, 1.0 if sup.state == "running" else 0.0)
            for key, gauge in quantiles.items():
                recent = getattr(stats, key)
                for q, value in zip(("0.5", "0.99"), recent.percentiles(50, 99), strict=True):
                    if value is not None:
                        gauge.add_metric([*labels, q], value)
        yield from counters.values()
        yield rss
        yield up
        yield from quantiles.values()
