"""The external broker's session on one node of several (docs/scale-out.md).

Every node connecting to the broker with the platform's client id would take the session from
the one before (MQTT allows one connection per client id), and nodes with client ids of their
own would each receive every device's message. So one node holds the session: the one that
holds the lease `mqtt-broker:0` (store/leases.py), renewed every few seconds. When that node
stops, another takes the lease over and connects with the same client id and its lasting
session (clean session 0), so the QoS 1 messages the broker kept meanwhile are delivered to
it: nothing a device sent is lost, only delayed by the takeover (within the lease's TTL). The
other nodes show the state `standby`; commands for the devices reach the holder through the
command relay, as for any device connected to another node."""

from __future__ import annotations

import asyncio
import contextlib
import logging

from twinlink.domain.errors import StorageError
from twinlink.ingest.mqtt.external import ExternalBroker
from twinlink.ingest.mqtt.status import MqttStatus
from twinlink.store.leases import Claims

log = logging.getLogger("twinlink.mqtt")

SESSION = 0  # the lease's id: there is one broker session


class LeasedBroker:
    """`ExternalBroker` opened only while this node holds the session's lease."""

    def __init__(self, broker: ExternalBroker, claims: Claims, status: MqttStatus) -> None:
        self.broker = broker
        self.claims = claims
        self.status = status
        self.holding = False
        self._keeper: asyncio.Task[None] | None = None

    async def open(self) -> None:
        self.status.address = str(self.broker.address)
        self.status.set_state("standby")
        await self._round()  # the first node up connects before it says it serves
        self._keeper = asyncio.create_task(self.claims.keep(self._round), name="mqtt-lease")

    async def close(self) -> None:
        if self._keeper is not None:
            self._keeper.cancel()
            await asyncio.gather(self._keeper, return_exceptions=True)
        if self.holding:
            await self.broker.close()
            self.holding = False
            try:  # stopped: another node may take the session over at once
                await self.claims.release_all()
            except StorageError as err:
                log.warning("mqtt broker lease not released (it expires): %s", err)
        self.status.set_state("stopped")

    async def _round(self) -> None:
        held = SESSION in await self.claims.hold([SESSION])
        if held and not self.holding:
            log.info("mqtt broker session taken", extra={"event": "mqtt_session_taken"})
            await self.broker.open()  # refused at the first round: the start fails, as alone
            self.holding = True
        elif not held and self.holding:
            log.warning("mqtt broker session given up (lease lost)",
                        extra={"event": "mqtt_session_lost"})  # fmt: skip
            self.holding = False
            with contextlib.suppress(Exception):
                await self.broker.close()
            self.status.set_state("standby")
