"""Where a subject goes in Kafka: its topic, and the key that picks the partition.

Each family of subjects has its topic (`{prefix}.samples`, `.commands`, `.command-results`,
`.properties`, `.processor-events`); any other subject goes to `{prefix}.other`, so every
subject that works on the memory bus works here too. The key is the subject's second part,
the twin (`samples.7.telemetry` -> `7`): Kafka keeps the order of records within a partition
and a key always maps to the same partition, so each twin's batches, of all its streams, arrive
in the order they were published.
"""

from __future__ import annotations

FAMILIES = {
    "samples": "samples",
    "commands": "commands",
    "command-results": "command-results",
    "properties": "properties",
    "processors": "processor-events",
}
OTHER = "other"


def topic_names(prefix: str) -> list[str]:
    """Every topic of the bus: each node reads them all."""
    return [f"{prefix}.{name}" for name in (*FAMILIES.values(), OTHER)]


def topic_of(subject: str, prefix: str) -> str:
    family = subject.split(".", 1)[0]
    return f"{prefix}.{FAMILIES.get(family, OTHER)}"


def key_of(subject: str) -> bytes | None:
    """The twin part of the subject; None (any partition) for a subject without one."""
    parts = subject.split(".", 2)
    return parts[1].encode() if len(parts) > 1 and parts[1] else None
