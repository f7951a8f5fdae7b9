"""Raw MQTT 3.1.1 clients in a process of their own (bench/mqtt.py), on twinlink's own packet
codec so the client costs little.

    _mqtt_client.py pub CONFIG   # CONFIG: JSON, see publish(); prints one JSON line
    _mqtt_client.py sub CONFIG   # a subscriber that only counts; see subscribe()

`pub` opens one connection a device and publishes telemetry for some seconds: QoS 1 with a
window of messages in flight (a PUBACK frees a place), or QoS 0 as fast as the socket takes
it, ending with one QoS 1 message whose PUBACK says the ones before it were handled.
"""

from __future__ import annotations

import asyncio
import json
import sys
import time
from typing import Any

import uvloop

from twinlink.ingest.mqtt import packets as mq

MAX_PACKET = 1 << 24


async def _packets(reader: asyncio.StreamReader, packets: mq.PacketReader) -> list[Any]:
    while True:
        data = await reader.read(65536)
        if not data:
            raise ConnectionError("the server closed the connection")
        got = packets.feed(data)
        if got:
            return got


async def _connect(
    host: str, port: int, client_id: str, username: str, password: str
) -> tuple[asyncio.StreamReader, asyncio.StreamWriter, mq.PacketReader]:
    reader, writer = await asyncio.open_connection(host, port)
    packets = mq.PacketReader(MAX_PACKET)
    writer.write(mq.encode_connect(mq.V311, client_id, True, 60, username, password))
    ack = (await _packets(reader, packets))[0]
    if not isinstance(ack, mq.ConnAck) or ack.reason != 0:
        raise ConnectionError(f"refused: {ack}")
    return reader, writer, packets


class Payloads:
    """Telemetry of the signals `angle` and `force`: flat values (one sample, the server's
    time) or a batch of `per_message` samples with their own times (ns)."""

    def __init__(self, per_message: int) -> None:
        self.per_message = per_message
        self.counter = 0
        self.t0 = time.time_ns()

    def next(self) -> bytes:
        n = self.counter
        self.counter += self.per_message
        if self.per_message == 1:
            return b'{"angle":%d.5,"force":2.5}' % n
        t = self.t0 + n * 1000
        samples = b",".join(
            b'{"time":%d,"values":{"angle":%d.5,"force":2.5}}' % (t + i * 1000, n + i)
            for i in range(self.per_message)
        )
        return b'{"samples":[' + samples + b"]}"


async def _publisher(cfg: dict[str, Any], index: int, start: float, end: float) -> dict[str, Any]:
    username, password = cfg["credentials"][index]
    topic = cfg["topics"][index]
    reader, writer, packets = await _connect(
        cfg["host"], cfg["port"], f"bench-{index}", username, password
    )
    payloads = Payloads(cfg["per_message"])
    qos, window = cfg["qos"], cfg["window"]
    await start_barrier(start)
    sent = 0
    if qos == 0:
        while time.time() < end:
            for _ in range(64):
                writer.write(mq.encode_publish(mq.V311, topic, payloads.next(), 0))
            sent += 64
            await writer.drain()
        # The last one QoS 1: its PUBACK comes once the ones before it are handled.
        writer.write(mq.encode_publish(mq.V311, topic, payloads.next(), 1, 1))
        sent += 1
        while not any(isinstance(p, mq.Ack) for p in await _packets(reader, packets)):
            pass
    else:
        free = asyncio.Semaphore(window)
        acked = 0
        finished = asyncio.Event()

        async def read_acks() -> None:
            nonlocal acked
            while True:
                for packet in await _packets(reader, packets):
                    if isinstance(packet, mq.Ack):
                        acked += 1
                        free.release()
                if finished.is_set() and acked >= sent:
                    return

        acks = asyncio.create_task(read_acks())
        while time.time() < end:
            await free.acquire()
            writer.write(mq.encode_publish(mq.V311, topic, payloads.next(), qos, sent % 65535 + 1))
            sent += 1
            if sent % 32 == 0:
                await writer.drain()
        await writer.drain()
        finished.set()
        if acked < sent:
            await acks
        else:
            acks.cancel()
    done = time.time()
    writer.write(mq.encode_disconnect(mq.V311))
    writer.close()
    return {"sent": sent, "end": done}


async def start_barrier(start: float) -> None:
    await asyncio.sleep(max(0.0, start - time.time()))


async def publish(cfg: dict[str, Any]) -> dict[str, Any]:
    """cfg: host, port, credentials ([user, password] a connection), topics (one a
    connection), qos, window, per_message, start (wall time), seconds. All connect, then
    start together."""
    start = max(cfg["start"], time.time() + 0.2)  # all connect first
    end = start + cfg["seconds"]
    n = len(cfg["topics"])
    cpu = time.process_time()  # connecting costs little next to sending
    results = await asyncio.gather(*(_publisher(cfg, i, start, end) for i in range(n)))
    cpu = time.process_time() - cpu
    return {
        "sent": sum(r["sent"] for r in results),
        "start": start,
        "end": max(r["end"] for r in results),
        "seconds": max(r["end"] for r in results) - start,
        "client_cpu": cpu / (max(r["end"] for r in results) - start),
    }


async def subscribe(cfg: dict[str, Any]) -> None:
    """cfg: host, port, username, password, filter. Prints READY once subscribed; on a line
    `count` on stdin waits until nothing arrived for a second and prints what it received."""
    reader, writer, packets = await _connect(
        cfg["host"], cfg["port"], "bench-sub", cfg["username"], cfg["password"]
    )
    writer.write(mq.encode_subscribe(mq.V311, 1, [(cfg["filter"], 1)]))
    received, last = 0, 0.0

    async def count() -> None:
        nonlocal received, last
        while True:
            acks = []
            for packet in await _packets(reader, packets):
                if isinstance(packet, mq.Publish):
                    received += 1
                    if packet.qos:
                        acks.append(mq.encode_ack(mq.PUBACK, packet.packet_id, mq.V311))
                elif isinstance(packet, mq.SubAck):
                    print("READY", flush=True)
            if acks:
                writer.write(b"".join(acks))
            last = time.time()

    task = asyncio.create_task(count())
    loop = asyncio.get_running_loop()
    while (await loop.run_in_executor(None, sys.stdin.readline)).strip() == "count":
        deadline = time.time() + 120
        while time.time() - last < 1.0 and time.time() < deadline:
            await asyncio.sleep(0.05)
        print(json.dumps({"received": received, "last": last}), flush=True)
    task.cancel()
    writer.close()


def main() -> None:
    mode, cfg = sys.argv[1], json.loads(sys.argv[2])
    if mode == "pub":
        print(json.dumps(uvloop.run(publish(cfg))), flush=True)
    else:
        uvloop.run(subscribe(cfg))


if __name__ == "__main__":
    main()
