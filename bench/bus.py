"""The Kafka bus between two nodes: sample batches published on one KafkaBus and received by
another's subscriber, on a real single-node Kafka broker (the tests' KRaft JVM, see
tests/integration/_kafka.py) on this machine; the in-process MemoryBus in the same run as the
reference. Both buses run in this one process (as two nodes would, each with its own
producer and reader), so the broker, the two nodes and the publishers share the machine.

    .venv/bin/python bench/bus.py            # 4 cases x 2 buses, 5 s each, about 1 minute
    .venv/bin/python bench/bus.py --quick    # 2 s each

A case is publishers (each awaiting its publish before the next, as a device session does)
x samples per batch (4 signals each). Figures: batches/s and samples/s from the first publish
until the other node's subscriber has every batch (end to end), and the published rate; then
the delay of each batch from its publish to the other node at 1 000 samples/s.
"""

from __future__ import annotations

import argparse
import asyncio
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
from tests.integration._kafka import kafka_libs, start_kafka, stop_kafka  # noqa: E402

from twinlink.bus import Bus, MemoryBus  # noqa: E402
from twinlink.bus.kafka import KafkaBus  # noqa: E402
from twinlink.domain.samples import SampleBatch, Value  # noqa: E402


@dataclass(frozen=True)
class Case:
    publishers: int
    samples: int  # per batch


CASES = [Case(1, 100), Case(16, 100), Case(8, 1000)]


def make_batch(twin_id: int, samples: int, seq: int) -> SampleBatch:
    t0 = time.time_ns()
    values: list[dict[str, Value]] = [
        {"angle": 0.001 * i, "force": 12.5 + i, "count": i, "ok": True} for i in range(samples)
    ]
    times = [t0 + i * 1000 for i in range(samples)]
    return SampleBatch(twin_id, f"twin-{twin_id}", "telemetry", times, values, t0, "bench", seq)


async def run_case(sender: Bus, receiver: Bus, case: Case, seconds: float) -> dict[str, float]:
    received = 0
    done = asyncio.Event()
    sent_total: int | None = None

    def on_batch(subject: str, message: object) -> None:
        nonlocal received
        received += 1
        if sent_total is not None and received >= sent_total:
            done.set()

    stop = receiver.subscribe("samples.*", on_batch)
    batches = [make_batch(p + 1, case.samples, 0) for p in range(case.publishers)]
    start = time.perf_counter()
    deadline = start + seconds

    async def publisher(p: int) -> int:
        n = 0
        subject = f"samples.{p + 1}.telemetry"
        while time.perf_counter() < deadline:
            await sender.publish(subject, batches[p])
            n += 1
        return n

    counts = await asyncio.gather(*(publisher(p) for p in range(case.publishers)))
    published_s = time.perf_counter() - start
    sent_total = sum(counts)
    if received < sent_total:
        await asyncio.wait_for(done.wait(), timeout=120)
    total_s = time.perf_counter() - start
    stop()
    return {
        "batches": sent_total,
        "published_batches_per_s": sent_total / published_s,
        "end_to_end_batches_per_s": sent_total / total_s,
        "end_to_end_samples_per_s": sent_total * case.samples / total_s,
    }


async def run_latency(sender: Bus, receiver: Bus, seconds: float) -> dict[str, float]:
    """100 batches/s of 10 samples (1 000 samples/s, the issue's live delay case): the delay
    from the publish call to the other node's subscriber, per batch."""
    delays: list[int] = []

    def on_batch(subject: str, message: object) -> None:
        if isinstance(message, SampleBatch):
            delays.append(time.monotonic_ns() - message.received_ns)

    stop = receiver.subscribe("samples.*", on_batch)
    template = make_batch(1, 10, 0)
    count = int(seconds * 100)
    start = time.monotonic()
    for i in range(count):
        await asyncio.sleep(max(0.0, start + i / 100 - time.monotonic()))
        template.received_ns = time.monotonic_ns()
        await sender.publish("samples.1.telemetry", template)
    while len(delays) < count:
        await asyncio.sleep(0.01)
    stop()
    ordered = sorted(delays)
    return {
        "p50_ms": ordered[len(ordered) // 2] / 1e6,
        "p99_ms": ordered[min(len(ordered) - 1, int(len(ordered) * 0.99))] / 1e6,
        "max_ms": ordered[-1] / 1e6,
    }


async def measure(buses: list[tuple[str, Bus, Bus]], seconds: float) -> None:
    print(f"{'bus':8} {'publishers':>10} {'samples':>8} {'batches/s':>10} "
          f"{'samples/s':>11} {'published/s':>12}")  # fmt: skip
    for case in CASES:
        for name, sender, receiver in buses:
            r = await run_case(sender, receiver, case, seconds)
            print(
                f"{name:8} {case.publishers:>10} {case.samples:>8} "
                f"{r['end_to_end_batches_per_s']:>10,.0f} "
                f"{r['end_to_end_samples_per_s']:>11,.0f} "
                f"{r['published_batches_per_s']:>12,.0f}"
            )
    print("delay of a batch at 1 000 samples/s (100 batches/s of 10):")
    for name, sender, receiver in buses:
        r = await run_latency(sender, receiver, seconds)
        print(
            f"{name:8} p50 {r['p50_ms']:.2f} ms, p99 {r['p99_ms']:.2f} ms, max {r['max_ms']:.2f} ms"
        )


async def main(seconds: float) -> None:
    memory = MemoryBus()
    with tempfile.TemporaryDirectory() as folder:
        broker = start_kafka(Path(folder), kafka_libs())
        try:
            node_a = KafkaBus(broker.bootstrap, topic_prefix="bench", client_id="node-a")
            node_b = KafkaBus(broker.bootstrap, topic_prefix="bench", client_id="node-b")
            await node_a.start()
            await node_b.start()
            try:
                await measure([("memory", memory, memory), ("kafka", node_a, node_b)], seconds)
            finally:
                await node_b.stop()
                await node_a.stop()
        finally:
            stop_kafka(broker)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="2 s per case instead of 5")
    args = parser.parse_args()
    asyncio.run(main(2.0 if args.quick else 5.0))
