from __future__ import annotations

import logging
import subprocess
import sys

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


# A process of its own: setup_logging configures the root logger, which pytest uses too.
LIBRARIES_LOG = """
import logging
from asyncua.crypto import cert_gen, uacrypto
from cryptography import x509
from twinlink.logs import setup_logging

setup_logging("info", "{fmt}")
key = cert_gen.generate_private_key()
san = [x509.UniformResourceIdentifier("urn:example:client")]
cert = cert_gen.generate_self_signed_app_certificate(key, "client", {{}}, san, [])
# asyncua's own warnings, as an OPC UA connector's attempts make them (one per attempt)
uacrypto.check_certificate(cert, "urn:example:other", "no-such-host")
logging.getLogger("websockets.server").warning("a warning of another library")
logging.getLogger("httpx").info("a library's info line: left out")
logging.getLogger("twinlink.test").info("twinlink at info")
logging.getLogger("uvicorn.error").info("the server at info")
"""


def log_lines(fmt: str) -> list[str]:
    done = subprocess.run(
        [sys.executable, "-c", LIBRARIES_LOG.format(fmt=fmt)],
        capture_output=True,
        text=True,
        timeout=60,
        check=True,
    )
    assert done.stdout == ""
    return done.stderr.splitlines()


def test_library_loggers_write_json_lines_as_twinlink_does() -> None:
    records = [orjson.loads(line) for line in log_lines("json")]  # each line one JSON object
    assert [(r["level"], r["logger"]) for r in records] == [
        ("warning", "asyncua.crypto.uacrypto"),
        ("warning", "asyncua.crypto.uacrypto"),
        ("warning", "websockets.server"),
        ("info", "twinlink.test"),
        ("info", "uvicorn.error"),
    ]
    assert records[1]["msg"] == (
        "certificate does not contain the hostname in DNSNames no-such-host. Some applications "
        "will check this."
    )


def test_library_loggers_write_text_lines_in_the_text_format() -> None:
    lines = log_lines("text")
    assert len(lines) == 5
    assert (
        " WARNING asyncua.crypto.uacrypto: certificate does not contain the application "
        in (lines[0])
    )
    assert lines[4].endswith(" INFO uvicorn.error: the server at info")
