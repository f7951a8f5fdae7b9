"""Structured logs: one line per event, JSON by default. Secrets are never passed to a logger."""

from __future__ import annotations

import logging
import re
import sys
import time
from typing import Any

import orjson

# Record attributes that are not the event's own fields (color_message: uvicorn's ANSI copy).
_STANDARD = set(logging.makeLogRecord({}).__dict__) | {"message", "asctime", "color_message"}


# A token in a query string (the gateway takes WebSocket tokens as `access_token`, as browsers
# cannot set headers there): uvicorn logs request paths with their query.
_QUERY_TOKEN = re.compile(r"((?:access_token|token)=)[^&\s\"']+", re.IGNORECASE)


class RedactTokens(logging.Filter):
    """Replaces tokens in query strings with `***` before any handler formats the line."""

    def filter(self, record: logging.LogRecord) -> bool:
        message = record.getMessage()
        if "token=" in message.lower():
            record.msg, record.args = _QUERY_TOKEN.sub(r"\1***", message), None
        return True


class JsonFormatter(logging.Formatter):
    def format(self, record: logging.LogRecord) -> str:
        out: dict[str, Any] = {
            "ts": self.formatTime(record, "%Y-%m-%dT%H:%M:%S") + f".{int(record.msecs):03d}Z",
            "level": record.levelname.lower(),
            "logger": record.name,
            "msg": record.getMessage(),
        }
        out.update({k: v for k, v in record.__dict__.items() if k not in _STANDARD})
        if record.exc_info:
            out["exc"] = self.formatException(record.exc_info)
        return orjson.dumps(out, default=str).decode()


# Loggers that log at the chosen level; every other one (asyncua, httpx, websockets, ...) at
# warning or above: their info lines are for their own developers.
OWN_LOGGERS = ("twinlink", "uvicorn")


def setup_logging(level: str, fmt: str) -> None:
    """One handler, on the root logger, for every logger: twinlink's, the server's (uvicorn)
    and the libraries' (asyncua warns once per attempt of an OPC UA connector that cannot
    connect). Without a handler on the root, Python prints library records as plain text
    lines among the JSON ones."""
    handler = logging.StreamHandler(sys.stderr)
    formatter: logging.Formatter
    if fmt == "json":
        formatter = JsonFormatter()
    else:
        formatter = logging.Formatter("%(asctime)s %(levelname)s %(name)s: %(message)s")
    formatter.converter = time.gmtime
    handler.setFormatter(formatter)
    handler.addFilter(RedactTokens())
    chosen = logging.getLevelNamesMapping()[level.upper()]
    root = logging.getLogger()
    root.handlers[:] = [handler]
    root.setLevel(max(logging.WARNING, chosen))
    # asyncua logs a traceback at ERROR each time a server it is connected to goes away;
    # the OPC UA connector's status already says so, with the reason, and it reconnects.
    logging.getLogger("asyncua.client.ua_session").setLevel(logging.CRITICAL)
    for name in (*OWN_LOGGERS, "uvicorn.error", "uvicorn.access"):
        logger = logging.getLogger(name)
        logger.handlers[:] = []  # records go up to the root's handler, once
        logger.propagate = True
        if name in OWN_LOGGERS:
            logger.setLevel(chosen)
