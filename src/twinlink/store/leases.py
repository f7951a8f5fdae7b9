"""Leases: which node runs an item (a processor, a connector) when several share one store.

A lease is a name ("processor:12") held by one holder (a node's run) until it expires. A node
acquires or renews the leases of what it wants to run, well within their TTL, and runs only
what it holds; it releases them when it stops cleanly. When it dies, its leases expire and
another node's next round takes the items over. Expiry is the store's clock (PostgreSQL's
`now()`), never a node's, so nodes whose clocks disagree still agree on who holds what.

A lease also keeps its item's *position* in its input (the input stream and the newest
sample time processed), saved by the holder with its renewals: the node that takes the item
over from a dead one starts from there (processors/catchup.py). Only the holder of a live
lease can save it, and a position never moves back, so a node that lost its lease cannot
overwrite its successor's.

`LocalLeases` is the embedded backend's: one node, the same semantics, in memory. `Claims`
is what a service keeps: the leases of one kind of item, by id.
"""

from __future__ import annotations

import asyncio
import logging
import os
import secrets
import socket
import time
from collections.abc import Awaitable, Callable, Iterable
from typing import NamedTuple, Protocol

from twinlink.domain.errors import StorageError

log = logging.getLogger("twinlink.store")

# A node renews every RENEW_S; a lease it fails to renew lasts TTL_S from its last renewal.
# So a dead node's items are taken over within TTL_S + RENEW_S of its last renewal.
TTL_S = 10.0
RENEW_S = 3.0


def new_holder() -> str:
    """This node's run: host and pid for people reading the table, and a random part, so a
    restarted node (the same pid in a container) never holds its former run's leases."""
    return f"{socket.gethostname()}:{os.getpid()}:{secrets.token_hex(4)}"


def node_gone(node: str) -> bool:
    """Whether `node` (a `new_holder` value) was a server of this host whose process has
    ended: what it held (runs, leases) may be taken back at once."""
    host, _, rest = node.partition(":")
    pid = rest.partition(":")[0]
    if host != socket.gethostname() or not pid.isdigit():
        return False
    try:
        os.kill(int(pid), 0)
    except ProcessLookupError:
        return True
    except PermissionError:  # alive, another user's
        return False
    return False


class Position(NamedTuple):
    """How far an item got in its input: every sample of `stream` up to time `t` (ns) that
    reached it has been processed."""

    stream: str
    t: int


class LeaseStore(Protocol):
    async def acquire(self, names: list[str], holder: str, ttl_s: float) -> set[str]:
        """Take each lease that is free or expired, renew each `holder` holds; the names
        `holder` holds now (for `ttl_s` more seconds)."""
        ...

    async def release(self, names: list[str], holder: str) -> None:
        """Give up the leases of `names` that `holder` holds; others' are left alone."""
        ...

    async def held(self, holder: str) -> set[str]:
        """The names `holder` holds and that have not expired."""
        ...

    async def save_positions(self, positions: dict[str, Position], holder: str) -> None:
        """Keep each name's position, for the names `holder` holds now (others are left as
        they are); a position in the same stream never moves back."""
        ...

    async def positions(self, names: list[str]) -> dict[str, Position]:
        """The kept positions of `names` (those that have one)."""
        ...

    async def forget_positions(self, names: list[str]) -> None:
        """Forget the positions of `names` (their items were stopped on purpose)."""
        ...


class LocalLeases:
    """Leases of one node (the embedded backend): the same semantics as the shared store's,
    kept in memory with the monotonic clock (nothing else could hold one across a restart)."""

    def __init__(self) -> None:
        self._leases: dict[str, tuple[str, float]] = {}  # name -> (holder, expires)
        self._positions: dict[str, Position] = {}

    async def acquire(self, names: list[str], holder: str, ttl_s: float) -> set[str]:
        now = time.monotonic()
        got = set()
        for name in names:
            current = self._leases.get(name)
            if current is None or current[0] == holder or current[1] <= now:
                self._leases[name] = (holder, now + ttl_s)
                got.add(name)
        return got

    async def release(self, names: list[str], holder: str) -> None:
        for name in names:
            if self._leases.get(name, ("", 0.0))[0] == holder:
                del self._leases[name]

    async def held(self, holder: str) -> set[str]:
        now = time.monotonic()
        return {n for n, (h, expires) in self._leases.items() if h == holder and expires > now}

    async def save_positions(self, positions: dict[str, Position], holder: str) -> None:
        held = await self.held(holder)
        for name, position in positions.items():
            if name in held:
                self._positions[name] = _later(self._positions.get(name), position)

    async def positions(self, names: list[str]) -> dict[str, Position]:
        return {n: self._positions[n] for n in names if n in self._positions}

    async def forget_positions(self, names: list[str]) -> None:
        for name in names:
            self._positions.pop(name, None)


def _later(kept: Position | None, new: Position) -> Position:
    """The position to keep: the new one, unless the kept one is further in the same stream."""
    if kept is not None and kept.stream == new.stream and kept.t > new.t:
        return kept
    return new


class Claims:
    """The leases of one kind of item ("processor", "connector") that a node holds, by id."""

    def __init__(
        self,
        store: LeaseStore,
        kind: str,
        holder: str,
        *,
        ttl_s: float = TTL_S,
        renew_s: float = RENEW_S,
    ) -> None:
        self.store = store
        self.kind = kind
        self.holder = holder
        self.ttl_s = ttl_s
        self.renew_s = renew_s
        self.held: set[int] = set()
        self._renewed = time.monotonic()  # when the held leases were last renewed

    def _name(self, item_id: int) -> str:
        return f"{self.kind}:{item_id}"

    async def hold(self, wanted: Iterable[int]) -> set[int]:
        """Acquire or renew the leases of `wanted`, release those held and no longer wanted;
        the ids held now. While the store cannot be reached, what is held is kept until its
        leases may have expired (another node may then run it), then nothing is."""
        wanted = sorted(set(wanted))  # one order on every node: no deadlock between them
        dropped = sorted(self.held - set(wanted))
        try:
            if dropped:
                await self.store.release([self._name(i) for i in dropped], self.holder)
            got = await self.store.acquire([self._name(i) for i in wanted], self.holder,
                                           self.ttl_s)  # fmt: skip
        except StorageError as err:
            if time.monotonic() - self._renewed > self.ttl_s - self.renew_s:
                log.warning("%s leases not renewed, stopping what they cover: %s", self.kind,
                            err, extra={"event": "leases_lost"})  # fmt: skip
                self.held = set()
            else:
                self.held -= set(dropped)
            return set(self.held)
        self._renewed = time.monotonic()
        self.held = {i for i in wanted if self._name(i) in got}
        return set(self.held)

    async def keep(
        self, each_round: Callable[[], Awaitable[None]], turn: asyncio.Lock | None = None
    ) -> None:
        """Run `each_round` every `renew_s` (holding `turn`, when given) until cancelled; a
        round that fails is logged and the next tries again: the loop must not end."""
        while True:
            await asyncio.sleep(self.renew_s)
            try:
                if turn is None:
                    await each_round()
                else:
                    async with turn:
                        await each_round()
            except Exception:
                log.exception("%s leases: a round failed", self.kind)

    async def claim(self, item_id: int) -> bool:
        """Take (or renew) the one lease of `item_id`: True when this node holds it."""
        got = await self.store.acquire([self._name(item_id)], self.holder, self.ttl_s)
        if got:
            self.held.add(item_id)
        return bool(got)

    async def save_positions(self, positions: dict[int, Position]) -> bool:
        """Keep the positions of items this node holds; False (logged) when the store cannot
        be reached: they are saved with a later round."""
        if not positions:
            return True
        named = {self._name(i): p for i, p in positions.items()}
        try:
            await self.store.save_positions(named, self.holder)
        except StorageError as err:
            log.warning("%s positions not saved (tried again next round): %s", self.kind, err,
                        extra={"event": "positions_not_saved"})  # fmt: skip
            return False
        return True

    async def position(self, item_id: int) -> Position | None:
        """Where the item got in its input when it last ran (on any node)."""
        name = self._name(item_id)
        return (await self.store.positions([name])).get(name)

    async def forget_position(self, item_id: int) -> None:
        await self.store.forget_positions([self._name(item_id)])

    async def release_all(self) -> None:
        """Give up every lease held (a clean stop): the other nodes take them over at once."""
        held, self.held = sorted(self.held), set()
        if held:
            await self.store.release([self._name(i) for i in held], self.holder)
