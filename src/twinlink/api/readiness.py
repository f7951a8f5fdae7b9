"""Readiness: may a load balancer send this node work? (GET /readyz, and /healthz's ping)

A node is ready when its store answers a ping and its bus is usable, each within a short
bound. The bound matters more than the answer: a database that stopped answering (a node cut
off from PostgreSQL, the server stopped with SIGSTOP) makes a ping wait for ever, and a health
check that waits for ever is one the load balancer times out on its own terms, while the
probes pile up on the node.

Probes share the check in flight (single flight): however many arrive while a ping is
underway, one ping is sent, and each probe waits for it at most the bound. A check that
outlives the bound is cancelled; one that does not end even then (a cancelled query whose
connection the driver still cleans up) stays the one in flight, so a stuck database gets one
ping at a time, never one per probe.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from typing import Protocol

log = logging.getLogger("twinlink.api")


class Pingable(Protocol):
    async def ping(self) -> bool: ...


class Readied(Protocol):
    async def ready(self) -> bool: ...


@dataclass(frozen=True, slots=True)
class Verdict:
    """What a check found: `failures` names each part that did not answer, in words."""

    failures: tuple[str, ...]

    @property
    def ready(self) -> bool:
        return not self.failures


class SingleFlight:
    """One run of `check` at a time; callers arriving while it runs wait for that run (at
    most `timeout_s` each), and a run is cancelled once it has taken `timeout_s`."""

    def __init__(self, check: Callable[[], Awaitable[bool]], timeout_s: float) -> None:
        self._check = check
        self._timeout_s = timeout_s
        self._flight: asyncio.Task[bool] | None = None

    async def answers(self) -> bool:
        """True when the check ran and said yes within the bound; False when it said no,
        raised, or had not ended by then."""
        flight = self._flight
        if flight is None or flight.done():
            flight = self._flight = asyncio.create_task(self._bounded(), name="readiness-check")
        # Waited on, never cancelled from here: other probes may be waiting for it too.
        done, _ = await asyncio.wait({flight}, timeout=self._timeout_s)
        if not done:
            return False
        return not flight.cancelled() and flight.exception() is None and flight.result()

    async def close(self) -> None:
        """Cancel the check in flight, waiting for it at most the bound."""
        if self._flight is not None and not self._flight.done():
            self._flight.cancel()
            await asyncio.wait({self._flight}, timeout=self._timeout_s)
        self._flight = None

    async def _bounded(self) -> bool:
        try:
            async with asyncio.timeout(self._timeout_s):
                return await self._check()
        except TimeoutError:
            return False
        except Exception as err:  # a broken store or bus is what readiness exists to report
            log.debug("readiness check failed", extra={"event": "ready_check", "error": repr(err)})
            return False


class Readiness:
    """The node's store and bus, each checked by a single flight of its own."""

    def __init__(self, store: Pingable, bus: Readied, timeout_s: float) -> None:
        self.timeout_s = timeout_s
        self._store = SingleFlight(store.ping, timeout_s)
        self._bus = SingleFlight(bus.ready, timeout_s)
        self._was_ready = True  # a change is logged once, not at every probe

    async def close(self) -> None:
        await asyncio.gather(self._store.close(), self._bus.close())

    async def store_answers(self) -> bool:
        return await self._store.answers()

    async def check(self) -> Verdict:
        store, bus = await asyncio.gather(self._store.answers(), self._bus.answers())
        bound = f"{self.timeout_s:g} s"
        failures = []
        if not store:
            failures.append(f"the store does not answer within {bound}")
        if not bus:
            failures.append(f"the bus is not connected (no answer within {bound})")
        verdict = Verdict(tuple(failures))
        self._log_change(verdict)
        return verdict

    def _log_change(self, verdict: Verdict) -> None:
        if verdict.ready == self._was_ready:
            return
        self._was_ready = verdict.ready
        if verdict.ready:
            log.info("ready again", extra={"event": "ready_again"})
        else:
            # Why a load balancer stopped sending this node work, for whoever reads the log.
            reason = "; ".join(verdict.failures)
            log.warning("not ready: %s", reason, extra={"event": "not_ready", "reason": reason})
