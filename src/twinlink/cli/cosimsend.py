"""A co-simulation's rows sent as one device's samples through HTTP ingest
(`POST /api/v1/device/samples`, docs/protocol.md), in batches, from a thread of its own: the
simulation never waits on the network, so a real-time run keeps its pace.

A row [t, v1, v2, ...] becomes one sample at `start_ns + (t - t0)` (the wall clock when the
run started plus the simulated time since its start) holding each column as a signal. A batch
keeps its `seq` until it is acknowledged, so a batch resent after a lost answer is stored
once (the platform acknowledges a known seq again as a duplicate). The simulation is held
back when the rows waiting reach MAX_PENDING_ROWS: a slow server slows a batch run down
rather than filling the memory.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import httpx
import numpy as np
import numpy.typing as npt
import orjson

from twinlink.domain.errors import TwinlinkError

# A batch holds at most this many values (rows x signals): about 2 MB of JSON, far from the
# 16 MiB and 100 000 samples a batch may have.
BATCH_VALUES = 50_000
INTERVAL_S = 0.25  # a batch at least this often while rows come (live charts follow)
MAX_PENDING_ROWS = 200_000
RETRIES = 5  # a refused connection or a 503 is tried again, with a growing wait


class SendError(TwinlinkError):
    """The server refused the samples (a wrong device token, a twin that refuses them) or
    could not be reached; the message says which."""


@dataclass(slots=True)
class Sent:
    """What was sent: samples accepted, refused (with the first reason), batches."""

    accepted: int = 0
    rejected: int = 0
    batches: int = 0
    first_rejection: str = ""
    signals: tuple[str, ...] = field(default_factory=tuple)


class DeviceSender:
    """Send rows as a device's samples. `names` are the signal names of the columns after
    "time"; `add` queues a row, `close` sends what is left and says what was sent."""

    def __init__(
        self,
        url: str,
        device_token: str,
        names: Sequence[str],
        *,
        t0: float,
        stream: str = "cosim",
        start_ns: int | None = None,
        timeout: float = 30.0,
    ) -> None:
        self._names = list(names)
        self._t0 = t0
        self._start_ns = time.time_ns() if start_ns is None else start_ns
        self._stream = stream
        # Unique per device across runs, as the edge SDK's: microseconds since the epoch.
        self._seq = time.time_ns() // 1000
        self._rows_per_batch = max(1, BATCH_VALUES // max(1, len(self._names)))
        self._http = httpx.Client(
            base_url=url.rstrip("/"),
            headers={"Authorization": f"Bearer {device_token}"},
            timeout=timeout,
        )
        self._pending: list[npt.NDArray[np.float64]] = []
        self._cond = threading.Condition()
        self._closing = False
        self._error: SendError | None = None
        self.sent = Sent(signals=tuple(self._names))
        self._thread = threading.Thread(target=self._loop, name="cosim-sender", daemon=True)
        self._thread.start()

    def add(self, row: npt.NDArray[np.float64]) -> None:
        """Queue one row (copied: the caller may reuse its array). Raises SendError once a
        batch was refused, so a run does not go on computing what cannot be stored."""
        with self._cond:
            if self._error is not None:
                raise self._error
            while len(self._pending) >= MAX_PENDING_ROWS and self._error is None:
                self._cond.wait()
            self._pending.append(np.array(row, dtype=np.float64))
            if len(self._pending) >= self._rows_per_batch:
                self._cond.notify_all()

    def close(self) -> Sent:
        """Send every queued row, stop the thread; raises SendError if a batch was refused."""
        with self._cond:
            self._closing = True
            self._cond.notify_all()
        self._thread.join()
        self._http.close()
        if self._error is not None:
            raise self._error
        return self.sent

    def abandon(self) -> None:
        """Stop without sending what is queued (the run failed; nothing more to say)."""
        with self._cond:
            self._pending.clear()
            self._closing = True
            self._cond.notify_all()
        self._thread.join()
        self._http.close()

    def _loop(self) -> None:
        while True:
            with self._cond:
                if not self._closing and len(self._pending) < self._rows_per_batch:
                    self._cond.wait(INTERVAL_S)
                rows = self._pending[: self._rows_per_batch]
                del self._pending[: self._rows_per_batch]
                self._cond.notify_all()  # room again for a waiting add
                done = self._closing and not self._pending and not rows
            if done:
                return
            if not rows:
                continue
            try:
                self._send(np.vstack(rows))
            except SendError as err:
                with self._cond:
                    self._error = err
                    self._pending.clear()
                    self._cond.notify_all()
                return

    def _send(self, block: npt.NDArray[np.float64]) -> None:
        samples = self._samples(block)
        if not samples:
            return
        body = orjson.dumps(
            {"seq": self._seq, "stream": self._stream, "time_unit": "ns", "samples": samples}
        )
        self._seq += 1
        ack = self._post(body)
        self.sent.batches += 1
        self.sent.accepted += int(ack.get("accepted", 0))
        rejected = int(ack.get("rejected_count", 0))
        if rejected and not self.sent.first_rejection:
            first = (ack.get("rejected") or [{}])[0]
            self.sent.first_rejection = str(first.get("reason") or first)
        self.sent.rejected += rejected

    def _samples(self, block: npt.NDArray[np.float64]) -> list[dict[str, Any]]:
        """The rows as samples: times in ns, and only finite values (JSON has no NaN, and
        a sample without a value is left out)."""
        # integers: the wall clock in ns is past float64's 53 bits of exact integers
        times = np.rint((block[:, 0] - self._t0) * 1e9).astype(np.int64) + self._start_ns
        values = block[:, 1:]
        names = self._names
        if bool(np.isfinite(values).all()):
            return [
                {"time": t, "values": dict(zip(names, row, strict=True))}
                for t, row in zip(times.tolist(), values.tolist(), strict=True)
            ]
        samples = []
        for t, row in zip(times.tolist(), values.tolist(), strict=True):
            kept = {n: v for n, v in zip(names, row, strict=True) if np.isfinite(v)}
            if kept:
                samples.append({"time": t, "values": kept})
        return samples

    def _post(self, body: bytes) -> dict[str, Any]:
        wait = 0.2
        for attempt in range(RETRIES + 1):
            try:
                response = self._http.post(
                    "/api/v1/device/samples",
                    content=body,
                    headers={"Content-Type": "application/json"},
                )
            except httpx.HTTPError as err:
                problem = f"cannot reach twinlink at {self._http.base_url}: {err}"
            else:
                if response.status_code < 300:
                    answer: dict[str, Any] = response.json()
                    return answer
                problem = _refusal(response)
                if response.status_code not in (502, 503, 504):
                    raise SendError(problem)
            if attempt == RETRIES:
                raise SendError(problem)
            time.sleep(wait)  # a transient failure: the same batch (same seq) again
            wait *= 2
        raise AssertionError("unreachable")


def _refusal(response: httpx.Response) -> str:
    try:
        body = response.json()
    except ValueError:
        body = None
    detail = body.get("detail") if isinstance(body, dict) else None
    text = detail or response.text[:300] or response.reason_phrase
    hint = ""
    if response.status_code == 401:
        hint = " (check --device-token / TWINLINK_DEVICE_TOKEN: a device token, tld_...)"
    return f"the samples were refused (HTTP {response.status_code}): {text}{hint}"
