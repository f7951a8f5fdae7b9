"""MQTT device connectivity (docs/mqtt.md): an embedded listener or a client of an external
broker, one topic scheme, the device protocol's payloads."""

from twinlink.ingest.mqtt.client import BrokerError, BrokerRefused
from twinlink.ingest.mqtt.listener import ListenerError
from twinlink.ingest.mqtt.service import MqttService

__all__ = ["BrokerError", "BrokerRefused", "ListenerError", "MqttService"]
