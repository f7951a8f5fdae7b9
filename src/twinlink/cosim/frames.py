"""The frames between an isolated instance (isolated.py) and its child process
(slaveproc.py): a request is `op` (1 byte) and the payload's length (4 bytes), then the
payload; an answer is a status (1 byte), the length, and the payload."""

from __future__ import annotations

import struct
from typing import IO

HEADER = struct.Struct("<BI")  # op or status, payload length
TIMES = struct.Struct("<dd")
TIME = struct.Struct("<d")
STATE = struct.Struct("<Q")
# requests
OPEN, PORTS, START, ENTER, EXIT, READ, WRITE, STEP, SAVE, RESTORE, FREE, CLOSE = range(12)
# answers
OK, RUN_ERROR, TERMINATED, FAILED = range(4)


def read_exactly(stream: IO[bytes], n: int) -> bytes:
    """`n` bytes from `stream`; EOFError if it ends first."""
    data = stream.read(n)
    if len(data) != n:
        raise EOFError
    return data
