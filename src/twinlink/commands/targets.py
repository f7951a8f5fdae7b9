"""Which device a command goes to.

A command that names a device goes to it. One that names none goes to the twin's only device;
else to the device the twin's `interface` declares as `default_device` (checked here, when it
is used: the interface is an open model); else to the only device online. Otherwise the
sender has to name one, and `DeviceChoiceError` says why.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from twinlink.domain.errors import ConflictError, InvalidInputError, NotFoundError
from twinlink.domain.merge import merge_parts
from twinlink.domain.records import Device, TwinRecord
from twinlink.registry.cache import GenerationCache
from twinlink.registry.service import RegistryService


class DeviceChoiceError(InvalidInputError):
    """A command names no device and none can be chosen for it. `reason` says why without
    saying how to name one, which each surface says in its own terms (the API's `device`
    field, the CLI's --device option); `devices` are the twin's device names."""

    def __init__(self, reason: str, devices: list[str]) -> None:
        super().__init__(f"{reason}; name one with `device`")
        self.reason = reason
        self.devices = devices

    def problem_extensions(self) -> dict[str, Any]:
        # Why, and the devices to choose from, so a client can say it in its own terms (the
        # CLI names its --device option).
        return {"reason": self.reason, "devices": self.devices}


@dataclass(slots=True, frozen=True)
class TwinDevices:
    by_name: dict[str, Device]
    default: Any  # the interface's `default_device` as written


class DeviceTargets:
    def __init__(self, registry: RegistryService, online: Callable[[int], bool]) -> None:
        self.registry = registry
        self.online = online  # whether a device (by id) can take a command now
        # The devices of each twin and its default, until a device is added or removed or a
        # document changes (each bumps the registry's generation).
        self._devices: GenerationCache[int, TwinDevices] = GenerationCache(
            lambda: registry.generation
        )

    async def target(self, twin: TwinRecord, name: str | None) -> Device:
        """The device named `name`, or the one chosen when `name` is None."""
        devices = await self.devices_of(twin.id)
        if name is not None:
            found = devices.by_name.get(name)
            if found is None:
                raise NotFoundError(f"twin {twin.slug!r} has no device {name!r}")
            return found
        if not devices.by_name:
            raise ConflictError(f"twin {twin.slug!r} has no devices; add one first")
        if len(devices.by_name) == 1:
            return next(iter(devices.by_name.values()))
        if devices.default is not None:
            return _declared_default(twin.slug, devices)
        online = [d for d in devices.by_name.values() if self.online(d.id)]
        if len(online) == 1:
            return online[0]
        names = sorted(devices.by_name)
        raise DeviceChoiceError(
            f"twin {twin.slug!r} has several devices ({', '.join(names)}), its interface "
            f"declares no `default_device`, and {len(online) or 'none'} of them are connected",
            names,
        )

    async def chosen(self, twin: TwinRecord) -> str | None:
        """The name of the device a command that names none goes to now; None when the
        sender has to name one."""
        try:
            return (await self.target(twin, None)).name
        except (ConflictError, DeviceChoiceError):
            return None

    async def devices_of(self, twin_id: int) -> TwinDevices:
        devices = self._devices.get(twin_id)
        if devices is None:
            read_at = self._devices.generation()
            by_name = {d.name: d for d in await self.registry.store.list_devices(twin_id)}
            parts = await self.registry.store.get_parts(twin_id)
            interface = merge_parts(parts).get("interface") if parts else None
            default = interface.get("default_device") if isinstance(interface, dict) else None
            devices = TwinDevices(by_name, default)
            self._devices.keep(twin_id, devices, read_at)
        return devices


def _declared_default(slug: str, devices: TwinDevices) -> Device:
    default = devices.default
    found = devices.by_name.get(default) if isinstance(default, str) else None
    if found is None:
        names = sorted(devices.by_name)
        raise DeviceChoiceError(
            f"twin {slug!r} has several devices ({', '.join(names)}), and the "
            f"`default_device` its interface declares, {default!r}, is not one of them",
            names,
        )
    return found
