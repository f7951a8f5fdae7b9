"""A processor whose output the bus refuses (Kafka away between nodes: a 503 UnavailableError)
keeps running: the output is stored all the same, only live views and chained processors
miss it, and the worker is not counted as crashed or restarted for a fault outside it."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from tests.integration._opcua import eventually, running_platform
from twinlink.bus import samples_subject
from twinlink.domain.errors import UnavailableError

pytestmark = pytest.mark.integration

T0 = 1_700_000_000 * 10**9


async def test_a_processor_goes_on_when_the_bus_refuses_its_output(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    async with running_platform(tmp_path) as p:
        s = p.services
        refused: list[str] = []
        publish = s.bus.publish
        out_subject = samples_subject(p.twin.id, "doubled")

        async def refusing(subject: str, message: Any) -> None:
            if subject == out_subject:
                refused.append(subject)
                raise UnavailableError("Kafka did not take the message (a test's refusal)")
            await publish(subject, message)

        monkeypatch.setattr(s.bus, "publish", refusing)
        await s.processors.create(p.principal, p.twin.slug, {
            "name": "double", "blueprint": "expression", "output": "doubled",
            "params": {"outputs": {"y": "x * 2"}}})  # fmt: skip

        async def running() -> bool:
            view = await s.processors.get(p.principal, p.twin.slug, "double")
            return bool(view["state"] == "running")

        await eventually(running, "the processor to run")
        for seq in range(1, 4):
            await s.ingest.ingest(p.device, {"seq": seq, "samples": [
                {"time": T0 + seq, "values": {"x": seq}}]})  # fmt: skip

        async def stored() -> bool:
            rows = await s.history.samples(p.twin.id, "doubled", None, 0, 2**62, 10, None)
            return [r["values"]["y"] for r in rows.rows] == [2, 4, 6]

        await eventually(stored, "every output stored although the bus refused it")
        view = await s.processors.get(p.principal, p.twin.slug, "double")
        assert view["state"] == "running"
        assert view["stats"]["crashes"] == 0 and view["stats"]["restarts"] == 0
        assert len(refused) == 3
        said = [r.getMessage() for r in caplog.records if "not published" in r.getMessage()]
        assert len(said) == 1  # once a minute, not once per batch
