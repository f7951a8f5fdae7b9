"""The reference of bench/udp.py: a bare asyncio (uvloop) UDP receiver that only counts
datagrams, in a process of its own; the most a Python listener takes in on this machine.
Prints its port, then, on a line on stdin, the count so far as JSON."""

from __future__ import annotations

import asyncio
import json
import socket
import sys

import uvloop


class Counter(asyncio.DatagramProtocol):
    def __init__(self) -> None:
        self.datagrams = 0

    def datagram_received(self, data: bytes, addr: object) -> None:
        self.datagrams += 1


async def main() -> None:
    loop = asyncio.get_running_loop()
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4 * 2**20)
    sock.bind(("127.0.0.1", 0))
    transport, counter = await loop.create_datagram_endpoint(Counter, sock=sock)
    print(sock.getsockname()[1], flush=True)
    reader = asyncio.StreamReader()
    await loop.connect_read_pipe(lambda: asyncio.StreamReaderProtocol(reader), sys.stdin)
    while await reader.readline():
        print(json.dumps({"received": counter.datagrams}), flush=True)
    transport.close()


if __name__ == "__main__":
    uvloop.run(main())
