"""Authentication on a store that cannot write: "last used" times kept in memory and written
behind in batches, and the periodic check of a device's token, which closes the connection
when it cannot be made instead of stopping silently."""

from __future__ import annotations

import asyncio
import logging
from collections.abc import AsyncIterator, Mapping
from pathlib import Path
from typing import Any

import pytest

from twinlink.api.device_ws import _recheck_token
from twinlink.auth.last_used import LastUsed
from twinlink.auth.rights import Principal
from twinlink.auth.service import AuthError, AuthService
from twinlink.domain.errors import StorageFullError
from twinlink.domain.records import Device, SearchRow, TwinWrite
from twinlink.ingest.sessions import DeviceSession
from twinlink.registry.devices import DeviceService
from twinlink.registry.service import RegistryService
from twinlink.store.sqlite import SqliteStore


class FullDisk:
    """The store, except that "last used" writes fail while `full` is set."""

    def __init__(self, store: SqliteStore) -> None:
        self.store = store
        self.full = True
        self.writes: list[dict[int, int]] = []

    async def touch_tokens(self, times: Mapping[int, int]) -> None:
        await self._touch(times, self.store.touch_tokens)

    async def touch_devices(self, times: Mapping[int, int]) -> None:
        await self._touch(times, self.store.touch_devices)

    async def _touch(self, times: Mapping[int, int], write: Any) -> None:
        if self.full:
            raise StorageFullError("full")
        self.writes.append(dict(times))
        await write(times)

    def __getattr__(self, name: str) -> Any:
        return getattr(self.store, name)


@pytest.fixture
async def store(tmp_path: Path) -> AsyncIterator[FullDisk]:
    real = SqliteStore(tmp_path)
    await real.open()
    try:
        yield FullDisk(real)
    finally:
        await real.close()


async def test_requests_authenticate_while_last_used_cannot_be_written(
    store: FullDisk, caplog: pytest.LogCaptureFixture
) -> None:
    last_used = LastUsed(store)  # type: ignore[arg-type]
    auth = AuthService(store, 3600, last_used)  # type: ignore[arg-type]
    bob = await store.store.create_user("bob", None, False, [], 1)
    issued = await auth.issue_token(bob, "t", ttl_s=None)
    for _ in range(3):
        principal = await auth.authenticate(issued.token)  # never raises for the write
        assert principal.token_id == issued.record.id
    with caplog.at_level(logging.INFO, logger="twinlink.auth"):
        assert await last_used.write() is False
        assert await last_used.write() is False  # logged once, not on every try
        store.full = False
        assert await last_used.write() is True
        assert await last_used.write() is True  # nothing left: no write at all
    assert [r.getMessage()[:48] for r in caplog.records] == [
        "could not write when tokens and devices were las",
        "last-used times written again",
    ]
    assert [list(w) for w in store.writes] == [[issued.record.id]]
    [listed] = await store.store.list_tokens(None)
    assert listed.last_used_ns is not None and listed.last_used_ns > 1


async def test_lists_show_times_not_yet_written(store: FullDisk) -> None:
    registry = RegistryService(store, "http://x")  # type: ignore[arg-type]
    devices = DeviceService(store, registry)  # type: ignore[arg-type]
    alice = await store.store.create_user("alice", None, True, [], 1)
    write = TwinWrite(
        slug="rig", dt_id="urn:rig", name="rig", created_ns=1, modified_ns=1,
        parts={"public": {"name": "rig"}}, edges=[],
        search_rows=[SearchRow("public", None, "rig", "", [], "")], owner_user_id=alice.id,
    )  # fmt: skip
    await store.store.save_twins([write])
    _, token = await devices.create(Principal(alice), "rig", "pi", "")
    seen = (await devices.authenticate(token)).last_seen_ns
    assert seen is not None
    [listed] = await devices.list(Principal(alice), "rig")
    assert listed.last_seen_ns == seen  # from memory: the store has nothing yet
    assert (await store.store.list_devices(listed.twin_id))[0].last_seen_ns is None


async def test_close_writes_what_waits_once_the_disk_takes_it(store: FullDisk) -> None:
    last_used = LastUsed(store, every_s=3600)  # type: ignore[arg-type]
    last_used.start()
    last_used.device_seen(7, 100)
    last_used.device_seen(7, 90)  # older: the newer time stays
    store.full = False
    await last_used.close()
    assert store.writes == [{7: 100}]


async def test_close_on_a_full_disk_does_not_raise(store: FullDisk) -> None:
    last_used = LastUsed(store)  # type: ignore[arg-type]
    last_used.start()
    last_used.token_used(1, 5)
    await last_used.close()
    assert last_used.token_time(1, None) == 5  # kept: nothing was lost in memory either


# -- the device token, checked again while connected ------------------------------------------


class Wire:
    def __init__(self) -> None:
        self.closed: tuple[int, str] | None = None

    async def send_text(self, data: str) -> None:
        return None

    async def close(self, code: int, reason: str) -> None:
        self.closed = (code, reason)


class Devices:
    recheck_token_s = 0.001

    def recheck_delay(self) -> float:
        return self.recheck_token_s

    def __init__(self, error: Exception | None) -> None:
        self.error = error
        self.checks = 0

    async def authenticate(self, token: str) -> Device:
        self.checks += 1
        if self.error is not None and self.checks >= 3:
            raise self.error
        return device()


def device() -> Device:
    return Device(1, 1, "rig-twin", "rig", "", "tld_x", 0, None)


@pytest.mark.parametrize(
    ("error", "code"),
    [
        (AuthError("the device token is not valid"), 4401),
        (StorageFullError("full"), 1011),  # any failure: never left open unchecked
        (RuntimeError("the store is not open"), 1011),
    ],
)
async def test_a_token_check_that_fails_closes_the_connection(error: Exception, code: int) -> None:
    wire = Wire()
    session = DeviceSession(device(), wire)
    session.open({"type": "welcome"})
    devices = Devices(error)
    await asyncio.wait_for(_recheck_token(session, devices, "tld_x"), 10)  # type: ignore[arg-type]
    assert session.closed.is_set() and wire.closed is not None
    assert wire.closed[0] == code and devices.checks == 3
    if code == 1011:
        assert wire.closed[1] == "the device token could not be checked again; reconnect"


def test_token_rechecks_are_spread_around_the_interval() -> None:
    from twinlink.registry.devices import DeviceService

    service = DeviceService(store=None, registry=None, recheck_token_s=60.0)  # type: ignore[arg-type]
    delays = [service.recheck_delay() for _ in range(2000)]
    assert all(45.0 <= d <= 75.0 for d in delays)
    assert max(delays) - min(delays) > 20.0  # not all at once after a mass reconnect


async def test_a_token_that_cannot_be_read_closes_the_new_connection_with_a_reason() -> None:
    from types import SimpleNamespace

    from twinlink.api.device_ws import device_socket
    from twinlink.domain.errors import StorageError

    class Unreadable:
        async def authenticate(self, token: str) -> Device:
            raise StorageError("the disk failed while reading the token; try again")

    closed: list[tuple[int, str]] = []

    class Socket:
        def __init__(self) -> None:
            self.headers = {"authorization": "Bearer tld_x"}
            services = SimpleNamespace(devices=Unreadable())
            self.app = SimpleNamespace(state=SimpleNamespace(services=services))

        async def accept(self) -> None:
            return None

        async def close(self, code: int, reason: str) -> None:
            closed.append((code, reason))

    await device_socket(Socket())  # type: ignore[arg-type]
    assert closed == [(1011, "the disk failed while reading the token; try again")]
