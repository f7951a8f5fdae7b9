"""The live WebSocket's messages: reading what a client sends, building what the server sends.

Every client message is a JSON object with an `op`. A message that cannot be read raises
`LiveMessageError`; the connection answers it with an `error` message and stays open.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import orjson

from twinlink.domain.errors import TwinlinkError
from twinlink.domain.jsontext import JsonTextError, first_big_int, int64_problem, loads
from twinlink.domain.samples import SIGNAL_NAME, STREAM_NAME
from twinlink.live.subscription import Subscription

MAX_CLIENT_MESSAGE = 64 * 1024  # bytes; a subscribe with 1 000 signal names fits easily
MAX_SUBSCRIPTIONS = 100  # per connection
MAX_SIGNALS = 1_000  # per subscription
MAX_ID = 64  # characters of a subscription (or command op) id
MAX_RATE = 1_000_000_000.0  # samples per second; above this max_rate would keep every sample
DEFAULT_STREAM = "telemetry"
MAX_COMMANDS = 256  # command ops of one connection under way at once
OPS = ("subscribe", "unsubscribe", "command", "ping")


class LiveMessageError(TwinlinkError, ValueError):
    """A client message the server cannot act on; answered with an `error` message. Its
    `status` is the HTTP status the same refusal would have: 422 unless given. The message
    shows it only when given (a command op's refusal)."""

    status = 422

    def __init__(
        self, message: str, op: str | None = None, sub: str | None = None, status: int = 0
    ) -> None:
        super().__init__(message)
        self.op = op
        self.sub = sub
        self.shown_status = status  # 0: none shown
        if status:
            self.status = status


@dataclass(frozen=True, slots=True)
class CommandRequest:
    """A `command` op: the fields of POST /api/v1/twins/{twin}/commands, and the op's id."""

    id: str
    twin: str
    name: str
    args: dict[str, Any] | None = None
    device: str | None = None
    timeout_s: float | None = None
    queue: bool = False
    wait: bool = True


@dataclass(frozen=True, slots=True)
class SubscribeRequest:
    id: str
    twin: str
    stream: str
    signals: frozenset[str] | None
    max_rate: float | None


def read_message(raw: str | bytes) -> dict[str, Any]:
    """Parse one client frame into an object with a string `op`."""
    if _size(raw) > MAX_CLIENT_MESSAGE:
        raise LiveMessageError(f"a message holds at most {MAX_CLIENT_MESSAGE} bytes")
    try:
        message = loads(raw)  # integers exact: one beyond 64 bits is refused, not rounded
    except JsonTextError as err:
        raise LiveMessageError(f"the message is not JSON: {err}") from err
    if not isinstance(message, dict):
        raise LiveMessageError('a message is a JSON object with an "op"')
    op = message.get("op")
    if not isinstance(op, str):
        raise LiveMessageError(f'a message needs an "op": one of {", ".join(OPS)}')
    _refuse_big_ints(message, op)
    return message


def _refuse_big_ints(message: dict[str, Any], op: str) -> None:
    """A whole message is refused for an integer outside 64 bits anywhere in it (command
    arguments, a ping's id): nothing could store, send or echo it as sent."""
    found = first_big_int(message)
    if found is None:
        return
    sub = message.get("id")
    raise LiveMessageError(
        f"{found[0]}: {int64_problem(found[1])}",
        op=op if op in OPS else None,
        sub=sub if isinstance(sub, str) and 0 < len(sub) <= MAX_ID else None,
        status=422 if op == "command" else 0,
    )


def _size(raw: str | bytes) -> int:
    if isinstance(raw, bytes) or len(raw) > MAX_CLIENT_MESSAGE:
        return len(raw)  # a text longer in characters is longer in UTF-8 bytes too
    return len(raw.encode())


def read_token(message: dict[str, Any]) -> str:
    """The token of a first `{"op": "auth", "token": ...}` message."""
    token = message.get("token")
    if message.get("op") != "auth" or not isinstance(token, str) or not token:
        raise LiveMessageError('authenticate first: {"op": "auth", "token": "tl_..."}', op="auth")
    return token


def read_sub_id(message: dict[str, Any]) -> str:
    op = str(message.get("op"))
    sub = message.get("id")
    if not isinstance(sub, str) or not 0 < len(sub) <= MAX_ID:
        raise LiveMessageError(f'"id" must be a string of 1 to {MAX_ID} characters', op=op)
    return sub


def read_subscribe(message: dict[str, Any]) -> SubscribeRequest:
    sub = read_sub_id(message)
    twin = message.get("twin")
    if not isinstance(twin, str) or not twin:
        raise LiveMessageError('"twin" must be the slug of a twin', "subscribe", sub)
    stream = message.get("stream", DEFAULT_STREAM)
    if not isinstance(stream, str) or not STREAM_NAME.match(stream):
        raise LiveMessageError(f'"stream" must match {STREAM_NAME.pattern}', "subscribe", sub)
    return SubscribeRequest(
        sub, twin, stream, _read_signals(message.get("signals"), sub), _read_rate(message, sub)
    )


def read_command(message: dict[str, Any]) -> CommandRequest:
    """A `command` op; LiveMessageError (status 422) names the first field that is wrong."""
    op_id = read_sub_id(message)

    def wrong(text: str) -> LiveMessageError:
        return LiveMessageError(text, "command", op_id, 422)

    twin, name = message.get("twin"), message.get("name")
    if not isinstance(twin, str) or not twin:
        raise wrong('"twin" must be the slug of a twin')
    if not isinstance(name, str) or not name:
        raise wrong('"name" must be the name of a command')
    args, device = message.get("args"), message.get("device")
    if args is not None and not isinstance(args, dict):
        raise wrong('"args" must be an object of argument name -> value')
    if device is not None and not isinstance(device, str):
        raise wrong('"device" must be the name of a device of the twin')
    timeout = message.get("timeout_s")
    if timeout is not None and (isinstance(timeout, bool) or not isinstance(timeout, int | float)):
        raise wrong('"timeout_s" must be a number of seconds')
    queue, wait = message.get("queue", False), message.get("wait", True)
    if not isinstance(queue, bool) or not isinstance(wait, bool):
        raise wrong('"queue" and "wait" must be true or false')
    return CommandRequest(
        op_id, twin, name, args, device, None if timeout is None else float(timeout), queue, wait
    )


def _read_signals(raw: Any, sub: str) -> frozenset[str] | None:
    if raw is None:
        return None
    if not isinstance(raw, list) or not 0 < len(raw) <= MAX_SIGNALS:
        raise LiveMessageError(
            f'"signals" must be a list of 1 to {MAX_SIGNALS} names (leave it out for all)',
            "subscribe",
            sub,
        )
    for name in raw:
        if not isinstance(name, str) or not SIGNAL_NAME.match(name):
            raise LiveMessageError(
                f"signal name {name!r} must match {SIGNAL_NAME.pattern}", "subscribe", sub
            )
    return frozenset(raw)


def _read_rate(message: dict[str, Any], sub: str) -> float | None:
    rate = message.get("max_rate")
    if rate is None:
        return None
    if (
        isinstance(rate, bool)
        or not isinstance(rate, int | float)
        or not math.isfinite(rate)
        or not 0 < rate <= MAX_RATE
    ):
        raise LiveMessageError(
            '"max_rate" must be a number of samples per second above 0', "subscribe", sub
        )
    return float(rate)


# -- server messages ------------------------------------------------------------------------


def encode(message: dict[str, Any]) -> bytes:
    return orjson.dumps(message)


def welcome(user: str, queue_messages: int) -> dict[str, Any]:
    return {
        "type": "welcome",
        "user": user,
        "server_time": time.time_ns(),
        "limits": {
            "subscriptions": MAX_SUBSCRIPTIONS,
            "signals": MAX_SIGNALS,
            "message_bytes": MAX_CLIENT_MESSAGE,
            "queue_messages": queue_messages,
            "commands": MAX_COMMANDS,
        },
    }


def subscribed(sub: Subscription, latest: dict[str, dict[str, Any]]) -> dict[str, Any]:
    return {
        "type": "subscribed",
        "id": sub.id,
        "twin": sub.twin,
        "stream": sub.stream,
        "signals": sorted(sub.signals) if sub.signals is not None else None,
        "max_rate": sub.max_rate,
        "latest": latest,
    }


def unsubscribed(sub: str, reason: str | None = None) -> dict[str, Any]:
    out: dict[str, Any] = {"type": "unsubscribed", "id": sub}
    if reason is not None:
        out["reason"] = reason
    return out


def pong(message: dict[str, Any]) -> dict[str, Any]:
    out: dict[str, Any] = {"type": "pong", "server_time": time.time_ns()}
    if "id" in message:
        out["id"] = message["id"]
    return out


def error(err: LiveMessageError) -> dict[str, Any]:
    out: dict[str, Any] = {"type": "error", "message": str(err)}
    if err.op is not None:
        out["op"] = err.op
    if err.sub is not None:
        out["id"] = err.sub
    if err.shown_status:
        out["status"] = err.shown_status
    return out


def command(op_id: str, view: dict[str, Any]) -> dict[str, Any]:
    """The answer to a `command` op: the command as the HTTP API shows it."""
    return {"type": "command", "id": op_id, "command": view}


def dropped(sub: str, messages: int, samples: int) -> dict[str, Any]:
    return {"type": "dropped", "sub": sub, "messages": messages, "samples": samples}
