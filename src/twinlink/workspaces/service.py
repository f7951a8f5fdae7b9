"""Workspaces: at most one JupyterLab per user, started on demand, stopped on request, when
idle, or with the server.

Each start makes an API token of the user for the workspace (TWINLINK_TOKEN in its kernels),
revoked when it stops; the token's name marks it, so a server that died without stopping
its workspaces revokes the ones left at its next start. The workspaces live in this server
process: on several nodes (or workers), a workspace is reached through the node that
started it (docs/workspaces.md).
"""

from __future__ import annotations

import asyncio
import logging
import time
from collections.abc import Awaitable, Callable
from dataclasses import dataclass, field
from pathlib import Path

import httpx

from twinlink.auth.rights import Principal
from twinlink.auth.service import AuthService
from twinlink.config import Settings
from twinlink.domain.errors import ConflictError, ForbiddenError, NotFoundError, UnavailableError
from twinlink.domain.records import User
from twinlink.workspaces.access import Access
from twinlink.workspaces.folder import environment, prepare
from twinlink.workspaces.process import JupyterProcess, Launch, StartFailed

log = logging.getLogger("twinlink.workspaces")
TOKEN_NAME = "workspace (revoked when it stops)"
SWEEP_MAX_S = 30.0
# Fills a user's library folder at start (library.py): (principal, the folder's library/).
Materializer = Callable[[Principal, Path], Awaitable[None]]


@dataclass(frozen=True, slots=True)
class WorkspaceSettings:
    enabled: bool
    root: Path  # data_dir/workspaces
    server_url: str  # TWINLINK_URL in the workspaces
    idle_s: float
    memory_mb: int
    start_timeout_s: float
    max_running: int

    @classmethod
    def of(cls, settings: Settings) -> WorkspaceSettings:
        return cls(settings.workspaces_enabled, settings.data_dir / "workspaces",
                   settings.base_url, settings.workspace_idle_s, settings.workspace_memory_mb,
                   settings.workspace_start_timeout_s, settings.max_workspaces)  # fmt: skip


@dataclass(slots=True)
class Workspace:
    user: User
    state: str = "stopped"  # starting, running, stopping, stopped, failed
    process: JupyterProcess | None = None
    token_id: int | None = None
    started_ns: int | None = None
    last_activity: float = 0.0  # monotonic s of the last proxied request or frame
    error: str | None = None
    logs: list[str] = field(default_factory=list)  # the last lines of a failed one
    lock: asyncio.Lock = field(default_factory=asyncio.Lock)
    watcher: asyncio.Task[None] | None = None

    def touch(self) -> None:
        self.last_activity = time.monotonic()

    def view(self) -> dict[str, object]:
        idle_s = time.monotonic() - self.last_activity if self.state == "running" else None
        return {
            "user": self.user.username,
            "state": self.state,
            "started_ns": self.started_ns if self.state == "running" else None,
            "idle_s": round(idle_s, 1) if idle_s is not None else None,
            "error": self.error,
            "log": self.logs if self.state == "failed" else [],
        }


class WorkspaceService:
    def __init__(
        self,
        settings: WorkspaceSettings,
        auth: AuthService,
        library: Materializer | None = None,
        shared_store: bool = False,
    ) -> None:
        self.settings = settings
        self.auth = auth
        self.library = library
        self.shared_store = shared_store
        self.access = Access(auth.store)
        self.workspaces: dict[str, Workspace] = {}
        self._sweeper: asyncio.Task[None] | None = None
        # The proxy's connections to the workspaces (a long timeout: a kernel may take
        # minutes to answer a request to restart).
        self.http = httpx.AsyncClient(timeout=httpx.Timeout(600, connect=5, pool=10),
                                      trust_env=False)  # fmt: skip

    async def open(self) -> None:
        if not self.settings.enabled:
            return
        if not self.shared_store:  # on a shared store, other nodes' workspaces use theirs
            await self._revoke_left_tokens()
        self._sweeper = asyncio.create_task(self._sweep())

    async def close(self) -> None:
        """Stop every workspace (their kernels too) and revoke their tokens."""
        if self._sweeper is not None:
            self._sweeper.cancel()
            await asyncio.gather(self._sweeper, return_exceptions=True)
        await asyncio.gather(*(self._stop(ws) for ws in list(self.workspaces.values())))
        await self.http.aclose()

    def require_enabled(self) -> None:
        if not self.settings.enabled:
            raise NotFoundError(
                "workspaces are turned off on this server (TWINLINK_WORKSPACES_ENABLED)"
            )

    def get(self, username: str) -> Workspace | None:
        return self.workspaces.get(username)

    def running(self, username: str) -> Workspace | None:
        ws = self.workspaces.get(username)
        return ws if ws is not None and ws.state == "running" else None

    async def start(self, principal: Principal) -> Workspace:
        """The caller's workspace, started if it is not running (the call waits until it
        answers); UnavailableError saying why when it could not start."""
        self.require_enabled()
        user = principal.user
        assert user is not None
        ws = self.workspaces.setdefault(user.username, Workspace(user))
        async with ws.lock:
            if ws.state == "running":
                ws.touch()
                return ws
            busy = sum(w.state in ("starting", "running") for w in self.workspaces.values())
            if busy >= self.settings.max_running:
                raise ConflictError(
                    f"{busy} workspaces run on this server, the most it allows "
                    "(TWINLINK_MAX_WORKSPACES); try again when one has stopped"
                )
            ws.user = user  # as the caller is now (groups, admin)
            await self._launch(ws, principal)
        return ws

    async def _launch(self, ws: Workspace, principal: Principal) -> None:
        ws.state, ws.error, ws.logs = "starting", None, []
        root = self.settings.root / ws.user.username
        try:
            await asyncio.to_thread(prepare, root, ws.user.username)
            if self.library is not None:
                await self.library(principal, root / "library")
            issued = await self.auth.issue_token(ws.user, TOKEN_NAME, ttl_s=None)
            ws.token_id = issued.record.id
            env = environment(root, self.settings.server_url, issued.token)
            base_url = f"/workspaces/{ws.user.username}/"
            process = JupyterProcess(Launch(base_url, root, env, self.settings.memory_mb))
            try:
                await process.start(self.settings.start_timeout_s)
            finally:
                ws.logs = list(process.logs)
        except BaseException as err:
            ws.state, ws.error = "failed", str(err) or type(err).__name__
            await self._revoke(ws)
            if isinstance(err, StartFailed):
                log.warning(
                    "workspace of %s did not start: %s",
                    ws.user.username,
                    err,
                    extra={"event": "workspace_failed", "user": ws.user.username},
                )
                raise UnavailableError(
                    f"your workspace did not start: {err}; its last log lines are in "
                    "GET /api/v1/workspaces/me. Start it again, or ask an admin"
                ) from err
            raise
        ws.process, ws.state, ws.started_ns = process, "running", time.time_ns()
        ws.touch()
        ws.watcher = asyncio.create_task(self._watch(ws, process))
        log.info(
            "workspace of %s started (pid %d, port %d)",
            ws.user.username,
            process.proc.pid if process.proc else 0,
            process.port,
            extra={"event": "workspace_started", "user": ws.user.username},
        )

    async def _watch(self, ws: Workspace, process: JupyterProcess) -> None:
        """A JupyterLab that ends by itself is shown failed with its last log lines."""
        code = await process.wait()
        if ws.process is not process:
            return  # it was stopped
        ws.process, ws.state, ws.started_ns = None, "failed", None
        ws.error, ws.logs = f"JupyterLab ended with code {code}", list(process.logs)
        self.access.end(ws.user.username)
        log.warning(
            "workspace of %s ended with code %s",
            ws.user.username,
            code,
            extra={"event": "workspace_failed", "user": ws.user.username},
        )
        await process.stop()  # its kernels, if any were left
        await self._revoke(ws)

    async def stop(self, principal: Principal, username: str) -> Workspace:
        """Stop `username`'s workspace (its owner or an admin); its files stay."""
        self.require_enabled()
        if principal.user is None or (
            principal.user.username != username and not principal.is_admin
        ):
            raise ForbiddenError("only its owner or an admin may stop a workspace")
        ws = self.workspaces.get(username)
        if ws is None:
            raise NotFoundError(f"{username} has no workspace on this server")
        await self._stop(ws)
        return ws

    async def _stop(self, ws: Workspace, why: str = "stop") -> None:
        async with ws.lock:
            if why == "idle" and (ws.state != "running" or not self._idle(ws)):
                return  # started again, or used, while the sweep waited for the lock
            process, ws.process = ws.process, None
            self.access.end(ws.user.username)
            if process is not None:
                ws.state = "stopping"
                await process.stop()
                log.info(
                    "workspace of %s stopped (%s)",
                    ws.user.username,
                    why,
                    extra={"event": "workspace_stopped", "user": ws.user.username},
                )
            if ws.watcher is not None:
                await asyncio.gather(ws.watcher, return_exceptions=True)
                ws.watcher = None
            await self._revoke(ws)
            if ws.state != "failed":
                ws.state, ws.started_ns = "stopped", None

    async def _revoke(self, ws: Workspace) -> None:
        token_id, ws.token_id = ws.token_id, None
        if token_id is None:
            return
        try:
            await self.auth.revoke_token(Principal(ws.user), token_id)
        except Exception:  # the store failing at shutdown: the next start revokes it
            log.exception(
                "could not revoke the token of %s's workspace",
                ws.user.username,
                extra={"event": "workspace_token_left"},
            )

    async def _revoke_left_tokens(self) -> None:
        """Tokens of workspaces a server that died did not stop (single node only)."""
        left = [
            t
            for t in await self.auth.store.list_tokens(None)
            if t.name == TOKEN_NAME and t.revoked_ns is None
        ]
        for record in left:
            await self.auth.store.revoke_token(record.id, time.time_ns())
        if left:
            self.auth.forget_cached()

    async def _sweep(self) -> None:
        """Stop the workspaces idle for longer than idle_s."""
        interval = min(SWEEP_MAX_S, max(0.2, self.settings.idle_s / 4))
        while True:
            await asyncio.sleep(interval)
            for ws in list(self.workspaces.values()):
                if ws.state == "running" and self._idle(ws):
                    await self._stop(ws, "idle")

    def _idle(self, ws: Workspace) -> bool:
        return time.monotonic() - ws.last_activity > self.settings.idle_s
