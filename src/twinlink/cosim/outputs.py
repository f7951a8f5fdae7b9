"""A co-simulation's results written into its twin's history as they arrive: each batch of
rows the run sends becomes one sample batch of the twin's stream, stored and on the bus (so
live charts show a real-time run as it goes), before the next batch is read (a slow disk
slows the run down; rows never pile up in memory).

A column "{msd1}.m1.x1" (Maestro's) or "m1.x1" is the signal `{prefix}msd1.m1.x1` or
`{prefix}m1.x1`; a character a signal name may not hold ("der(x)", "r[1]") becomes "_". A
row at simulated time t is stamped with the wall clock at the run's start plus t.
"""

from __future__ import annotations

import logging
import re
import time

import numpy as np

from twinlink.domain.errors import TwinlinkError
from twinlink.domain.samples import SampleBatch, Value
from twinlink.ingest.service import IngestService

from .jobs import Rows

log = logging.getLogger("twinlink.cosim")

_NOT_IN_SIGNAL = re.compile(r"[^A-Za-z0-9_.:-]")


def signal_of(column: str) -> str:
    """The signal name of a result column: Maestro's key braces dropped, others as "_"."""
    return _NOT_IN_SIGNAL.sub("_", column.replace("{", "").replace("}", ""))


class HistoryOutput:
    """The rows of one run, into the stream `stream` of twin `twin` (its id `twin_id`)."""

    def __init__(
        self, ingest: IngestService, twin_id: int, twin: str, stream: str, prefix: str, source: str
    ) -> None:
        self.ingest = ingest
        self.twin_id, self.twin, self.stream = twin_id, twin, stream
        self.prefix = prefix
        self.source = source
        self.start_ns = time.time_ns()
        self.signals: list[str] = []
        self.failed = ""  # why the twin's history stopped taking the rows

    def columns(self, columns: list[str]) -> None:
        self.signals = [self.prefix + signal_of(c) for c in columns[1:]]

    async def rows(self, rows: Rows) -> None:
        if self.failed or not len(rows):
            return
        times = (self.start_ns + np.rint(rows[:, 0] * 1e9)).astype(np.int64).tolist()
        signals = self.signals
        values: list[dict[str, Value]] = [
            {s: v for s, v in zip(signals, row, strict=False) if v == v}  # NaN: no value
            for row in rows[:, 1:].tolist()
        ]
        batch = SampleBatch(
            twin_id=self.twin_id, twin=self.twin, stream=self.stream, times=times,
            values=values, received_ns=time.time_ns(), source=self.source,
        )  # fmt: skip
        try:
            await self.ingest.publish(batch)
        except TwinlinkError as err:  # the run goes on; its results are in its CSV
            self.failed = f"its results stopped going into twin {self.twin!r}'s history: {err}"
            log.warning("co-simulation %s: %s", self.source, self.failed,
                        extra={"event": "cosim_output_refused", "twin": self.twin})  # fmt: skip
