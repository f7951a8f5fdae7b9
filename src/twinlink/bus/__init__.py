"""Publish/subscribe of sample batches and events between the parts of the platform."""

from twinlink.bus.base import Bus, Handler, Unsubscribe, samples_subject
from twinlink.bus.memory import MemoryBus

__all__ = ["Bus", "Handler", "MemoryBus", "Unsubscribe", "samples_subject"]
