from __future__ import annotations

import logging

import orjson

from twinlink.logs import JsonFormatter


def test_json_lines_carry_event_fields_only() -> None:
    record = logging.makeLogRecord(
        {
            "name": "twinlink.x",
            "levelname": "INFO",
            "msg": "ready %s",
            "args": ("now",),
            "event": "ready",
            "color_message": "\x1b[36mready\x1b[0m",
        }
    )
    line = JsonFormatter().format(record)
    assert "\n" not in line
    data = orjson.loads(line)
    assert data["msg"] == "ready now" and data["event"] == "ready"
    assert data["level"] == "info" and data["logger"] == "twinlink.x"
    assert "color_message" not in data and "args" not in data


def test_tokens_in_query_strings_never_reach_a_log_line() -> None:
    import logging

    from twinlink.logs import JsonFormatter, RedactTokens

    record = logging.makeLogRecord(
        {
            "msg": '%s - "WebSocket %s" [accepted]',
            "args": ("127.0.0.1:5", "/twins/t/services/s/ws?a=1&access_token=tl_secret&b=2"),
        }
    )
    assert RedactTokens().filter(record)
    line = JsonFormatter().format(record)
    assert "tl_secret" not in line and "access_token=***&b=2" in line
