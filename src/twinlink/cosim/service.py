"""Co-simulations made through the API: created from an uploaded file or folder (kept in
data_dir/cosims/<id>/, its FMUs resolved and inspected: bundle.py), run in a process of
their own (jobs.py), their results in outputs.csv and, with a twin, in its history.

Who: a signed-in user creates one; its owner and admins see, start, stop and delete it.
Writing results into a twin's history needs the editor role on that twin (as changing its
processors does), checked at create and again at each start. FMU files inside an upload are
native code that will run on the server: they need the right to upload FMUs
(TWINLINK_FMU_UPLOADERS). A stop of the server stops the runs (state `stopped`); a crash's
`running` records are failed at the next start.
"""

from __future__ import annotations

import asyncio
import contextlib
import errno
import logging
import secrets
import shutil
import time
from collections.abc import AsyncIterator
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import Any, cast

from twinlink.auth.rights import Principal, has_role
from twinlink.config import Settings
from twinlink.domain.cosims import CosimRecord
from twinlink.domain.errors import (
    ConflictError,
    ForbiddenError,
    InvalidInputError,
    NotFoundError,
    StorageFullError,
    TwinlinkError,
)
from twinlink.domain.records import FmuRecord, TwinRecord, User
from twinlink.ingest.service import IngestService
from twinlink.library.service import LibraryService
from twinlink.processors.fmus import FmuService
from twinlink.registry.service import RegistryService
from twinlink.store.base import MetadataStore

from . import bundle as bundles
from . import params
from .jobs import CosimJob, End, Format, JobSpec, Mode, Rows
from .outputs import HistoryOutput
from .recovery import gone_nodes, kill_leftover, note_worker
from .resultfile import read_columns
from .upload import receive

_NATIVE = "FMU files, native code that would run on the server"
_INSTALLS = "python_requirements, packages pip would install (and run the code of) on the server"
log = logging.getLogger("twinlink.cosim")

INTERRUPTED = "the server stopped while this co-simulation ran; start it again"
SAVE_EVERY_S = 1.0  # a running co-simulation's progress is saved at most this often
RESULTS_DIR = "results"
RESULTS = f"{RESULTS_DIR}/outputs.csv"


@dataclass(frozen=True, slots=True)
class CosimSettings:
    root: Path  # data_dir/cosims
    max_bytes: int  # of an upload, and of its unpacked files
    fmu_uploaders: str = "admins"  # who may upload FMUs (in a folder too)
    node: str = "local"  # this node, in the records of the runs it runs
    shared: bool = False  # other nodes share the store (PostgreSQL)
    max_running: int = 8  # runs at once on this node

    @classmethod
    def of(cls, settings: Settings, node: str, shared: bool) -> CosimSettings:
        """As the server's settings have them: data_dir/cosims, the limits."""
        return cls(settings.data_dir / "cosims", settings.cosim_max_mb * 2**20,
                   settings.fmu_uploaders, node, shared, settings.max_cosims)  # fmt: skip


@dataclass(slots=True)
class _Running:
    record: CosimRecord
    output: HistoryOutput | None
    job: CosimJob = field(init=False)
    task: asyncio.Task[None] | None = None
    saved_at: float = 0.0


class CosimService:
    def __init__(
        self,
        store: MetadataStore,
        registry: RegistryService,
        ingest: IngestService,
        fmus: FmuService,
        library: LibraryService | None,
        settings: CosimSettings,
    ) -> None:
        self.store = store
        self.registry = registry
        self.ingest = ingest
        self.fmus = fmus
        self.library = library
        self.settings = settings
        self._running: dict[int, _Running] = {}
        # One start (or delete) at a time: two starts of one co-simulation run it once.
        self._changing = asyncio.Lock()

    def folder(self, cosim_id: int) -> Path:
        return self.settings.root / str(cosim_id)

    # -- life of the service ---------------------------------------------------------------

    async def open(self) -> None:
        """Fail the runs a server that stopped (or crashed) left `running`: on the only node
        every one; with a shared store, those of this host's nodes that are gone."""
        self.settings.root.mkdir(parents=True, exist_ok=True)
        nodes: list[str] | None = None
        if self.settings.shared:
            running = await self.store.list_cosims("running")
            nodes = gone_nodes([r.node for r in running if r.node])
        failed = await self.store.fail_running_cosims(nodes, INTERRUPTED, time.time_ns())
        for record in failed:  # a worker a killed server left behind ends with it
            await asyncio.to_thread(kill_leftover, self.folder(record.id) / RESULTS_DIR)
        if failed:
            log.warning("co-simulations interrupted by a stop", extra={
                "event": "cosims_interrupted", "cosims": [r.id for r in failed]})  # fmt: skip
        for leftover in self.settings.root.glob(".incoming-*"):  # creates a crash cut off
            await asyncio.to_thread(shutil.rmtree, leftover, True)

    async def close(self) -> None:
        """Stop this node's runs (each `stopped`, its rows so far kept) and wait for them."""
        running = list(self._running.values())
        await asyncio.gather(*(r.job.stop() for r in running), return_exceptions=True)
        await asyncio.gather(*(r.task for r in running if r.task), return_exceptions=True)

    # -- reading ---------------------------------------------------------------------------

    async def list_cosims(self, principal: Principal) -> list[CosimRecord]:
        user = _signed_in(principal)
        records = await self.store.list_cosims()
        return [self._live(r) for r in records if principal.is_admin or r.owner_id == user.id]

    async def get(self, principal: Principal, cosim_id: int) -> CosimRecord:
        user = _signed_in(principal)
        record = await self.store.get_cosim(cosim_id)
        if record is None or not (principal.is_admin or record.owner_id == user.id):
            raise NotFoundError(f"no co-simulation {cosim_id}")
        return self._live(record)

    def _live(self, record: CosimRecord) -> CosimRecord:
        """The record as this node's run has it now (progress is saved now and then)."""
        running = self._running.get(record.id)
        return running.record if running is not None else record

    async def owner_name(self, record: CosimRecord) -> str | None:
        user = await self.store.get_user(record.owner_id) if record.owner_id else None
        return user.username if user is not None else None

    def results_path(self, record: CosimRecord) -> Path:
        return self.folder(record.id) / RESULTS

    async def results(self, principal: Principal, cosim_id: int, max_points: int) -> Any:
        record = await self.get(principal, cosim_id)
        return await asyncio.to_thread(read_columns, self.results_path(record), max_points)

    # -- create and delete -----------------------------------------------------------------

    async def create(
        self,
        principal: Principal,
        body: AsyncIterator[bytes],
        content_type: str,
        *,
        name: str | None = None,
        twin: str | None = None,
        mode: str = "batch",
        factor: float = 1.0,
        prefix: str = "",
        stream: str | None = None,
    ) -> CosimRecord:
        user = _signed_in(principal)
        record = CosimRecord(
            id=0, name=params.check_name(name), owner_id=user.id, twin=twin,
            prefix=params.check_prefix(prefix), stream=params.check_stream(stream),
            mode=params.check_mode(mode), factor=params.check_factor(factor), state="created",
            format="", document="", created_ns=time.time_ns(),
        )  # fmt: skip
        twin_record = await self._writable_twin(principal, twin) if twin else None
        incoming = self.settings.root / f".incoming-{secrets.token_hex(8)}"
        try:
            made = await self._bundle(principal, body, content_type, incoming, twin_record)
            record.format, record.document = made[0], made[1]
            record.fmus, record.system = made[2].fmus, made[2].view
            record = await self.store.create_cosim(record)
            await asyncio.to_thread(incoming.rename, self.folder(record.id))
        except BaseException as err:
            await asyncio.to_thread(shutil.rmtree, incoming, True)
            if isinstance(err, OSError) and err.errno == errno.ENOSPC:
                raise StorageFullError("the server's disk is full; nothing was kept") from err
            raise
        log.info("co-simulation created", extra={"event": "cosim_created", "cosim": record.id})
        return record

    async def _bundle(
        self,
        principal: Principal,
        body: AsyncIterator[bytes],
        content_type: str,
        folder: Path,
        twin: TwinRecord | None,
    ) -> tuple[str, str, bundles.Bundle]:
        self.settings.root.mkdir(parents=True, exist_ok=True)
        received = await receive(body, content_type, folder, self.settings.max_bytes)
        system = await asyncio.to_thread(bundles.read_system, folder, received)
        if any(i.python_requirements for i in system.instances):  # pip runs packages' code
            self._check_may_upload_fmus(principal, twin is not None, _INSTALLS)
        sources = bundles.Sources(principal, self.library)
        if twin is not None:
            sources.twin, sources.twin_fmus = twin.slug, lambda: self._twin_fmus(twin)
        made = await bundles.resolve(folder, received, system, sources)
        if any(f["source"] == "upload" for f in made.fmus.values()):
            self._check_may_upload_fmus(principal, twin is not None)
        document = bundles.shown(str(folder / received.document), folder)
        await asyncio.to_thread(bundles.inspect, made, folder, document)
        received = await asyncio.to_thread(bundles.merge_settings, folder, received)
        return received.format, received.document, made

    async def _twin_fmus(self, twin: TwinRecord) -> tuple[list[FmuRecord], Path]:
        return await self.store.list_fmus(twin.id), self.fmus.folder(twin.id)

    def _check_may_upload_fmus(
        self, principal: Principal, editor_of_twin: bool, what: str = _NATIVE
    ) -> None:
        if principal.is_admin or (self.settings.fmu_uploaders == "editors" and editor_of_twin):
            return
        raise ForbiddenError(
            f"the upload holds {what}: only admins send them here (TWINLINK_FMU_UPLOADERS="
            "editors lets a twin's editors, with ?twin=)"
            + (
                "; or name FMUs uploaded to the twin, or library models (lib:...)"
                if what == _NATIVE
                else ""
            )
        )

    async def _writable_twin(self, principal: Principal, slug: str) -> TwinRecord:
        twin, role = await self.registry.require_twin(principal, slug)
        if not has_role(principal, role, "editor"):
            raise ForbiddenError(
                f"writing co-simulation results into the streams of {slug!r} needs the "
                "editor role on it"
            )
        return twin

    async def delete(self, principal: Principal, cosim_id: int) -> None:
        async with self._changing:
            record = await self.get(principal, cosim_id)
            if record.state == "running":
                raise ConflictError(f"co-simulation {cosim_id} is running: stop it first")
            await self.store.delete_cosim(cosim_id)
            await asyncio.to_thread(shutil.rmtree, self.folder(cosim_id), True)

    # -- runs ------------------------------------------------------------------------------

    async def start(
        self,
        principal: Principal,
        cosim_id: int,
        mode: str | None = None,
        factor: float | None = None,
    ) -> CosimRecord:
        """Run it (again: an ended run's results are replaced); 409 while it runs."""
        async with self._changing:
            return await self._start(principal, cosim_id, mode, factor)

    async def _start(
        self, principal: Principal, cosim_id: int, mode: str | None, factor: float | None
    ) -> CosimRecord:
        record = await self.get(principal, cosim_id)
        if record.state == "running":
            raise ConflictError(f"co-simulation {cosim_id} is running already")
        if len(self._running) >= self.settings.max_running:
            raise ConflictError(
                f"{len(self._running)} co-simulations run on this server already, its limit "
                "(max_cosims): stop one, or start this one when one has ended"
            )
        record.mode = params.check_mode(mode) if mode is not None else record.mode
        record.factor = params.check_factor(factor) if factor is not None else record.factor
        _check_runnable(record)
        output = None
        if record.twin:
            twin = await self._writable_twin(principal, record.twin)
            output = HistoryOutput(self.ingest, twin.id, twin.slug, record.stream,
                                   record.prefix, f"cosim:{record.id}")  # fmt: skip
        folder = self.folder(record.id)
        csv = folder / RESULTS
        await asyncio.to_thread(_fresh, csv)
        record.state, record.progress, record.sim_time, record.message = "running", 0.0, None, ""
        record.columns, record.rows, record.node = [], 0, self.settings.node
        record.started_ns, record.ended_ns = time.time_ns(), None
        spec = JobSpec(
            document=folder / record.document, format=cast(Format, record.format),
            fmu_paths={ref: folder / f["path"] for ref, f in record.fmus.items()}, csv=csv,
            mode=cast(Mode, record.mode), factor=record.factor, stream=output is not None,
            envs_dir=self.settings.root.parent / "fmu-envs",  # shared with FMU processors
        )  # fmt: skip
        running = _Running(record, output)
        running.job = CosimJob(spec, on_columns=partial(self._columns, running),
                               on_progress=partial(self._progress, running),
                               on_rows=partial(self._rows, running))  # fmt: skip
        await self.store.save_cosim(record)
        self._running[record.id] = running
        await running.job.start()
        running.task = asyncio.create_task(self._follow(running), name=f"cosim-{record.id}")
        with contextlib.suppress(OSError):  # only a killed server's next start needs it
            await asyncio.to_thread(note_worker, csv.parent, running.job.pid)
        log.info("co-simulation started", extra={"event": "cosim_started", "cosim": record.id,
                                                 "mode": record.mode})  # fmt: skip
        return record

    async def stop(self, principal: Principal, cosim_id: int) -> CosimRecord:
        """Stop a run after its current step (its rows so far kept); an ended one is fine."""
        record = await self.get(principal, cosim_id)
        if record.state != "running":
            return record
        running = self._running.get(cosim_id)
        if running is None:
            raise ConflictError(
                f"co-simulation {cosim_id} runs on another node ({record.node}): stop it there"
            )
        await running.job.stop()
        if running.task is not None:
            await asyncio.shield(running.task)
        return running.record

    def _columns(self, running: _Running, columns: list[str]) -> None:
        running.record.columns = columns
        if running.output is not None:
            running.output.columns(columns)

    async def _progress(self, running: _Running, fraction: float, sim_time: float) -> None:
        running.record.progress, running.record.sim_time = fraction, sim_time
        now = time.monotonic()
        if now - running.saved_at >= SAVE_EVERY_S:
            running.saved_at = now
            with contextlib.suppress(TwinlinkError):  # saved again at its end
                await self.store.save_cosim(running.record)

    async def _rows(self, running: _Running, rows: Rows) -> None:
        running.record.rows += len(rows)
        if running.output is not None:
            await running.output.rows(rows)

    async def _follow(self, running: _Running) -> None:
        record = running.record
        end: End = "failed"
        message = "the server stopped following this run"
        try:
            end, message = await running.job.wait()
        finally:
            record.state, record.message, record.ended_ns = end, message, time.time_ns()
            if end == "finished":
                record.progress = 1.0
            if running.output is not None and running.output.failed:
                record.message = "; ".join(m for m in (message, running.output.failed) if m)
            record.rows = await asyncio.to_thread(_count_rows, self.folder(record.id) / RESULTS)
            with contextlib.suppress(TwinlinkError):  # a store away: the next start fails it
                await self.store.save_cosim(record)
            self._running.pop(record.id, None)
            log.info("co-simulation ended", extra={"event": "cosim_ended", "cosim": record.id,
                                                   "end": end})  # fmt: skip


def _signed_in(principal: Principal) -> User:
    if principal.user is None:
        raise ForbiddenError("co-simulations are for signed-in users")
    return principal.user


def _check_runnable(record: CosimRecord) -> None:
    system = record.system
    if system.get("loops"):
        loops = "; ".join(" -> ".join([*loop, loop[0]]) for loop in system["loops"])
        raise InvalidInputError(
            f"the system has algebraic loops, which a fixed-point master cannot step: {loops}; "
            "break each (a delay, or an FMU whose output does not depend on its input at once)"
        )
    if record.mode == "batch" and system.get("end_time") is None:
        raise InvalidInputError(
            "the system has no end time: a batch run needs one (Maestro's endTime, the YAML "
            "form's end_time, the SSP's DefaultExperiment stopTime); or start it with "
            '{"mode": "realtime"}, which runs until stopped'
        )


def _fresh(csv: Path) -> None:
    csv.parent.mkdir(parents=True, exist_ok=True)
    csv.unlink(missing_ok=True)


def _count_rows(csv: Path) -> int:
    try:
        with csv.open("rb") as file:
            return max(sum(1 for _ in file) - 1, 0)
    except FileNotFoundError:
        return 0
