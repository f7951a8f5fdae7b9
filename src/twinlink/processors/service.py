"""Processors of twins: what people create and change, and the supervised workers behind them.

Each enabled processor has a Supervisor (its worker process) and a bus subscription to its
source stream; its output goes back through ingest (bus at once, history at the next group
commit), so it can be charted live, read from history and fed to the next processor.
On a store shared by several nodes, a processor starting on a node first catches up from
history on what it has not processed (catchup.py), from the position its last node saved.
"""

from __future__ import annotations

import asyncio
import logging
import time
from functools import partial
from pathlib import Path
from typing import Any

from twinlink.auth.rights import Principal
from twinlink.bus import Bus
from twinlink.commands import CommandService
from twinlink.domain.errors import ConflictError, InvalidInputError, NotFoundError, StorageError
from twinlink.domain.records import ProcessorEvent, ProcessorRecord
from twinlink.ingest.service import IngestService
from twinlink.library.service import LibraryService
from twinlink.processors.access import editable_twin, stored_processor
from twinlink.processors.catalog import Entry, discover
from twinlink.processors.checks import check_chain, check_fmu, checked_spec, spec_of
from twinlink.processors.fmuenv import FmuEnvs
from twinlink.processors.hosting import Hosted, save_positions, subscribed
from twinlink.processors.libref import LibraryFmus
from twinlink.processors.outputs import Outputs
from twinlink.processors.reports import Reports, finished_before
from twinlink.processors.spec import ProcessorSpec
from twinlink.processors.supervisor import Supervisor, WorkerConfig
from twinlink.registry.service import RegistryService
from twinlink.store.base import MetadataStore
from twinlink.store.history import HistoryReadStore
from twinlink.store.leases import Claims

log = logging.getLogger("twinlink.processors")


class ProcessorService:
    def __init__(
        self,
        store: MetadataStore,
        registry: RegistryService,
        bus: Bus,
        ingest: IngestService,
        commands: CommandService,
        data_dir: Path,
        blueprints_dir: Path | None,
        max_running: int = 64,
        claims: Claims | None = None,
        history: HistoryReadStore | None = None,
        library: LibraryService | None = None,
        env_build_timeout_s: float = 900.0,
    ) -> None:
        self.store = store
        self.registry = registry
        self.bus = bus
        self.ingest = ingest
        self.commands = commands
        self.data_dir = Path(data_dir).resolve()
        self.blueprints_dir = blueprints_dir or self.data_dir / "blueprints"
        self.max_running = max_running
        self.catalog: dict[str, Entry] = {}
        self.hosted: dict[int, Hosted] = {}
        self.reports = Reports(store, commands)  # events and commands, in the background
        # On a store shared by several nodes: the leases of the processors this node runs
        # (None: the only node, which runs every enabled processor).
        self.claims = claims
        self.history = history  # where a processor catches up from (with `claims` only)
        self._keeper: asyncio.Task[None] | None = None
        # A lease round and a change made through the API take turns: a round that read the
        # processors before a stop must not start again what the stop just ended.
        self._changing = asyncio.Lock()
        self.outputs = Outputs(ingest)
        self.lib = LibraryFmus(library)  # FMUs of the library (`fmu: lib:...`, libref.py)
        # The logs and last error of processors stopped here, kept for the API until they
        # are started again or deleted (a stopped processor's diagnostics are what one reads).
        self.left: dict[int, tuple[list[tuple[int, str]], str | None]] = {}
        # python_requirements (fmuenv.py)
        self.envs = FmuEnvs(self.data_dir / "fmu-envs", env_build_timeout_s)
        registry.deleted_listeners.append(self._twins_deleted)

    # -- lifecycle --------------------------------------------------------------------------

    async def open(self) -> None:
        self.catalog = await asyncio.to_thread(discover, self.blueprints_dir)
        records = await self.store.list_processors()
        await self.lib.open(records)
        if self.claims is None:  # the only node: it runs every enabled processor
            await self.lib.prepare([r for r in records if r.enabled])
            self._host_all(records, await finished_before(self.store, records))
        else:  # one of several: it runs those whose leases it takes, now and every round
            await self._rebalance()
            self._keeper = asyncio.create_task(self.claims.keep(self._rebalance, self._changing))
        # Import the installed blueprints now, off the event loop, not at the first request.
        self.reports.spawn(asyncio.to_thread(lambda: [e.cls for e in self.catalog.values()]))

    async def close(self) -> None:
        if self._keeper is not None:
            self._keeper.cancel()
            await asyncio.gather(self._keeper, return_exceptions=True)
        stopped = list(self.hosted.values())
        await asyncio.gather(*(self._unhost(pid) for pid in list(self.hosted)))
        await self.reports.drain()
        if self.claims is not None:  # stopped: the other nodes may take them over at once
            await save_positions(self.claims, stopped)  # and go on from where these stopped
            try:
                await self.claims.release_all()
            except StorageError as err:
                log.warning("processor leases not released (they expire): %s", err)

    def blueprints(self) -> list[dict[str, Any]]:
        return [entry.view() for entry in self.catalog.values()]

    def blueprint(self, name: str) -> dict[str, Any]:
        entry = self.catalog.get(name)
        if entry is None:
            raise NotFoundError(f"no blueprint {name!r}; see /api/v1/blueprints")
        return entry.view()

    # -- people ---------------------------------------------------------------------------

    async def list_processors(self, principal: Principal, slug: str) -> list[dict[str, Any]]:
        twin, _ = await self.registry.require_twin(principal, slug)
        return [self.view(r) for r in await self.store.list_processors(twin.id)]

    async def get(self, principal: Principal, slug: str, name: str) -> dict[str, Any]:
        return self.view(await self._find(principal, slug, name, "viewer"))

    async def create(self, principal: Principal, slug: str, body: dict[str, Any]) -> dict[str, Any]:
        twin = await editable_twin(self.registry, principal, slug)
        spec = self._checked(body)
        pinned = await self.lib.pin(principal, spec.params)  # a library FMU, pinned
        await check_fmu(spec, twin.id, twin.slug, self.store, self.lib, self.catalog)
        existing = await self.store.list_processors(twin.id)
        if any(r.name == spec.name for r in existing):
            raise ConflictError(f"the twin already has a processor {spec.name!r}")
        check_chain(spec, existing)
        if spec.enabled:
            self._check_room()
        user_id = principal.user.id if principal.user else None
        async with self._changing:
            record = await self.store.create_processor(
                twin.id, spec.name, spec.blueprint, spec.stored(), spec.enabled, user_id,
                time.time_ns(),
            )  # fmt: skip
            await self.lib.hold(record, pinned)
            if record.enabled and await self._may_run(record.id):
                await self.lib.prepare([record])
                self._host(record)
        return self.view(record)

    async def update(
        self, principal: Principal, slug: str, name: str, changes: dict[str, Any]
    ) -> dict[str, Any]:
        """Change a processor. Parameters alone are applied to the running worker when its
        blueprint can keep its state; anything else restarts it."""
        record = await self._find(principal, slug, name, "editor")
        current = spec_of(record)
        if "name" in changes and changes["name"] != record.name:
            raise InvalidInputError("a processor cannot be renamed; create a new one")
        merged = {**current.model_dump(mode="json"), **changes}
        spec = self._checked(merged)
        new_fmu = spec.params.get("fmu") != current.params.get("fmu")
        pinned = await self.lib.pin(principal, spec.params) if new_fmu else None
        await check_fmu(spec, record.twin_id, slug, self.store, self.lib, self.catalog)
        others = [r for r in await self.store.list_processors(record.twin_id) if r.id != record.id]
        check_chain(spec, others)
        if spec.enabled and record.id not in self.hosted:
            self._check_room()
        async with self._changing:
            now = time.time_ns()
            await self.store.update_processor(record.id, spec.stored(), spec.enabled, now)
            record.spec, record.enabled = spec.stored(), spec.enabled
            record.blueprint = spec.blueprint
            record.modified_ns = now  # as stored: other rounds see no change made elsewhere
            if new_fmu:  # what it used before is no longer held by it
                await self.lib.hold(record, pinned)
            kept = await self._apply(record, current, spec)
        return {**self.view(record), "kept_state": kept}

    async def set_enabled(
        self, principal: Principal, slug: str, name: str, enabled: bool
    ) -> dict[str, Any]:
        return await self.update(principal, slug, name, {"enabled": enabled})

    async def restart(self, principal: Principal, slug: str, name: str) -> dict[str, Any]:
        record = await self._find(principal, slug, name, "editor")
        hosted = self.hosted.get(record.id)
        if hosted is None and record.enabled and self.claims is not None:
            raise ConflictError(
                f"processor {name!r} runs on another node of this cluster, which alone can "
                "restart it: send the request to that node, or stop the processor, wait 5 s "
                "(its node stops it) and start it"
            )
        if hosted is None:
            raise ConflictError(f"processor {name!r} is stopped; start it instead")
        await hosted.supervisor.restart()
        return self.view(record)

    async def delete(self, principal: Principal, slug: str, name: str) -> None:
        record = await self._find(principal, slug, name, "editor")
        async with self._changing:
            await self._unhost(record.id)
            await self.store.delete_processor(record.id)
            self.left.pop(record.id, None)
            await self.lib.release([record.id])
            await self._forget_position(record.id)

    async def events(
        self, principal: Principal, slug: str, name: str, limit: int, before: int | None,
        kind: str | None,
    ) -> list[ProcessorEvent]:  # fmt: skip
        record = await self._find(principal, slug, name, "viewer")
        return await self.store.list_processor_events(record.id, limit, before, kind)

    async def logs(self, principal: Principal, slug: str, name: str) -> list[tuple[int, str]]:
        record = await self._find(principal, slug, name, "viewer")
        hosted = self.hosted.get(record.id)
        return list(hosted.supervisor.logs) if hosted else self.left.get(record.id, ([], None))[0]

    def view(self, record: ProcessorRecord) -> dict[str, Any]:
        hosted = self.hosted.get(record.id)
        sup = hosted.supervisor if hosted else None
        return {
            "name": record.name,
            "twin": record.twin_slug,
            "blueprint": record.blueprint,
            **record.spec,
            "enabled": record.enabled,
            "state": sup.state if sup else "stopped",
            "pid": sup.pid if sup and sup.state == "running" else None,
            "last_error": sup.last_error if sup else self.left.get(record.id, ([], None))[1],
            "restart_at": sup.restart_at if sup else None,
            "stats": sup.stats.view() if sup else None,
            "running": sup.info if sup else {},
            "created_ns": record.created_ns,
            "modified_ns": record.modified_ns,
        }

    # -- which node runs what (a shared store) --------------------------------------------

    def _host_all(self, records: list[ProcessorRecord], finished: dict[int, str]) -> None:
        for record in records:
            if not record.enabled:
                continue
            if len(self.hosted) >= self.max_running:
                log.warning(
                    "processor %s/%s not started: over max_processors (%d)",
                    record.twin_slug, record.name, self.max_running,
                )  # fmt: skip
                continue
            self._host(record, finished.get(record.id))

    async def _may_run(self, processor_id: int) -> bool:
        """Whether this node may run the processor: always when it is the only node; on a
        shared store, when it holds (or now takes) its lease."""
        return self.claims is None or await self.claims.claim(processor_id)

    async def _rebalance(self) -> None:
        """Renew the leases of the processors this node runs and take free ones (up to
        max_processors); stop what it no longer holds or what is disabled or deleted, start
        what it now holds, apply what another node changed."""
        assert self.claims is not None
        try:
            enabled = {r.id: r for r in await self.store.list_processors() if r.enabled}
        except StorageError:  # renewed if it can be; stopped once their leases may have expired
            enabled = {pid: hosted.record for pid, hosted in self.hosted.items()}
        keep = [pid for pid in enabled if pid in self.hosted]
        more = [pid for pid in sorted(enabled) if pid not in self.hosted]
        held = await self.claims.hold(keep + more[: max(0, self.max_running - len(keep))])
        await self.lib.prepare([enabled[pid] for pid in held if pid not in self.hosted])
        for pid in [pid for pid in self.hosted if pid not in held]:
            await self._unhost(pid)
            if pid not in enabled:  # disabled or deleted, not taken over: start anew later
                await self._forget_position(pid)
        # taken over finished (on its old node, or before a restart): it stays finished
        try:
            taken = [enabled[p] for p in held if p not in self.hosted]
            finished = await finished_before(self.store, taken)
        except StorageError:  # not known now: started, from the beginning
            finished = {}
        for pid in sorted(held):
            record, hosted = enabled[pid], self.hosted.get(pid)
            if hosted is None:
                self._host(record, finished.get(pid))
            elif hosted.record.modified_ns != record.modified_ns:  # changed on another node
                await self._apply(record, spec_of(hosted.record), spec_of(record))
        await save_positions(self.claims, list(self.hosted.values()))

    async def _forget_position(self, processor_id: int) -> None:
        """Stopped on purpose: when it runs again it starts from then, not from here."""
        if self.claims is None:
            return
        try:
            await self.claims.forget_position(processor_id)
        except StorageError as err:
            log.warning("processor %d: its position not forgotten: %s", processor_id, err)

    # -- hosting ----------------------------------------------------------------------------

    def _host(self, record: ProcessorRecord, finished: str | None = None) -> None:
        entry = self.catalog.get(record.blueprint)
        config = self._worker_config(record, entry)
        supervisor = Supervisor(
            config,
            on_output=partial(self.outputs.publish, record),
            on_events=partial(self.reports.events, record),
            on_commands=partial(self.reports.send_commands, record),
        )
        catch_up_from = None  # on a shared store: first what it has not processed (catchup.py)
        if self.claims is not None and self.history is not None and entry is not None:
            catch_up_from = (self.claims, self.history)
        hosted = subscribed(record, supervisor, self.bus, catch_up_from)
        self.hosted[record.id] = hosted
        logs, _ = self.left.pop(record.id, ([], None))
        supervisor.logs.extend(logs)  # the earlier runs' lines first, as before the stop
        if finished is not None:
            supervisor.finished(finished)
            return
        if entry is None:
            why = f"blueprint {record.blueprint!r} is not available"
            supervisor.last_error = why
            self.reports.events(record, [("failed", why, time.time_ns(), {})])
            return
        hosted.start()

    async def _unhost(self, processor_id: int) -> None:
        hosted = self.hosted.pop(processor_id, None)
        if hosted is not None:
            await hosted.stop()
            sup = hosted.supervisor
            self.left[processor_id] = (list(sup.logs), sup.last_error)

    async def _apply(self, record: ProcessorRecord, old: ProcessorSpec, new: ProcessorSpec) -> bool:
        if new.enabled:  # its library FMU's file (if it uses one), found before it starts
            await self.lib.prepare([record])
        hosted = self.hosted.get(record.id)
        if hosted is None or not new.enabled or new.source != old.source:
            await self._unhost(record.id)
            if not new.enabled:
                await self._forget_position(record.id)
            if new.enabled and await self._may_run(record.id):
                self._host(record)
            return False
        hosted.record = record
        params_only = old.model_dump(exclude={"params"}) == new.model_dump(exclude={"params"})
        config = self._worker_config(record, self.catalog.get(record.blueprint))
        return await hosted.supervisor.reconfigure(config, params_only)

    def _worker_config(self, record: ProcessorRecord, entry: Entry | None) -> WorkerConfig:
        spec = spec_of(record)
        files = self.data_dir / "fmus" / str(record.twin_id)
        params, files = self.lib.worker_files(record.id, spec.params, files)
        # a Python FMU's own env: its processor's requirements, and its library asset's
        wanted = [*spec.python_requirements, *self.lib.requirements(record.id)]
        return WorkerConfig(
            processor_id=record.id,
            name=record.name,
            twin=record.twin_slug,
            ref=entry.ref if entry else {},
            params=params,
            inputs={k: v.model_dump() for k, v in spec.input_maps().items()},
            rates=spec.rates.model_dump(),
            files=files,
            workdir=self.data_dir / "processors" / str(record.id),
            memory_limit_bytes=spec.memory_limit_mb * 2**20,
            batch_timeout_s=spec.batch_timeout_s,
            interpreter=partial(self.envs.python, wanted) if wanted else None,
        )

    def _twins_deleted(self, twin_ids: list[int]) -> None:
        gone = [pid for pid, h in self.hosted.items() if h.record.twin_id in twin_ids]
        for pid in gone:
            self.reports.spawn(self._unhost(pid))
        self.reports.spawn(self.lib.release(self.lib.of_twins(twin_ids)))

    # -- checks -----------------------------------------------------------------------------

    def _checked(self, body: dict[str, Any]) -> ProcessorSpec:
        return checked_spec(body, self.catalog)

    def _check_room(self) -> None:
        if len(self.hosted) >= self.max_running:
            raise ConflictError(
                f"this server runs at most {self.max_running} processors at once "
                "(TWINLINK_MAX_PROCESSORS); stop or delete one first"
            )

    async def _find(
        self, principal: Principal, slug: str, name: str, needed: str
    ) -> ProcessorRecord:
        record = await stored_processor(self.registry, self.store, principal, slug, name, needed)
        hosted = self.hosted.get(record.id)
        return hosted.record if hosted else record
