"""A paced UDP sender in a process of its own (bench/udp.py): catman records
(`<HHI` header, then doubles) to an address, at a rate, for some seconds; prints one JSON line
with what it sent. Rate 0 sends as fast as it can."""

from __future__ import annotations

import json
import socket
import struct
import sys
import time


def main() -> None:
    host, port, rate, seconds, records, channels = sys.argv[1:7]
    n_records, n_channels = int(records), int(channels)
    record = struct.Struct(f"<HHI{n_channels}d")
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 4 * 2**20)
    target = (host, int(port))
    per_s, duration = float(rate), float(seconds)
    sent = counter = errors = 0
    start = time.perf_counter()
    end = start + duration
    while True:
        now = time.perf_counter()
        if now >= end:
            break
        due = int((now - start) * per_s) if per_s else sent + 64
        while sent < due:
            payload = b"".join(
                record.pack(1, n_channels, counter + i, time.time(), *([0.5] * (n_channels - 1)))
                for i in range(n_records)
            )
            counter += n_records
            try:
                sock.sendto(payload, target)
            except OSError:  # the send buffer is full: the datagram is lost here
                errors += 1
            sent += 1
        if per_s:
            time.sleep(0.0005)
    elapsed = time.perf_counter() - start
    print(json.dumps({"sent": sent, "send_errors": errors, "seconds": elapsed}), flush=True)


if __name__ == "__main__":
    main()
