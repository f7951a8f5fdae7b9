"""The bus over Apache Kafka, for several nodes (docs/scale-out.md). Only this package imports
the Kafka client (aiokafka); the rest of twinlink sees the `Bus` protocol."""

from twinlink.bus.kafka.bus import KafkaBus, KafkaBusError
from twinlink.bus.kafka.codec import UnencodableMessageError

__all__ = ["KafkaBus", "KafkaBusError", "UnencodableMessageError"]
