"""`command` ops on a live connection: commands sent by scripts and the web UI over the socket
they already hold, with the same rights and states as POST /api/v1/twins/{slug}/commands.

Each op runs in a task of its own, so one that waits for a slow device does not hold up the
next; at most `MAX_COMMANDS` run at once, and the connection stops reading the client while
that many are under way (back-pressure, as with unread answers). An op's answer is a `command`
message once the command is finished (or at once without `wait`), or an `error` message
with the HTTP status the same refusal would have.
"""

from __future__ import annotations

import asyncio
import logging
from typing import Any, Protocol

from twinlink.auth.rights import Principal
from twinlink.domain.commands import CommandRecord
from twinlink.domain.errors import TwinlinkError
from twinlink.live import protocol
from twinlink.live.outbox import Outbox
from twinlink.live.protocol import CommandRequest, LiveMessageError

log = logging.getLogger("twinlink.live")


class CommandSender(Protocol):
    async def send(
        self,
        principal: Principal,
        slug: str,
        name: str,
        args: dict[str, Any] | None = None,
        device: str | None = None,
        timeout_s: float | None = None,
        queue: bool = False,
        wait: bool = True,
    ) -> CommandRecord: ...


class CommandOps:
    """The command ops of one connection under way."""

    def __init__(
        self, sender: CommandSender, outbox: Outbox, limit: int = protocol.MAX_COMMANDS
    ) -> None:
        self.sender = sender
        self.outbox = outbox
        self._room = asyncio.Semaphore(limit)
        self._tasks: set[asyncio.Task[None]] = set()

    def __len__(self) -> int:
        return len(self._tasks)

    async def start(self, principal: Principal, request: CommandRequest) -> None:
        """Start the op; waits while `limit` ops are under way."""
        await self._room.acquire()
        task = asyncio.create_task(self._run(principal, request))
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    async def _run(self, principal: Principal, request: CommandRequest) -> None:
        try:
            record = await self.sender.send(
                principal, request.twin, request.name, request.args, request.device,
                request.timeout_s, request.queue, request.wait,
            )  # fmt: skip
        except Exception as err:
            self.outbox.put_control(protocol.error(_refusal(err, request.id)))
        else:
            self.outbox.put_control(protocol.command(request.id, record.view(request.twin)))
        finally:
            self._room.release()

    async def close(self) -> None:
        """The connection ended: stop waiting. Commands already sent go on (their state is
        in the command log); ops still being checked are not sent."""
        tasks = list(self._tasks)
        for task in tasks:
            task.cancel()
        if tasks:
            await asyncio.gather(*tasks, return_exceptions=True)


def _refusal(err: Exception, op_id: str) -> LiveMessageError:
    if isinstance(err, TwinlinkError) and err.status != 500:  # an answer of its own
        return LiveMessageError(str(err), "command", op_id, err.status)
    log.error("a command op failed", exc_info=err, extra={"event": "live_command_failed"})
    return LiveMessageError(
        "internal error; the command may not have been sent", "command", op_id, 500
    )
