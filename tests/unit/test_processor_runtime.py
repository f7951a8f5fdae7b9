"""The worker's runtime around a blueprint, and the wire format between server and worker."""

from __future__ import annotations

import socket
from pathlib import Path

import numpy as np
import pytest

from twinlink.processors.blueprint import Batch, Blueprint, Context, NoParams
from twinlink.processors.runtime import Runtime
from twinlink.processors.spec import InputMap, ProcessorSpec, Rates
from twinlink.processors.wire import BlockingChannel, frame, pack_batch, unpack_batch

MS = 1_000_000


class Echo(Blueprint[NoParams]):
    """Returns its inputs, records the size of every batch and raises an event per batch."""

    name = "echo"

    def start(self) -> None:
        self.sizes: list[int] = []

    def inputs(self) -> list[str]:
        return ["a", "b"]

    def process(self, batch: Batch) -> Batch | None:
        self.sizes.append(len(batch))
        self.ctx.event("seen", f"{len(batch)} samples", int(batch.times[-1]), n=len(batch))
        self.ctx.command("blink", device="d1", times=2)
        return batch


def runtime(tmp_path: Path, maps: dict[str, InputMap] | None = None, **rates: float) -> Runtime:
    blueprint = Echo(NoParams(), Context("p", "t", tmp_path, tmp_path))
    blueprint.start()
    return Runtime(blueprint, maps or {}, Rates(**rates))


def test_inputs_are_renamed_scaled_and_offset(tmp_path: Path) -> None:
    rt = runtime(tmp_path, {"a": InputMap(signal="force", scale=2.0, offset=1.0)})
    batch = Batch.of([1, 2], force=[1.0, 3.0], b=[5.0, 6.0], other=[9.0, 9.0])
    reply, out = rt.feed(batch)
    assert out is not None
    assert out.columns.keys() == {"a", "b"}  # `other` is not an input of the blueprint
    assert out["a"].tolist() == [3.0, 7.0] and out["b"].tolist() == [5.0, 6.0]
    assert reply["n_in"] == 2 and len(reply["timings"]) == 1


def test_spacing_of_inputs_and_outputs_holds_across_batches(tmp_path: Path) -> None:
    rt = runtime(tmp_path, min_input_spacing_s=0.0025)
    times = [i * MS for i in range(10)]
    _, first = rt.feed(Batch.of(times[:5], a=range(5)))
    _, second = rt.feed(Batch.of(times[5:], a=range(5, 10)))
    assert first is not None and second is not None
    assert [*first.times.tolist(), *second.times.tolist()] == [0, 3 * MS, 6 * MS, 9 * MS]
    rt = runtime(tmp_path, min_output_spacing_s=0.004)
    _, out = rt.feed(Batch.of(times, a=range(10)))
    assert out is not None and out.times.tolist() == [0, 4 * MS, 8 * MS]


def test_large_batches_are_cut_to_max_batch(tmp_path: Path) -> None:
    rt = runtime(tmp_path, max_batch=4)
    reply, out = rt.feed(Batch.of(range(10), a=range(10)))
    assert rt.blueprint.sizes == [4, 4, 2]  # type: ignore[attr-defined]
    assert out is not None and out["a"].tolist() == list(range(10))
    assert [n for _, n in reply["timings"]] == [4, 4, 2]


def test_events_and_commands_are_handed_on_once(tmp_path: Path) -> None:
    rt = runtime(tmp_path)
    reply, _ = rt.feed(Batch.of([7 * MS], a=[1.0]))
    assert reply["events"] == [["seen", "1 samples", 7 * MS, {"n": 1}]]
    assert reply["commands"] == [["blink", {"times": 2}, "d1"]]
    reply, _ = rt.feed(Batch.of([8 * MS], a=[1.0]))
    assert len(reply["events"]) == 1 and len(reply["commands"]) == 1


def test_a_batch_travels_the_channel_unchanged() -> None:
    batch = Batch.of([1, 2, 3], x=[0.5, np.nan, -1e300], y=[1.0, 2.0, 3.0])
    left, right = socket.socketpair()
    with left, right:
        BlockingChannel(left).send({"t": "data", "id": 1, **pack_batch(batch)})
        got = BlockingChannel(right).receive()
    back = unpack_batch(got)
    assert got["t"] == "data" and back.times.tolist() == [1, 2, 3]
    np.testing.assert_array_equal(back["x"], batch["x"])
    assert frame({"t": "x"})[:4] == len(frame({"t": "x"})[4:]).to_bytes(4, "big")


def test_batch_concat_fills_missing_signals_with_nan() -> None:
    joined = Batch.concat([Batch.of([1], x=[1.0]), Batch.of([2], y=[2.0])])
    assert joined.times.tolist() == [1, 2]
    assert np.isnan(joined["x"][1]) and np.isnan(joined["y"][0])


@pytest.mark.parametrize("name", ["", "Upper", "with space", "a" * 65])
def test_processor_names_are_stream_names(name: str) -> None:
    with pytest.raises(ValueError, match="name"):
        ProcessorSpec(name=name, blueprint="x")


def test_inputs_given_as_names_mean_scale_one() -> None:
    spec = ProcessorSpec(name="p", blueprint="x", inputs={"F": "force"})
    assert spec.input_maps()["F"] == InputMap(signal="force", scale=1.0, offset=0.0)
    assert spec.output_stream == "p"
