"""Devices of a twin and their credentials.

A device token (`tld_...`, 256 random bits, stored as a SHA-256 hash, shown once) is accepted
only on the device-facing routes and only for its own twin; user API tokens are not accepted
there, and device tokens are not accepted anywhere else.
"""

from __future__ import annotations

import random
import re
import secrets
from collections.abc import Awaitable, Callable

from twinlink.auth.last_used import LastUsed
from twinlink.auth.rights import Principal, has_role
from twinlink.auth.secrets import hash_token, token_prefix
from twinlink.auth.service import AuthError, now_ns
from twinlink.domain.errors import ConflictError, ForbiddenError, NotFoundError
from twinlink.domain.records import Device, TwinRecord
from twinlink.registry.service import RegistryService
from twinlink.store.base import MetadataStore

DEVICE_TOKEN_PREFIX = "tld_"
DEVICE_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.:-]{0,63}$")
RECHECK_TOKEN_S = 60.0


def new_device_token() -> str:
    return DEVICE_TOKEN_PREFIX + secrets.token_urlsafe(32)


class DeviceService:
    def __init__(
        self,
        store: MetadataStore,
        registry: RegistryService,
        last_used: LastUsed | None = None,
        recheck_token_s: float = RECHECK_TOKEN_S,
    ) -> None:
        self.store = store
        self.registry = registry
        # When each device was last seen: kept in memory, written behind (last_used.py).
        self.last_used = last_used or LastUsed(store)
        # How often the token of an open connection is checked again (a device rotated,
        # or deleted, while connected is then cut off).
        self.recheck_token_s = recheck_token_s
        # Called with each deleted device, so what speaks for it (a connector) stops.
        self.deleted_listeners: list[Callable[[Device], Awaitable[None]]] = []

    def recheck_delay(self) -> float:
        """The wait before an open connection's token is checked again: `recheck_token_s`
        give or take a quarter, so the devices that connected together after a restart
        (2 000 of them) are not all checked in the same instant, every time."""
        return self.recheck_token_s * random.uniform(0.75, 1.25)

    async def _twin(self, principal: Principal, slug: str, needed: str) -> TwinRecord:
        twin, role = await self.registry.require_twin(principal, slug)
        if not has_role(principal, role, needed):
            raise ForbiddenError(f"the devices of {slug!r} need the {needed} role")
        return twin

    async def _device(self, principal: Principal, slug: str, name: str, needed: str) -> Device:
        twin = await self._twin(principal, slug, needed)
        device = await self.store.get_device(twin.id, name)
        if device is None:
            raise NotFoundError(f"twin {slug!r} has no device {name!r}")
        return device

    async def list(self, principal: Principal, slug: str) -> list[Device]:
        devices = await self.store.list_devices((await self._twin(principal, slug, "viewer")).id)
        return [self._seen(d) for d in devices]

    async def get(self, principal: Principal, slug: str, name: str) -> Device:
        return self._seen(await self._device(principal, slug, name, "viewer"))

    def _seen(self, device: Device) -> Device:
        device.last_seen_ns = self.last_used.device_time(device.id, device.last_seen_ns)
        return device

    async def create(
        self, principal: Principal, slug: str, name: str, description: str
    ) -> tuple[Device, str]:
        """The new device and its token; the token is not kept and cannot be shown again."""
        twin = await self._twin(principal, slug, "editor")
        if not DEVICE_NAME.match(name):
            raise ConflictError(f"device name {name!r}: use 1-64 letters, digits, . _ : -")
        if await self.store.get_device(twin.id, name) is not None:
            raise ConflictError(f"twin {slug!r} already has a device {name!r}")
        token = new_device_token()
        try:
            device = await self.store.create_device(
                twin.id, name, description, hash_token(token), token_prefix(token), now_ns()
            )
        finally:
            self.registry.changed()  # the devices commands may go to (CommandService)
        return device, token

    async def rotate(self, principal: Principal, slug: str, name: str) -> tuple[Device, str]:
        """A new token for the device; the old one stops working at once."""
        device = await self._device(principal, slug, name, "editor")
        token = new_device_token()
        try:
            await self.store.set_device_token(device.id, hash_token(token), token_prefix(token))
        finally:
            self.registry.changed()
        device.prefix = token_prefix(token)
        return device, token

    async def delete(self, principal: Principal, slug: str, name: str) -> None:
        device = await self._device(principal, slug, name, "editor")
        try:
            await self.store.delete_device(device.id)
        finally:
            self.registry.changed()
        for listener in self.deleted_listeners:
            await listener(device)

    async def authenticate(self, token: str) -> Device:
        device = await self.store.find_device(hash_token(token))
        if device is None:
            raise AuthError("the device token is not valid")
        # In memory only: the store gets it later, in a batch, and a store that cannot take
        # it (a full disk) never fails a connection.
        device.last_seen_ns = now_ns()
        self.last_used.device_seen(device.id, device.last_seen_ns)
        return device
