"""Where a processor's outputs go: its output stream, stored and on the bus
(`IngestService.publish_first`: on the bus at once, stored by the next group commit)."""

from __future__ import annotations

import logging
import time

from twinlink.domain.errors import UnavailableError
from twinlink.domain.records import ProcessorRecord
from twinlink.ingest.service import IngestService
from twinlink.processors.blueprint import Batch
from twinlink.processors.convert import to_samples

log = logging.getLogger("twinlink.processors")

SAY_EVERY_S = 60.0  # a bus refusing outputs is said once a minute per processor


class Outputs:
    def __init__(self, ingest: IngestService) -> None:
        self.ingest = ingest
        self._said: dict[int, float] = {}  # processor id -> when its refusal was last said

    async def publish(self, record: ProcessorRecord, out: Batch) -> None:
        stream = record.spec.get("output") or record.name
        source = f"processor:{record.name}"
        try:
            await self.ingest.publish_first(
                to_samples(out, record.twin_id, record.twin_slug, stream, source)
            )
        except UnavailableError as err:
            # The bus refused it (Kafka away): stored all the same (publish_first stores it
            # apart), but live views and chained processors miss it. A fault outside the
            # worker: it goes on, neither crashed nor restarted.
            now = time.monotonic()
            if now - self._said.get(record.id, -SAY_EVERY_S) >= SAY_EVERY_S:
                self._said[record.id] = now
                log.warning("processor %s/%s: output not published (stored): %s",
                            record.twin_slug, record.name, err,
                            extra={"event": "processor_output_not_published"})  # fmt: skip
