"""Inputs of every FMI scalar type stream from live signals into a real FMU, whose outputs
echo them (tests/integration/_fmu_types.py): integers rounded, values outside the type's
range or the declared min/max clamped or rejected (`out_of_range`) and reported, booleans 0
or 1, enumerations within their declared items."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from tests.conftest import Server
from tests.integration._fmu_types import FMI2_INPUTS, FMI3_INPUTS, build_echo_fmu
from tests.integration._live import device_twin
from tests.integration._processors import (
    create,
    events,
    post,
    samples_until,
    wait_for,
    watching,
)
from tests.integration._processors import server as server  # module fixture
from tests.integration.test_fmu_processors import upload

pytestmark = pytest.mark.integration


def run(
    server: Server, tmp_path: Path, version: int, rows: list[dict[str, float]], **params: Any
) -> tuple[str, list[dict[str, Any]]]:
    """The echo FMU (FMI `version`) as processor "echo" on `rows`; its twin and outputs."""
    slug, [device] = device_twin(server)
    upload(server, slug, build_echo_fmu(tmp_path, version))
    names = [n for n, *_ in (FMI2_INPUTS if version == 2 else FMI3_INPUTS)]
    create(server, slug, name="echo", blueprint="fmu",
           params={"fmu": f"echo{'' if version == 2 else '3'}.fmu", **params},
           inputs={n: f"s_{n}" for n in names})  # fmt: skip
    wait_for(server, slug, "echo", lambda p: p["state"] == "running")
    with watching(server, slug, "echo") as ws:
        post(server, device, 1, [{f"s_{k}": v for k, v in row.items()} for row in rows])
        expected = len(rows) if params.get("out_of_range") != "reject" else 1
        got = samples_until(ws, lambda s: len(s) >= expected)
    return slug, [{k.removesuffix("_out"): v for k, v in s["values"].items()} for s in got]


def test_fmi3_inputs_of_every_type_come_through(server: Server, tmp_path: Path) -> None:
    rows = [
        {"f32": 1.5, "i8": -3.4, "u8": 300, "i16": -40000, "u16": 7, "i32": 9, "u32": -1,
         "i64": -123456789, "u64": 1e15, "b": 1, "e": 2},
        {"f32": -0.25, "i8": 2.6, "u8": 255, "i16": 5, "u16": 70000, "i32": -5, "u32": 4e9,
         "i64": 2**40, "u64": 0, "b": 0, "e": 7},
    ]  # fmt: skip
    slug, got = run(server, tmp_path, 3, rows)
    assert got == [
        {"f32": 1.5, "i8": -3, "u8": 255, "i16": -32768, "u16": 7, "i32": 5, "u32": 0,
         "i64": -123456789, "u64": 1e15, "b": 1, "e": 2},
        {"f32": -0.25, "i8": 3, "u8": 255, "i16": 5, "u16": 65535, "i32": -5, "u32": 4e9,
         "i64": 2**40, "u64": 0, "b": 0, "e": 3},
    ]  # fmt: skip
    clamped = {e["data"]["input"]: e for e in events(server, slug, "echo", "input_clamped")}
    assert set(clamped) == {"u8", "i16", "i32", "u32", "u16", "e"}
    assert clamped["u8"]["data"]["max"] == 255 and clamped["u8"]["data"]["value"] == 300
    assert clamped["i32"]["data"]["max"] == 5  # the declared max, within Int32's


def test_fmi2_integer_boolean_and_enumeration_inputs_come_through(
    server: Server, tmp_path: Path
) -> None:
    rows = [{"x": 0.25, "n": 2.6, "b": 1, "e": 3}, {"x": -1, "n": -9, "b": 0, "e": 0}]
    _, got = run(server, tmp_path, 2, rows)
    assert got == [{"x": 0.25, "n": 3, "b": 1, "e": 3}, {"x": -1, "n": -5, "b": 0, "e": 1}]


def test_rejected_typed_inputs_skip_their_sample(server: Server, tmp_path: Path) -> None:
    rows = [{"x": 1, "n": 9, "b": 1, "e": 1}, {"x": 2, "n": 4, "b": 1, "e": 2}]
    slug, got = run(server, tmp_path, 2, rows, out_of_range="reject")
    assert got == [{"x": 2, "n": 4, "b": 1, "e": 2}]
    [rejected] = events(server, slug, "echo", "input_rejected")
    assert rejected["data"]["input"] == "n" and rejected["data"]["max"] == 5
