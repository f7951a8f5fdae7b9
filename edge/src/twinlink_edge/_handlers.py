"""Commands and desired properties: the application's handlers, and how they are run.

Async handlers run on the device's event loop; plain functions run in the loop's default
thread pool, so a slow one never stalls the connection and may call the synchronous
`Device` API."""

from __future__ import annotations

import asyncio
import functools
import inspect
import logging
import time
from collections import OrderedDict, deque
from typing import Any, Callable, TypeVar

from ._inbox import HeldCommand, Inbox
from ._protocol import JsonObject, dumps

log = logging.getLogger("twinlink_edge")

CommandHandler = Callable[[JsonObject], Any]  # args -> JSON-able result (or an awaitable)
AnyCommandHandler = Callable[[str, JsonObject], Any]  # name, args -> result
DesiredHandler = Callable[[JsonObject], Any]  # the desired properties that changed
F = TypeVar("F", bound=Callable[..., Any])

_REMEMBERED_COMMANDS = 1000


async def call(handler: Callable[..., Any], *args: Any) -> Any:
    """Run a sync or async handler without blocking the event loop."""
    if inspect.iscoroutinefunction(handler):
        return await handler(*args)
    loop = asyncio.get_running_loop()
    result = await loop.run_in_executor(None, functools.partial(handler, *args))
    if inspect.isawaitable(result):
        result = await result
    return result


class Dispatcher:
    """Runs command handlers (each command in its own task) and desired-property handlers
    (one at a time, in arrival order). Messages for the server go through `send`. With an
    `inbox`, commands without a handler of their own wait there until the program takes
    them (`take`), instead of going to `fallback`."""

    def __init__(self, send: Callable[[str], None]) -> None:
        self._send = send
        self.commands: dict[str, CommandHandler] = {}
        self.fallback: AnyCommandHandler | None = None
        self.inbox: Inbox | None = None
        self.desired_handlers: list[DesiredHandler] = []
        self._tasks: set[asyncio.Future[Any]] = set()
        self._results: OrderedDict[Any, str | None] = OrderedDict()  # id -> result (None: running)
        self._desired: deque[tuple[JsonObject, DesiredHandler | None]] = deque()
        self._desired_task: asyncio.Task[None] | None = None

    def on_command(self, name: str) -> Callable[[F], F]:
        if not isinstance(name, str) or not name:
            raise ValueError("a command name is a non-empty string")

        def register(handler: F) -> F:
            self.commands[name] = handler
            return handler

        return register

    def command(self, msg: JsonObject) -> None:
        """A `command` message: say it arrived, run its handler, send the result. A command
        that arrives again (after a reconnect) is not run twice: its result is sent again."""
        cid = msg.get("id")
        if not isinstance(cid, (str, int)) or isinstance(cid, bool):
            log.warning("a command without an id: %.200s", msg)
            return
        if self.inbox is not None and cid in self.inbox:
            return  # sent again (after a reconnect) while it waits to be taken
        if cid in self._results:
            self._send(dumps({"type": "delivered", "id": cid}))
            done = self._results[cid]
            if done is not None:
                self._send(done)
            return
        name = str(msg.get("name", ""))
        args = msg.get("args")
        args = dict(args) if isinstance(args, dict) else {}
        if self.inbox is not None and name not in self.commands:
            self.inbox.hold(HeldCommand(cid, name, args, time.time_ns()))
            return
        self._send(dumps({"type": "delivered", "id": cid}))
        self._remember(cid, None)
        self._spawn(self._run(cid, name, args))

    def _remember(self, cid: Any, result: str | None) -> None:
        """Keep a command's result (None: still running) for when it arrives again."""
        self._results[cid] = result
        while len(self._results) > _REMEMBERED_COMMANDS:
            self._results.popitem(last=False)

    def take(self) -> list[HeldCommand]:
        """The commands waiting in the inbox, taken by the program: each is answered
        `delivered`, then `succeeded` (taking it is all a program without handlers does)."""
        taken = self.inbox.take() if self.inbox is not None else []
        for command in taken:
            self._send(dumps({"type": "delivered", "id": command.id}))
            self._answer(command.id, {"status": "succeeded"})
        return taken

    def refuse_held(self, reason: str) -> int:
        """Answer every command still in the inbox `failed` with `reason`; how many."""
        held = self.inbox.take() if self.inbox is not None else []
        for command in held:
            log.warning("command %r (%s) %s", command.name, command.id, reason)
            self._answer(command.id, {"status": "failed", "error": reason})
        return len(held)

    def _answer(self, cid: Any, answer: JsonObject) -> None:
        text = dumps({"type": "result", "id": cid, **answer})
        self._remember(cid, text)
        self._send(text)

    async def _run(self, cid: Any, name: str, args: JsonObject) -> None:
        answer: JsonObject = {"type": "result", "id": cid, "status": "failed"}
        if name not in self.commands and self.fallback is None:
            log.warning("command %r (%s): no handler", name, cid)
            answer["error"] = f"no handler for command {name!r}"
        else:
            try:
                if name in self.commands:
                    result = await call(self.commands[name], args)
                else:
                    assert self.fallback is not None
                    result = await call(self.fallback, name, args)
                answer.update(status="succeeded", result=result)
            except Exception as e:  # the handler's failure is the command's, not the device's
                log.warning("command %r (%s) failed", name, cid, exc_info=True)
                answer["error"] = str(e) or type(e).__name__
        text = dumps(answer)
        if cid in self._results:
            self._results[cid] = text
        self._send(text)

    def desired(self, properties: JsonObject, only: DesiredHandler | None = None) -> None:
        """Call the desired-property handlers (or `only` that one) with `properties`."""
        if not self.desired_handlers:
            return
        self._desired.append((properties, only))
        if self._desired_task is None or self._desired_task.done():
            self._desired_task = self._spawn(self._run_desired())

    async def _run_desired(self) -> None:
        while self._desired:
            properties, only = self._desired.popleft()
            for handler in [only] if only is not None else list(self.desired_handlers):
                try:
                    await call(handler, dict(properties))
                except Exception:
                    log.exception("the desired-properties handler %r failed", handler)

    def _spawn(self, coro: Any) -> asyncio.Task[None]:
        task: asyncio.Task[None] = asyncio.ensure_future(coro)
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)
        return task

    async def stop(self) -> None:
        tasks = list(self._tasks)
        for task in tasks:
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)
