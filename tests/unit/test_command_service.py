"""CommandService on every storage backend (`_storage.BACKENDS`), through `CommandStore`:
what it writes to the command log is what a restarted service and readers find there."""

from __future__ import annotations

from collections.abc import AsyncIterator

import pytest

from tests.unit._services import SLUG, Setting, T, setting
from tests.unit._storage import Stores
from tests.unit._storage import stores as stores  # fixture
from twinlink.commands import CommandService
from twinlink.domain.commands import CommandRecord, new_command_id
from twinlink.domain.errors import ForbiddenError, NotFoundError


@pytest.fixture
async def world(stores: Stores) -> Setting:
    return await setting(stores)


async def started(world: Setting) -> CommandService:
    service = CommandService(world.registry, world.stores.commands, world.hub, 30.0)
    await service.open()
    return service


@pytest.fixture
async def commands(world: Setting) -> AsyncIterator[CommandService]:
    service = await started(world)
    yield service
    await service.close()


async def test_a_queued_command_outlives_a_restart_and_goes_out_with_the_next_poll(
    world: Setting,
) -> None:
    first = await started(world)
    sent = await first.send(world.owner, SLUG, "pause", {"why": "lunch"}, queue=True, wait=False)
    assert sent.state == "pending"  # the device is offline: it waits in the log
    await first.close()

    again = world.fresh()
    second = await started(again)
    try:
        [polled] = await second.poll(world.device, 0)
        assert (polled.id, polled.name, polled.args, polled.state) == (
            sent.id, "pause", {"why": "lunch"}, "delivered",
        )  # fmt: skip
        done = await second.record_result(world.device, sent.id, "succeeded", [1, "a"], None)
        assert done.state == "succeeded"
        shown = await second.get(world.viewer, SLUG, sent.id)
        assert (shown.state, shown.result, shown.queued) == ("succeeded", [1, "a"], True)
        assert shown.delivered_ns is not None and shown.finished_ns is not None
    finally:
        await second.close()
    stored = await world.stores.commands.get_command(sent.id)
    assert stored == shown


async def test_a_command_to_an_offline_device_fails_and_is_logged(
    commands: CommandService, world: Setting
) -> None:
    record = await commands.send(world.owner, SLUG, "pause")
    assert (record.state, record.error) == ("failed", "device offline")
    [logged] = await commands.list_commands(world.viewer, SLUG)
    assert (logged.id, logged.state, logged.error) == (record.id, "failed", "device offline")


async def test_the_log_is_newest_first_and_filtered(
    commands: CommandService, world: Setting
) -> None:
    names = ["start", "pause", "start", "stop"]
    sent = [await commands.send(world.owner, SLUG, name, queue=True, wait=False) for name in names]
    await commands.send(world.owner, SLUG, "pause")  # offline: failed
    log = await commands.list_commands(world.viewer, SLUG)
    assert [r.name for r in log] == ["pause", "stop", "start", "pause", "start"]
    assert [r.id for r in await commands.list_commands(world.viewer, SLUG, name="start")] == [
        sent[2].id,
        sent[0].id,
    ]
    pending = await commands.list_commands(world.viewer, SLUG, state="pending", limit=2)
    assert [r.id for r in pending] == [sent[3].id, sent[2].id]
    assert await commands.list_commands(world.viewer, SLUG, device="nope") == []
    with pytest.raises(ForbiddenError):  # viewers read the log; sending needs an editor
        await commands.send(world.viewer, SLUG, "pause")


async def test_commands_that_expired_while_the_server_was_down_are_closed_at_start(
    world: Setting,
) -> None:
    record = CommandRecord(
        id=new_command_id(), twin_id=world.twin.id, device_id=world.device.id, device="plc",
        name="pause", args={}, state="delivered", queued=True, sent_by="alice",
        created_ns=T, expires_ns=T + 10**9, delivered_ns=T + 1,
    )  # fmt: skip
    await world.stores.commands.save_commands([record])
    assert [r.id for r in await world.stores.commands.open_commands()] == [record.id]
    service = await started(world)
    await service.close()  # writes what opening changed
    stored = await world.stores.commands.get_command(record.id)
    assert stored is not None
    assert (stored.state, stored.finished_ns) == ("expired", T + 10**9)
    assert await world.stores.commands.open_commands() == []


async def test_deleting_the_twin_deletes_its_commands(world: Setting) -> None:
    service = await started(world)
    sent = await service.send(world.owner, SLUG, "pause", queue=True, wait=False)
    await world.registry.delete(world.owner, SLUG, cascade=False)
    assert sent.state == "failed" and sent.error == "the twin was deleted"
    await service.close()  # waits for the deletion it started
    assert await world.stores.commands.get_command(sent.id) is None
    assert await world.stores.commands.list_commands(world.twin.id, None, None, None, 10) == []


async def test_another_twin_s_command_is_not_found(
    commands: CommandService, world: Setting
) -> None:
    sent = await commands.send(world.owner, SLUG, "pause")
    with pytest.raises(NotFoundError, match="has no command"):
        await commands.get(world.owner, SLUG, sent.id + "x")
    with pytest.raises(NotFoundError, match="no command"):
        await commands.record_result(world.device, new_command_id(), "succeeded", None, None)
