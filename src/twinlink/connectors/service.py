"""Connectors of each twin: stored, started with the server, changed and stopped by API.

A connector speaks for one device of its twin (named in `device`, or a device of the
connector's own name, made when it is created). Creating and changing connectors is for
platform admins: a connector binds ports on the server's host or connects from it to other
hosts. Viewers of the twin see its connectors, their settings (never their secrets) and status.
"""

from __future__ import annotations

import asyncio
import logging
import time
from typing import Any

from twinlink.auth.last_used import LastUsed
from twinlink.auth.rights import Principal
from twinlink.auth.vault import Vault, VaultError
from twinlink.connectors.base import (
    Connector,
    ConnectorError,
    ConnectorStatus,
    ConnectorTransport,
    LinkHost,
)
from twinlink.connectors.kinds import (
    CONNECTOR_NAME,
    checked_config,
    connector_class,
    kinds_view,
    shown_config,
    split_config,
)
from twinlink.domain.errors import (
    ConflictError,
    ForbiddenError,
    InvalidInputError,
    NotFoundError,
    StorageError,
)
from twinlink.domain.records import ConnectorRecord, Device
from twinlink.ingest.link import DeviceLink
from twinlink.ingest.service import IngestService
from twinlink.ingest.sessions import DeviceHub
from twinlink.plugins import PluginUnavailable
from twinlink.registry.devices import DeviceService
from twinlink.registry.service import RegistryService
from twinlink.store.base import MetadataStore
from twinlink.store.leases import Claims

log = logging.getLogger("twinlink.connectors")

_CREATE_FIELDS = {"name", "kind", "device", "enabled", "config"}


class _SeenHost(LinkHost):
    """A connector's host that also notes when its device's session opens and ends. A device
    is seen when it authenticates; a connector speaks for its device without, which would
    leave the device "never seen" while connected and after."""

    def __init__(
        self, hub: DeviceHub, ingest: IngestService, device: Device, seen: LastUsed
    ) -> None:
        super().__init__(hub, ingest, device)
        self.seen = seen

    async def connect(self, transport: ConnectorTransport) -> DeviceLink:
        link = await super().connect(transport)
        self.seen.device_seen(self.device.id, time.time_ns())
        return link

    async def disconnect(self, link: DeviceLink) -> None:
        await super().disconnect(link)
        self.seen.device_seen(self.device.id, time.time_ns())


class ConnectorService:
    def __init__(
        self,
        store: MetadataStore,
        registry: RegistryService,
        devices: DeviceService,
        hub: DeviceHub,
        ingest: IngestService,
        vault: Vault,
        claims: Claims | None = None,
    ) -> None:
        self.store = store
        self.registry = registry
        self.devices = devices
        self.hub = hub
        self.ingest = ingest
        self.vault = vault
        self.running: dict[int, Connector] = {}
        # Why a connector that should run does not (it failed to start), by id.
        self.failed: dict[int, ConnectorStatus] = {}
        self._background: set[asyncio.Task[Any]] = set()
        # On a store shared by several nodes: the leases of the connectors this node runs
        # (None: the only node, which runs every enabled connector), and the version
        # (modified_ns) of each it started or tried to, to follow changes made elsewhere.
        self.claims = claims
        self._keeper: asyncio.Task[None] | None = None
        self._versions: dict[int, int] = {}
        # A lease round and a change made through the API take turns: a round that read the
        # connectors before a stop must not start again what the stop just ended.
        self._changing = asyncio.Lock()
        registry.deleted_listeners.append(self._twins_deleted)
        devices.deleted_listeners.append(self._device_deleted)

    # -- lifecycle ------------------------------------------------------------------------

    async def open(self) -> None:
        if self.claims is not None:  # one of several nodes: it runs those whose leases it takes
            await self._rebalance()
            self._keeper = asyncio.create_task(self.claims.keep(self._rebalance, self._changing))
            return
        for record in await self.store.list_connectors():
            if record.enabled:
                await self._start_quietly(record)

    async def close(self) -> None:
        if self._keeper is not None:
            self._keeper.cancel()
            await asyncio.gather(self._keeper, return_exceptions=True)
        await asyncio.gather(*(self._stop(cid) for cid in list(self.running)))
        if self._background:
            await asyncio.gather(*self._background, return_exceptions=True)
        if self.claims is not None:  # stopped: the other nodes may take them over at once
            try:
                await self.claims.release_all()
            except StorageError as err:
                log.warning("connector leases not released (they expire): %s", err)

    # -- people ---------------------------------------------------------------------------

    def kinds(self) -> list[dict[str, Any]]:
        return kinds_view()

    async def list_connectors(self, principal: Principal, slug: str) -> list[dict[str, Any]]:
        twin, _ = await self.registry.require_twin(principal, slug)
        return [self.view(r) for r in await self.store.list_connectors(twin.id)]

    async def get(self, principal: Principal, slug: str, name: str) -> dict[str, Any]:
        return self.view(await self._find(principal, slug, name))

    async def create(self, principal: Principal, slug: str, body: dict[str, Any]) -> dict[str, Any]:
        self._require_admin(principal)
        unknown = set(body) - _CREATE_FIELDS
        if unknown:
            raise InvalidInputError(f"unknown fields {sorted(unknown)}; a connector has "
                                    f"{sorted(_CREATE_FIELDS)}")  # fmt: skip
        name, kind = body.get("name"), body.get("kind")
        if not isinstance(name, str) or not CONNECTOR_NAME.match(name):
            raise InvalidInputError("`name`: 1-64 letters, digits, . _ : -, starting with one")
        if not isinstance(kind, str):
            raise InvalidInputError("`kind` is required (see GET /api/v1/connector-kinds)")
        enabled = body.get("enabled", True)
        if not isinstance(enabled, bool):
            raise InvalidInputError("`enabled` is true or false")
        public, secret = split_config(checked_config(kind, body.get("config", {})))
        twin, _ = await self.registry.require_twin(principal, slug)
        if any(r.name == name for r in await self.store.list_connectors(twin.id)):
            raise ConflictError(f"twin {slug!r} already has a connector {name!r}")
        device, made = await self._device_for(principal, slug, body.get("device"), name)
        async with self._changing:
            record = await self.store.create_connector(
                twin.id, device.id, name, kind, public, self._seal(secret), enabled,
                principal.user.id if principal.user else None, time.time_ns(),
            )  # fmt: skip
            if enabled and await self._may_run(record.id):
                try:
                    await self._start(record)
                except InvalidInputError:  # nothing is kept: the person fixes it and tries again
                    await self.store.delete_connector(record.id)
                    if made:
                        await self.devices.delete(principal, slug, device.name)
                    self.failed.pop(record.id, None)
                    raise
        return self.view(record)

    async def update(
        self, principal: Principal, slug: str, name: str, changes: dict[str, Any]
    ) -> dict[str, Any]:
        """Change `config` (the fields given; secrets left out are kept) and/or `enabled`;
        a running connector is restarted with the new settings."""
        self._require_admin(principal)
        record = await self._find(principal, slug, name)
        unknown = set(changes) - {"config", "enabled"}
        if unknown:
            raise InvalidInputError(
                f"only `config` and `enabled` can change, not {sorted(unknown)}"
            )
        enabled = changes.get("enabled", record.enabled)
        if not isinstance(enabled, bool):
            raise InvalidInputError("`enabled` is true or false")
        patch = changes.get("config", {})
        if not isinstance(patch, dict):
            raise InvalidInputError("`config` is a JSON object of the settings to change")
        merged = {**record.settings, **self._unseal(record), **patch}
        public, secret = split_config(checked_config(record.kind, merged))
        async with self._changing:
            before = (record.settings, record.secret, record.enabled)
            await self._stop(record.id)
            record.settings, record.secret, record.enabled = public, self._seal(secret), enabled
            try:
                if enabled and await self._may_run(record.id):
                    await self._start(record)
            except InvalidInputError:  # back to what it was, running again if it ran
                record.settings, record.secret, record.enabled = before
                if record.enabled:
                    await self._start_quietly(record)
                raise
            now = time.time_ns()
            await self.store.update_connector(record.id, public, record.secret, enabled, now)
            record.modified_ns = now
            if record.id in self._versions:  # as stored: no change made elsewhere to follow
                self._versions[record.id] = now
        return self.view(record)

    async def restart(self, principal: Principal, slug: str, name: str) -> dict[str, Any]:
        self._require_admin(principal)
        record = await self._find(principal, slug, name)
        if not record.enabled:
            raise ConflictError(f"connector {name!r} is disabled; enable it instead")
        async with self._changing:
            if not await self._may_run(record.id):  # it runs on another node: it restarts there
                await self.store.update_connector(
                    record.id, record.settings, record.secret, True, time.time_ns()
                )
                return self.view(record)
            await self._stop(record.id)
            await self._start(record)
        return self.view(record)

    async def delete(self, principal: Principal, slug: str, name: str) -> None:
        self._require_admin(principal)
        record = await self._find(principal, slug, name)
        async with self._changing:
            await self._stop(record.id)
            await self.store.delete_connector(record.id)

    def view(self, record: ConnectorRecord) -> dict[str, Any]:
        running = self.running.get(record.id)
        status = running.status if running else self.failed.get(record.id, ConnectorStatus())
        try:
            secret_names = set(self._unseal(record))
        except InvalidInputError:
            secret_names = set()
        return {
            "name": record.name,
            "twin": record.twin_slug,
            "kind": record.kind,
            "device": record.device,
            "enabled": record.enabled,
            "config": shown_config(record.kind, record.settings, secret_names),
            "status": status.view(),
            "created_ns": record.created_ns,
            "modified_ns": record.modified_ns,
        }

    # -- running --------------------------------------------------------------------------

    async def _start(self, record: ConnectorRecord) -> None:
        """Start `record`'s connector; a failure is kept as its status and raised."""
        self.failed.pop(record.id, None)
        self._versions[record.id] = record.modified_ns
        try:
            config = checked_config(record.kind, {**record.settings, **self._unseal(record)})
            device = await self.store.get_device(record.twin_id, record.device)
            if device is None:
                raise InvalidInputError(f"its device {record.device!r} no longer exists")
            cls = connector_class(record.kind)
            host = _SeenHost(self.hub, self.ingest, device, self.devices.last_used)
            connector = cls(record.name, config, host)
            await connector.start()
        except (ConnectorError, InvalidInputError, PluginUnavailable, OSError) as err:
            self._start_failed(record, str(err))
            raise InvalidInputError(f"connector {record.name!r} cannot start: {err}") from err
        except Exception as err:  # a bug in the kind's code (a plug-in's) stops only this one
            log.exception("connector %s/%s failed to start", record.twin_slug, record.name)
            reason = f"{type(err).__name__}: {err}"
            self._start_failed(record, reason)
            raise InvalidInputError(f"connector {record.name!r} cannot start: {reason}") from err
        self.running[record.id] = connector
        log.info("connector started", extra={"event": "connector_started", "connector":
                                              record.name, "twin": record.twin_slug})  # fmt: skip

    def _start_failed(self, record: ConnectorRecord, reason: str) -> None:
        status = ConnectorStatus()
        status.error("start_failed", reason)
        status.set_state("error")
        self.failed[record.id] = status

    async def _start_quietly(self, record: ConnectorRecord) -> None:
        """Start it if it can; why not is kept as its status."""
        try:
            await self._start(record)
        except InvalidInputError as err:
            log.warning("connector %s/%s not started: %s", record.twin_slug, record.name, err)

    async def _stop(self, connector_id: int) -> None:
        self.failed.pop(connector_id, None)
        self._versions.pop(connector_id, None)
        connector = self.running.pop(connector_id, None)
        if connector is not None:
            await connector.stop()

    # -- which node runs what (a shared store) --------------------------------------------

    async def _may_run(self, connector_id: int) -> bool:
        """Whether this node may run the connector: always when it is the only node; on a
        shared store, when it holds (or now takes) its lease."""
        return self.claims is None or await self.claims.claim(connector_id)

    async def _rebalance(self) -> None:
        """Renew the leases of the connectors this node runs and take free ones; stop what it
        no longer holds or what is disabled or deleted, start what it now holds, restart what
        another node changed. One that failed to start is tried again only once changed."""
        assert self.claims is not None
        try:
            enabled = {r.id: r for r in await self.store.list_connectors() if r.enabled}
        except StorageError:  # renewed if it can be; stopped once their leases may have expired
            held = await self.claims.hold(self._versions)
            for cid in [cid for cid in self._versions if cid not in held]:
                await self._stop(cid)
            return
        held = await self.claims.hold(enabled)
        for cid in [cid for cid in self._versions if cid not in held]:
            await self._stop(cid)
        for cid in sorted(held):
            record = enabled[cid]
            if self._versions.get(cid) == record.modified_ns:
                continue  # running (or failed) as it is stored
            await self._stop(cid)
            await self._start_quietly(record)

    def _twins_deleted(self, twin_ids: list[int]) -> None:
        doomed = [cid for cid, c in self.running.items() if c.host.device.twin_id in twin_ids]
        for cid in doomed:
            self._spawn(self._stop(cid))

    async def _device_deleted(self, device: Device) -> None:
        for cid in [cid for cid, c in self.running.items() if c.host.device.id == device.id]:
            await self._stop(cid)

    def _spawn(self, coro: Any) -> None:
        task = asyncio.ensure_future(coro)
        self._background.add(task)
        task.add_done_callback(self._background.discard)

    # -- helpers --------------------------------------------------------------------------

    @staticmethod
    def _require_admin(principal: Principal) -> None:
        if not principal.is_admin:
            raise ForbiddenError(
                "connectors bind ports on the server and connect from it: only admins "
                "create, change or delete them"
            )

    async def _find(self, principal: Principal, slug: str, name: str) -> ConnectorRecord:
        twin, _ = await self.registry.require_twin(principal, slug)
        for record in await self.store.list_connectors(twin.id):
            if record.name == name:
                return record
        raise NotFoundError(f"twin {slug!r} has no connector {name!r}")

    async def _device_for(
        self, principal: Principal, slug: str, device: Any, connector: str
    ) -> tuple[Device, bool]:
        """The device the connector speaks for, and whether it was made for it now."""
        if device is None:  # the connector's own device, made the first time
            twin, _ = await self.registry.require_twin(principal, slug)
            found = await self.store.get_device(twin.id, connector)
            if found is not None:
                return found, False
            made, _token = await self.devices.create(
                principal, slug, connector, f"Data from the connector {connector!r}"
            )
            return made, True
        if not isinstance(device, str):
            raise InvalidInputError("`device` is the name of one of the twin's devices")
        return await self.devices.get(principal, slug, device), False

    def _seal(self, secret: dict[str, Any]) -> bytes | None:
        return self.vault.seal(secret) if secret else None

    def _unseal(self, record: ConnectorRecord) -> dict[str, Any]:
        if record.secret is None:
            return {}
        try:
            return self.vault.unseal(record.secret)
        except VaultError as err:
            raise InvalidInputError(str(err)) from err
