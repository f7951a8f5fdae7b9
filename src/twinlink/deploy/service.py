"""Deployments: a twin package planned, applied all or nothing, and taken through its lifecycle
(`planned → created → running ⇄ stopped → terminated`, `failed` for a create that was undone).

Deploying needs a signed-in user who may read the package; the twin is theirs (the owner
role). Who may see and change a deployment: access.py."""

from __future__ import annotations

import asyncio
import logging
import time
from dataclasses import dataclass
from typing import Any

from twinlink.auth.rights import Principal
from twinlink.auth.vault import Vault
from twinlink.deploy import ending
from twinlink.deploy import secrets as sealing
from twinlink.deploy.access import check_may_change, may_see, signed_in
from twinlink.deploy.apply import Parts
from twinlink.deploy.loading import Library, Loaded, Where, check_name, load, package_ref
from twinlink.deploy.phases import PhaseRuns, Phases
from twinlink.deploy.plan import MASK, Plan, canonical, plan_change, plan_create
from twinlink.deploy.runs import RunTarget
from twinlink.domain.deployments import DeploymentRecord
from twinlink.domain.errors import (
    ConflictError,
    ForbiddenError,
    InvalidInputError,
    NotFoundError,
    TwinlinkError,
)
from twinlink.domain.records import User
from twinlink.store.base import MetadataStore

log = logging.getLogger("twinlink.deploy")
# Who undoes a create cut off by a crash, at the next start: nobody is signed in then.
SYSTEM = Principal(User(id=0, username="twinlink", is_admin=True, groups=[], created_ns=0))
# On a shared store: a create in `applying` that has not moved for 10 minutes was cut off.
STALE_AFTER_NS = 600 * 10**9


@dataclass(slots=True)
class Created:
    record: DeploymentRecord
    plan: Plan
    device_tokens: dict[str, str]


class DeploymentService:
    def __init__(
        self,
        store: MetadataStore,
        parts: Parts,
        library: Library | None,
        vault: Vault,
        server_url: str,
        runs: PhaseRuns | None = None,
        shared_store: bool = False,
    ) -> None:
        self.store = store
        self.parts = parts
        self.library = library
        self.vault = vault
        self.server_url = server_url.rstrip("/")
        self.phases = Phases(library)
        self.phases.runs = runs
        # One change of deployments at a time: a plan is applied against what it read.
        self.lock = asyncio.Lock()
        # On a store other nodes share, one of them may be applying right now: only a create
        # that has not moved for this long was cut off (each step is saved as it is made).
        self.stale_after_ns = STALE_AFTER_NS if shared_store else 0

    async def open(self) -> None:
        """Undo the creates a crash cut off (deployments left `applying`)."""
        now = time.time_ns()
        for record in await self.store.list_deployments("applying"):
            if now - record.updated_ns < self.stale_after_ns:
                continue  # another node's, going on (a node that starts later undoes it)
            log.warning("deployment %s was cut off while applying; undoing it", record.name,
                        extra={"event": "deployment_recovered"})  # fmt: skip
            await self._fail(record, "the server stopped while this deployment was applied; "
                             "what it had made was removed at the next start")  # fmt: skip

    @property
    def runs(self) -> PhaseRuns | None:
        """The lifecycle runs, when set up (app.py sets them once both services exist)."""
        return self.phases.runs

    @runs.setter
    def runs(self, runs: PhaseRuns | None) -> None:
        self.phases.runs = runs

    async def close(self) -> None:
        await self.phases.close()

    # -- reading ---------------------------------------------------------------------------

    async def list(self, principal: Principal) -> list[DeploymentRecord]:
        reg = self.parts.registry
        return [r for r in await self.store.list_deployments() if await may_see(reg, principal, r)]

    async def get(self, principal: Principal, name: str) -> DeploymentRecord:
        record = await self.store.find_deployment(name)
        if record is None or not await may_see(self.parts.registry, principal, record):
            raise NotFoundError(f"no deployment {name!r}")
        return record

    async def _changeable(
        self, principal: Principal, name: str, ended: bool = False
    ) -> DeploymentRecord:
        record = await self.get(principal, name)
        await check_may_change(self.parts.registry, principal, record, ended=ended)
        return record

    # -- create ----------------------------------------------------------------------------

    async def _load(self, principal: Principal, ref: str, parameters: Any, name: str) -> Loaded:
        if self.library is None:
            raise TwinlinkError("the library is not available on this server")
        where = Where(name, self.parts.registry.canonical_url(name), self.server_url)
        loaded = await load(self.library, principal, ref, parameters, where)
        for resource in loaded.resources:
            self.parts.check(resource)
        return loaded

    async def plan(
        self, principal: Principal, package: str, name: Any, parameters: Any, scope: str | None
    ) -> Plan:
        """What creating the deployment would make; nothing is stored."""
        signed_in(principal)
        name = check_name(name)
        loaded = await self._load(principal, package_ref(package, scope), parameters, name)
        return plan_create(loaded.resources, loaded.hidden)

    async def create(
        self,
        principal: Principal,
        package: str,
        name: Any,
        parameters: Any,
        scope: str | None,
        *,
        start: bool = False,
        planned: bool = False,
    ) -> Created:
        user = signed_in(principal)
        name = check_name(name)
        loaded = await self._load(principal, package_ref(package, scope), parameters, name)
        if not planned:
            self.phases.check(principal, user.id, loaded, "create", *(["execute"] * start))
        async with self.lock:
            await self._name_free(name)
            now = time.time_ns()
            shown_params, secret = sealing.split(loaded.parameters, loaded.secret_names)
            record = await self.store.create_deployment(
                DeploymentRecord(
                    id=0,
                    name=name,
                    package=loaded.pinned,
                    package_ref=package,
                    parameters=shown_params,
                    state="planned" if planned else "applying",
                    twin=name,
                    created_by=user.id,
                    created_ns=now,
                    updated_ns=now,
                    secrets=sealing.seal(self.vault, sealing.Sealed(parameters=secret)),
                )
            )
            try:
                await self._hold(record, loaded)
            except BaseException as err:
                await self._fail(record, f"holding the package's library versions failed: {err}")
                raise
            tokens: dict[str, str] = {}
            if not planned:
                tokens = await self._apply_create(principal, record, loaded, start)
        return Created(record, plan_create(loaded.resources, loaded.hidden), tokens)

    async def create_planned(self, principal: Principal, name: str) -> Created:
        """Apply a deployment stored as `planned`."""
        record = await self.get(principal, name)
        if record.state != "planned":
            raise ConflictError(f"deployment {name!r} is {record.state}, not planned")
        if not (principal.is_admin or (principal.user and principal.user.id == record.created_by)):
            raise ForbiddenError(f"only who planned {name!r} (or an admin) may create it")
        loaded = await self._load(
            principal, record.package, sealing.parameters_of(self.vault, record), name
        )
        self.phases.check(principal, record.created_by, loaded, "create")
        async with self.lock:
            await self._name_free(name, twin_only=True)
            record.state = "applying"
            await self.save(record)
            tokens = await self._apply_create(principal, record, loaded, start=False)
        return Created(record, plan_create(loaded.resources, loaded.hidden), tokens)

    async def _name_free(self, name: str, twin_only: bool = False) -> None:
        existing = await self.store.find_deployment(name)
        if not twin_only and existing is not None and existing.live:
            raise ConflictError(f"a deployment named {name!r} exists already ({existing.state})")
        if await self.parts.registry.get_twin(name) is not None:
            raise ConflictError(
                f"a twin {name!r} exists already; a deployment makes its own twin: choose "
                "another name"
            )

    async def _hold(self, record: DeploymentRecord, loaded: Loaded) -> None:
        if self.library is not None:
            await self.library.hold(holder(record), [loaded.resolved, *loaded.assets.values()])

    async def _apply_create(
        self, principal: Principal, record: DeploymentRecord, loaded: Loaded, start: bool
    ) -> dict[str, str]:
        """Make every resource, journaled; undone whole when any step fails."""
        tokens: dict[str, str] = {}
        step = "the twin"
        try:
            for resource in loaded.resources:
                step = f"{resource.type} {resource.name!r}"
                token = await self.parts.make(principal, record.name, resource, running=start)
                record.journal.append(self.parts.entry(resource, loaded.hidden))
                if token is not None:
                    tokens[resource.name] = token
                    record.secrets = sealing.with_tokens(self.vault, record, tokens)
                await self.save(record)
        except BaseException as err:
            await self._fail(record, f"making {step} failed: {err}; what was made before it "
                             "was removed")  # fmt: skip
            raise
        record.state = "running" if start else "created"
        await self.save(record)
        await self.phases.start(principal, record, loaded, "create", tokens)
        if start:
            await self.phases.start(principal, record, loaded, "execute", tokens)
        return tokens

    async def _fail(self, record: DeploymentRecord, error: str) -> None:
        async def saved() -> None:
            await self.save(record)

        await self.parts.undo(SYSTEM, record.twin, record.journal, saved)
        record.state, record.error, record.secrets = "failed", error, None
        await self.save(record)
        await self.release(record)

    async def release(self, record: DeploymentRecord) -> None:
        if self.library is not None:
            await self.library.release(holder(record))

    async def save(self, record: DeploymentRecord) -> None:
        record.updated_ns = time.time_ns()
        await self.store.save_deployment(record)

    async def run_phase(self, principal: Principal, name: str, phase: str) -> Any:
        """Start a run of any phase of the deployment's package (POST .../runs); the run."""
        record = await self.get(principal, name)
        if self.runs is None:
            raise TwinlinkError("lifecycle runs are not set up on this server")
        if not record.live or record.state == "planned":
            raise ConflictError(f"deployment {name!r} is {record.state}: it has nothing to run")
        loaded = await self._load(
            SYSTEM, record.package, sealing.parameters_of(self.vault, record), record.name
        )
        target = self.phases.target(record, loaded, self.device_tokens(record))
        return await self.runs.start(principal, target, phase)

    async def target_of(self, deployment_id: int) -> RunTarget:
        """The run target of a deployment (a run queued on another node is rebuilt so)."""
        record = await self.store.get_deployment(deployment_id)
        if record is None or self.library is None:
            raise NotFoundError(f"no deployment {deployment_id}")
        loaded = await self._load(
            SYSTEM, record.package, sealing.parameters_of(self.vault, record), record.name
        )
        return self.phases.target(record, loaded, self.device_tokens(record))

    # -- lifecycle -------------------------------------------------------------------------

    async def start(self, principal: Principal, name: str) -> DeploymentRecord:
        """Enable its processors and connectors and run `execute`; started already is fine."""
        record = await self._changeable(principal, name)
        if record.state == "running":
            return record
        if record.state not in ("created", "stopped"):
            raise ConflictError(f"deployment {name!r} is {record.state}; create it first")
        loaded = await self.pinned(record)
        self.phases.check(principal, record.created_by, loaded, "execute")
        async with self.lock:
            await self.parts.set_running(principal, record.twin, record.journal, True)
            record.state = "running"
            await self.save(record)
        await self.phases.start(principal, record, loaded, "execute", self.device_tokens(record))
        return record

    async def stop(self, principal: Principal, name: str) -> DeploymentRecord:
        """Disable its processors and connectors and end a running `execute`; the twin stays."""
        record = await self._changeable(principal, name)
        if record.state in ("stopped", "created"):
            return record
        if record.state != "running":
            raise ConflictError(f"deployment {name!r} is {record.state}, not running")
        async with self.lock:
            await self.phases.cancel(record.id, "execute")
            await self.parts.set_running(principal, record.twin, record.journal, False)
            record.state = "stopped"
            await self.save(record)
        return record

    async def terminate(self, principal: Principal, name: str, purge: bool) -> DeploymentRecord:
        """End the deployment (ending.py): its `terminate` script, what it made removed (the
        twin too when `purge`), `clean`, its working folder removed, its holds released; the
        deployment `terminated` at once, the scripts in the background."""
        record = await self._changeable(principal, name, ended=True)
        return await ending.terminate(self, principal, record, purge)

    async def reconfigure(
        self,
        principal: Principal,
        name: str,
        parameters: Any,
        package: str | None,
        dry_run: bool,
    ) -> Created:
        """Change parameters (those not given are kept) and/or the package version: the plan
        from what the deployment made to what it would make now, applied unless `dry_run`.
        Unchanged resources are not touched; a changed processor is updated in place."""
        record = await self._changeable(principal, name)
        if not record.live:
            raise ConflictError(f"deployment {name!r} is {record.state}: deploy it anew instead")
        if parameters is not None and not isinstance(parameters, dict):
            raise InvalidInputError("`parameters` is a JSON object of the parameters to change")
        sealed = sealing.unseal(self.vault, record)
        given = {
            k: v
            for k, v in (parameters or {}).items()
            if not (k in sealed.parameters and v == MASK)
        }  # a secret shown back: kept
        params = {**record.parameters, **sealed.parameters, **given}  # fmt: skip
        ref = package_ref(package, None) if package else record.package
        loaded = await self._load(principal, ref, params, name)
        fingerprints = {r.key: self.parts.fingerprint(canonical(r.spec)) for r in loaded.resources}
        plan = plan_change(record.journal, loaded.resources, fingerprints, loaded.hidden)
        if dry_run or record.state == "planned":
            if not dry_run:
                sealing.set_parameters(self.vault, record, loaded.parameters, loaded.secret_names)
                record.package = loaded.pinned
                record.package_ref = package or record.package_ref
                await self.save(record)
            return Created(record, plan, {})
        async with self.lock:

            async def saved() -> None:
                await self.save(record)

            running = record.state == "running"
            try:
                tokens = await self.parts.apply_plan(
                    principal, record.twin, plan, record.journal, running, saved
                )
            except TwinlinkError as err:
                record.error = f"reconfiguring stopped part way (resources list what is): {err}"
                await self.save(record)
                raise
            record.error = None
            sealing.set_parameters(self.vault, record, loaded.parameters, loaded.secret_names)
            record.secrets = sealing.with_tokens(self.vault, record, tokens)
            record.package = loaded.pinned
            record.package_ref = package or record.package_ref
            await self.save(record)
            await self.release(record)
            await self._hold(record, loaded)
        return Created(record, plan, tokens)

    async def pinned(self, record: DeploymentRecord) -> Loaded | None:
        """The deployment's package as it was deployed, for its lifecycle phases (read with
        the server's rights: the version is pinned and held for the deployment)."""
        if self.runs is None:
            return None
        return await self._load(
            SYSTEM, record.package, sealing.parameters_of(self.vault, record), record.name
        )

    def device_tokens(self, record: DeploymentRecord) -> dict[str, str]:
        """The deployment's device tokens (for its lifecycle runs); never answered by the API."""
        return sealing.unseal(self.vault, record).device_tokens


def holder(record: DeploymentRecord) -> str:
    """The name a deployment holds library versions by."""
    return f"deployment:{record.id}"
