"""PropertyService on every storage backend (`_storage.BACKENDS`), through `PropertyStore`:
desired and reported values, their versions and times come back the same after a restart,
and a deleted twin or device takes its properties with it."""

from __future__ import annotations

import dataclasses

import pytest

from tests.unit._services import SLUG, Setting, setting
from tests.unit._storage import Stores
from tests.unit._storage import stores as stores  # fixture
from twinlink.commands import PropertyService
from twinlink.domain.errors import ForbiddenError, NotFoundError


@pytest.fixture
async def world(stores: Stores) -> Setting:
    return await setting(stores)


def service(world: Setting) -> PropertyService:
    return PropertyService(world.registry, world.stores.properties, world.hub)


async def test_values_versions_and_times_come_back_after_a_restart(world: Setting) -> None:
    first = service(world)
    await first.set_desired(world.owner, SLUG, "plc", {"rate": 50, "mode": "eco"})
    await first.set_desired(world.owner, SLUG, "plc", {"mode": None})  # removed: version 2
    ack = await first.report(world.device, {"rate": 50.0, "mode": "fast", "on": True})
    assert ack == {"version": 2, "desired": {}}  # 50.0 reported is 50 desired
    before = (await first.show(world.viewer, SLUG, "plc")).view()
    await first.close()

    second = service(world.fresh())
    try:
        after = (await second.show(world.viewer, SLUG, "plc")).view()
        assert after == before
        assert after["desired"]["rate"]["value"] == 50 and after["version"] == 2
        assert sorted(after["reported"]) == ["mode", "on", "rate"]
        props = await second.set_desired(world.owner, SLUG, "plc", {"rate": 60})
        assert (props.version, props.delta()) == (3, {"rate": 60})
    finally:
        await second.close()
    stored = await world.stores.properties.load_properties(
        world.device.id, world.twin.id, world.device.created_ns
    )
    assert (stored.version, stored.desired["rate"][0], stored.reported["on"][0]) == (3, 60, True)


async def test_a_new_device_with_the_id_of_a_deleted_one_starts_empty(world: Setting) -> None:
    first = service(world)
    await first.set_desired(world.owner, SLUG, "plc", {"rate": 50})
    await first.close()
    newer = dataclasses.replace(world.device, created_ns=world.device.created_ns + 1)
    second = service(world.fresh())
    try:
        assert (await second.for_device(newer)).view()["version"] == 0
        await second.report(newer, {"x": 1})
    finally:
        await second.close()
    stored = await world.stores.properties.load_properties(
        newer.id, newer.twin_id, newer.created_ns
    )
    assert (stored.version, stored.desired, list(stored.reported)) == (0, {}, ["x"])
    older = await world.stores.properties.load_properties(
        world.device.id, world.twin.id, world.device.created_ns
    )
    assert (older.version, older.desired, older.reported) == (0, {}, {})  # rows start afresh


async def test_deleting_the_twin_deletes_its_properties(world: Setting) -> None:
    props = service(world)
    await props.set_desired(world.owner, SLUG, "plc", {"rate": 50})
    await props.report(world.device, {"rate": 40})
    await world.registry.delete(world.owner, SLUG, cascade=False)
    await props.close()  # waits for the deletion it started
    stored = await world.stores.properties.load_properties(
        world.device.id, world.twin.id, world.device.created_ns
    )
    assert (stored.version, stored.desired, stored.reported) == (0, {}, {})


async def test_who_may_read_and_change_them(world: Setting) -> None:
    props = service(world)
    try:
        with pytest.raises(ForbiddenError, match="needs the editor role"):
            await props.set_desired(world.viewer, SLUG, "plc", {"rate": 1})
        with pytest.raises(NotFoundError):  # no role on a private twin: not seen at all
            await props.show(world.stranger, SLUG, "plc")
        with pytest.raises(NotFoundError, match="has no device 'gone'"):
            await props.show(world.owner, SLUG, "gone")
    finally:
        await props.close()
    stored = await world.stores.properties.load_properties(
        world.device.id, world.twin.id, world.device.created_ns
    )
    assert stored.version == 0 and not stored.desired  # nothing refused was stored
