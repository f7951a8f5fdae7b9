"""Device properties: what the device reports, what people desire, and the delta sent to it.

The device learns the delta (desired values that differ from its reported ones) in its
`welcome`, in a `desired` message after every desired change, and in each `reported_ack`.
Every change is durable (in the `PropertyStore`; with SQLite, one group commit of history.db)
before it is acknowledged.

On a shared bus (several nodes, docs/scale-out.md), each node caches the properties of the
devices it served; after a change is stored, its node says so on `properties.{twin_id}`, and
the others drop that device's entry, so they read it again; the node holding the device's
session sends it the new delta when the desired values changed elsewhere. On one node (the
memory bus) nothing is published.
"""

from __future__ import annotations

import asyncio
import logging
import secrets
import time
from typing import Any

from twinlink.auth.rights import Principal, has_role
from twinlink.bus import Bus
from twinlink.commands.interfaces import InterfaceRules
from twinlink.commands.rules import check_desired, check_reported
from twinlink.domain.errors import ForbiddenError, NotFoundError, StorageError
from twinlink.domain.properties import DeviceProperties
from twinlink.domain.records import Device
from twinlink.ingest.sessions import DeviceHub, DeviceSession
from twinlink.registry.service import RegistryService
from twinlink.store.commands import PropertyStore

log = logging.getLogger("twinlink.commands")


class PropertyService:
    def __init__(
        self,
        registry: RegistryService,
        store: PropertyStore,
        hub: DeviceHub,
        shared_bus: Bus | None = None,
    ) -> None:
        """`shared_bus`: the bus other nodes share (Kafka), over which they hear of changes;
        None on one node (embedded)."""
        self.registry = registry
        self.store = store
        self.hub = hub
        self.rules = InterfaceRules(registry)
        self._cache: dict[int, DeviceProperties] = {}
        self._load_lock = asyncio.Lock()
        self._tasks: set[asyncio.Task[None]] = set()
        hub.handle("reported", self._on_reported)
        hub.welcome_extras.append(self._welcome)
        registry.deleted_listeners.append(self._twins_deleted)
        self.bus = shared_bus
        self.node = secrets.token_hex(8)  # tells this node's own messages from the others'
        if shared_bus is not None:
            shared_bus.subscribe("properties.*", self._heard)

    async def close(self) -> None:
        """Wait for the acks and deletions under way (before the store closes)."""
        if self._tasks:
            await asyncio.gather(*self._tasks, return_exceptions=True)

    # -- people ----------------------------------------------------------------------------

    async def show(self, principal: Principal, slug: str, device: str) -> DeviceProperties:
        return await self._state(await self._device(principal, slug, device, "viewer"))

    async def set_desired(
        self, principal: Principal, slug: str, device: str, changes: Any
    ) -> DeviceProperties:
        """Merge `changes` into the desired values (null removes one) and tell the device."""
        target = await self._device(principal, slug, device, "editor")
        checked = check_desired(await self.rules.get(target.twin_id), changes)
        props = await self._state(target)
        changed = props.set_desired(checked, time.time_ns())
        if changed:
            await self._save(props, changed, desired=True)
            session = self.hub.session(target.id)
            if session is not None:
                session.send({"type": "desired", "properties": props.delta(),
                              "version": props.version})  # fmt: skip
        return props

    async def _device(self, principal: Principal, slug: str, name: str, needed: str) -> Device:
        twin, role = await self.registry.require_twin(principal, slug)
        if not has_role(principal, role, needed):
            what = "changing" if needed == "editor" else "reading"
            raise ForbiddenError(f"{what} device properties of {slug!r} needs the {needed} role")
        found = await self.registry.store.get_device(twin.id, name)
        if found is None:
            raise NotFoundError(f"twin {slug!r} has no device {name!r}")
        return found

    # -- devices ---------------------------------------------------------------------------

    async def for_device(self, device: Device) -> DeviceProperties:
        return await self._state(device)

    async def report(self, device: Device, properties: Any) -> dict[str, Any]:
        """Store reported values (durably); the answer is the `reported_ack` body."""
        return await self._store_report(*await self._apply_report(device, properties))

    async def _apply_report(
        self, device: Device, properties: Any
    ) -> tuple[DeviceProperties, list[str]]:
        checked = check_reported(await self.rules.get(device.twin_id), properties)
        props = await self._state(device)
        return props, props.set_reported(checked, time.time_ns())

    async def _store_report(self, props: DeviceProperties, names: list[str]) -> dict[str, Any]:
        await self._save(props, names)
        return {"version": props.version, "desired": props.delta()}

    async def _on_reported(
        self, session: DeviceSession, message: dict[str, Any]
    ) -> dict[str, Any] | None:
        # Checked and applied here, in message order (a bad one is answered with an error);
        # the ack waits for the commit in a task, so reading the socket does not.
        props, names = await self._apply_report(session.device, message.get("properties"))
        ref = message.get("id")
        task = asyncio.create_task(self._ack(session, props, names, ref))
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)
        return None

    async def _ack(
        self, session: DeviceSession, props: DeviceProperties, names: list[str], ref: Any
    ) -> None:
        # `id` (when the device gave one) is echoed so it can match answers to reports.
        echo = {"id": ref} if isinstance(ref, str | int) and not isinstance(ref, bool) else {}
        try:
            body = await self._store_report(props, names)
        except Exception as err:
            text = "the reported values could not be stored; send them again"
            if isinstance(err, StorageError):  # counted and logged once a minute by the store
                text = str(err)
            else:
                log.exception("storing reported properties failed",
                              extra={"event": "reported_failed"})  # fmt: skip
            session.send(
                {"type": "error", "op": "reported", "fatal": False, "retry": True,
                 "message": text, **echo}
            )  # fmt: skip
            return
        session.send({"type": "reported_ack", **body, **echo})

    async def _welcome(self, device: Device) -> dict[str, Any]:
        props = await self._state(device)
        return {"desired": props.delta(), "desired_version": props.version}

    # -- state -----------------------------------------------------------------------------

    async def _state(self, device: Device) -> DeviceProperties:
        props = self._cache.get(device.id)
        if props is not None and props.device_created_ns == device.created_ns:
            return props
        async with self._load_lock:
            props = self._cache.get(device.id)
            if props is None or props.device_created_ns != device.created_ns:
                props = await self.store.load_properties(
                    device.id, device.twin_id, device.created_ns
                )
                self._cache[device.id] = props
        return props

    async def _save(self, props: DeviceProperties, names: list[str], desired: bool = False) -> None:
        try:
            await self.store.save_properties(props, names)
        except BaseException:
            self._cache.pop(props.device_id, None)  # memory ran ahead of the disk: reload
            raise
        if self.bus is not None and names:  # after the commit: what they read again is new
            self._spawn(self._tell(props, desired))

    # -- other nodes (a shared bus) --------------------------------------------------------

    async def _tell(self, props: DeviceProperties, desired: bool) -> None:
        message = {"node": self.node, "device": props.device_id, "desired": desired}
        assert self.bus is not None  # only called with a shared bus
        try:
            await self.bus.publish(f"properties.{props.twin_id}", message)
        except Exception as err:
            log.warning(
                "the other nodes were not told of a property change: they answer from their "
                "cache of the device's properties until their next change of it",
                extra={"event": "property_sync_failed", "error": str(err)},
            )

    def _heard(self, subject: str, message: object) -> None:
        if not isinstance(message, dict) or message.get("node") == self.node:
            return
        device_id = message.get("device")
        if not isinstance(device_id, int):
            return
        self._cache.pop(device_id, None)  # read again from the store at its next use
        session = self.hub.session(device_id)
        if session is not None and message.get("desired"):
            self._spawn(self._send_desired(session))

    async def _send_desired(self, session: DeviceSession) -> None:
        """The delta to a device on this node whose desired values changed on another."""
        props = await self._state(session.device)
        session.send({"type": "desired", "properties": props.delta(),
                      "version": props.version})  # fmt: skip

    def _spawn(self, work: Any) -> None:
        task: asyncio.Task[None] = asyncio.get_running_loop().create_task(work)
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    def _twins_deleted(self, twin_ids: list[int]) -> None:
        doomed = set(twin_ids)
        for device_id in [d for d, p in self._cache.items() if p.twin_id in doomed]:
            del self._cache[device_id]
        task = asyncio.create_task(self._forget(twin_ids))
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    async def _forget(self, twin_ids: list[int]) -> None:
        await self.store.delete_properties_of(twin_ids)
