"""The simulated devices: the Tingen cantilever and the generic signal source (pure models)."""

from __future__ import annotations

import itertools
import math
import random
import statistics
from pathlib import Path
from typing import Any

import pytest
import yaml

from twinlink.domain.samples import read_batch, schema_from_interface
from twinlink_edge.simulate.generic import GenericModel
from twinlink_edge.simulate.tingen import FORCE_PER_RAD, TingenModel

TINGEN = Path(__file__).resolve().parents[2] / "examples" / "tingen" / "tingen.yaml"
RATE_HZ = 100
DT = 1 / RATE_HZ
MINUTE = 60 * RATE_HZ
ANGLE = "Cantilever_Angle_radians"
FORCE = "Input_F_in"
ACCELERATION = "Tip_Acceleration_X_mps2"
RATE = "Tip_Angular_Rate_Y_radps"


def tingen_document() -> dict[str, Any]:
    document: dict[str, Any] = yaml.safe_load(TINGEN.read_text(encoding="utf-8"))
    return document


def declared_ranges() -> dict[str, tuple[float, float]]:
    signals = tingen_document()["interface"]["signals"]
    return {s["name"]: (s["min"], s["max"]) for s in signals}


def run(model: TingenModel, steps: int = MINUTE) -> list[dict[str, float]]:
    return [model.step(DT) for _ in range(steps)]


def run_with_plucks(model: TingenModel, steps: int) -> tuple[list[float], list[int]]:
    """The reported angles and the step indexes at which the beam was plucked."""
    angles, plucks = [], []
    for i in range(steps):
        before = model._next_pluck
        angles.append(model.step(DT)[ANGLE])
        if model._next_pluck != before:
            plucks.append(i)
    return angles, plucks


# --- Tingen -----------------------------------------------------------------------------------


def test_the_declared_ranges_are_the_ones_tested_here() -> None:
    assert declared_ranges() == {
        ANGLE: (0.0, 1.0),
        FORCE: (0.0, 10.0),
        ACCELERATION: (-19.62, 19.62),
        RATE: (-4.2761, 4.2761),
    }


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_a_minute_at_100_hz_stays_inside_the_interface(seed: int) -> None:
    out = run(TingenModel(rng=random.Random(seed)))
    assert all(set(row) == {ANGLE, FORCE, ACCELERATION, RATE} for row in out)
    for name, (lo, hi) in declared_ranges().items():
        values = [row[name] for row in out]
        assert lo <= min(values) and max(values) <= hi, name
    # and the platform's own check of that interface accepts every sample
    schema = schema_from_interface(tingen_document()["interface"])
    body = {"seq": 0, "samples": [{"values": row} for row in out]}
    read = read_batch(body, schema, now_ns=1_700_000_000 * 10**9)
    assert read.rejected == []
    assert len(read.values) == MINUTE


def test_the_beam_moves_in_a_minute() -> None:
    out = run(TingenModel(rng=random.Random(5)))
    angles = [row[ANGLE] for row in out]
    assert max(angles) > 0.15  # plucked (plucks are 0.2..0.5 rad)
    rates = [row[RATE] for row in out]
    assert min(rates) < -1 and max(rates) > 1  # swings both ways


def test_the_reported_angle_is_the_unsigned_filtered_angle() -> None:
    model = TingenModel(rng=random.Random(6))
    signs = set()
    for _ in range(MINUTE):
        row = model.step(DT)
        assert row[ANGLE] == pytest.approx(min(abs(model.filtered), 1.0))
        if abs(model.filtered) > 0.05:
            signs.add(model.filtered > 0)
    assert signs == {True, False}  # the beam leans both ways; the angle is reported positive


def test_force_is_the_angle_times_2_ei_over_l_squared() -> None:
    document = tingen_document()["physicalProperties"]
    e = document["youngsModulus"]["value"]
    width = document["width"]["value"]
    thickness = document["thickness"]["value"]
    length = document["length"]["value"]
    assert pytest.approx(2 * e * width * thickness**3 / 12 / length**2) == FORCE_PER_RAD
    assert pytest.approx(9.72, abs=0.005) == FORCE_PER_RAD
    assert pytest.approx(document["angleToForceFactor"]["value"], abs=0.005) == FORCE_PER_RAD
    for row in run(TingenModel(rng=random.Random(7))):
        assert row[FORCE] == pytest.approx(row[ANGLE] * FORCE_PER_RAD, rel=1e-12, abs=1e-12)


def test_the_oscillation_decays_between_plucks() -> None:
    angles, plucks = run_with_plucks(TingenModel(rng=random.Random(8)), MINUTE)
    assert len(plucks) >= 4  # 0.5 s, then every 8..15 s
    for start, end in itertools.pairwise(plucks):
        early = max(angles[start : start + RATE_HZ])  # first second after the pluck
        late = max(angles[end - RATE_HZ : end])  # last second before the next one
        assert late < 0.5 * early


def test_without_damping_the_oscillation_does_not_decay() -> None:
    # the contrast that shows the test above measures the damping
    model = TingenModel(damping=0.0, gyro_noise=0.0, acc_angle_noise=0.0, rng=random.Random(8))
    angles, plucks = run_with_plucks(model, MINUTE)
    start, end = plucks[1], plucks[2]
    early = max(angles[start : start + RATE_HZ])
    late = max(angles[end - RATE_HZ : end])
    assert late == pytest.approx(early, rel=0.1)


def _step_variance(k: float) -> float:
    model = TingenModel(k=k, rng=random.Random(9))
    filtered = []
    for _ in range(MINUTE):
        model.step(DT)
        filtered.append(model.filtered)
    return statistics.pvariance([b - a for a, b in itertools.pairwise(filtered)])


def test_a_larger_filter_k_gives_a_smoother_angle() -> None:
    noisy = _step_variance(0.1)
    assert _step_variance(0.85) < noisy / 5
    assert _step_variance(0.90) < _step_variance(0.85)


def test_the_same_seed_gives_the_same_data() -> None:
    assert run(TingenModel(rng=random.Random(3)), 500) == run(
        TingenModel(rng=random.Random(3)), 500
    )
    assert run(TingenModel(rng=random.Random(3)), 500) != run(
        TingenModel(rng=random.Random(4)), 500
    )


def test_slow_send_rates_stay_stable() -> None:
    model = TingenModel(rng=random.Random(10))
    for _ in range(60):  # one message a second
        row = model.step(1.0)
        assert abs(model.theta) <= 0.5 + 1e-9  # never more than the largest pluck
        assert 0.0 <= row[ANGLE] <= 1.0


def test_a_saturated_gyro_reading_is_inside_the_declared_range() -> None:
    model = TingenModel(pluck_rad=(0.8, 0.8), rng=random.Random(11))
    out = run(model, 5 * RATE_HZ)
    assert max(abs(row[RATE]) for row in out) == pytest.approx(math.radians(245))
    schema = schema_from_interface(tingen_document()["interface"])
    body = {"seq": 0, "samples": [{"values": row} for row in out]}
    assert read_batch(body, schema, now_ns=1_700_000_000 * 10**9).rejected == []


# --- generic ----------------------------------------------------------------------------------


def test_generic_names_cycle_through_the_shapes_when_mixed() -> None:
    model = GenericModel(signals=6)
    assert model.names() == ["sine_0", "step_1", "noise_2", "walk_3", "sine_4", "step_5"]
    assert GenericModel(signals=3, shape="walk").names() == ["walk_0", "walk_1", "walk_2"]
    assert GenericModel(signals=0).names() == []


def test_generic_step_gives_one_value_per_name() -> None:
    model = GenericModel(signals=5, rng=random.Random(1))
    row = model.step(DT)
    assert list(row) == model.names()
    assert all(isinstance(v, float) and math.isfinite(v) for v in row.values())
    assert GenericModel(signals=0).step(DT) == {}


def test_generic_signal_count_may_change_between_steps() -> None:
    model = GenericModel(signals=2, shape="walk", rng=random.Random(2))
    model.step(DT)
    model.signals = 5
    assert list(model.step(DT)) == [f"walk_{i}" for i in range(5)]


def test_sine_follows_period_amplitude_and_phase() -> None:
    model = GenericModel(signals=2, shape="sine", period_s=4.0, amplitude=3.0, noise=0.0)
    for i in range(1, 401):
        row = model.step(DT)
        t = i * DT
        assert row["sine_0"] == pytest.approx(3.0 * math.sin(2 * math.pi * t / 4.0), abs=1e-9)
        # signals are spread over the period: signal 1 is half a period later
        assert row["sine_1"] == pytest.approx(-row["sine_0"], abs=1e-9)


def test_sine_is_bounded_by_amplitude_plus_noise() -> None:
    model = GenericModel(
        signals=1, shape="sine", period_s=2.0, amplitude=2.0, noise=0.05, rng=random.Random(3)
    )
    values = [model.step(DT)["sine_0"] for _ in range(MINUTE)]
    assert max(abs(v) for v in values) <= 2.0 + 6 * 0.05
    assert max(values) > 1.9 and min(values) < -1.9


def test_step_takes_two_levels_without_noise() -> None:
    model = GenericModel(signals=1, shape="step", period_s=1.0, amplitude=1.5, noise=0.0)
    values = [model.step(DT)["step_0"] for _ in range(3 * RATE_HZ)]
    assert set(values) == {1.5, -1.5}
    changes = sum(1 for a, b in itertools.pairwise(values) if a != b)
    assert 5 <= changes <= 6  # twice a period for three periods


def test_step_with_noise_stays_near_the_two_levels() -> None:
    model = GenericModel(signals=1, shape="step", amplitude=1.0, noise=0.05, rng=random.Random(4))
    values = [model.step(DT)["step_0"] for _ in range(2000)]
    assert all(min(abs(v - 1.0), abs(v + 1.0)) < 0.3 for v in values)
    assert len(set(values)) > 2


def test_noise_has_zero_mean_and_the_amplitude_as_sigma() -> None:
    model = GenericModel(signals=1, shape="noise", amplitude=2.0, noise=0.0, rng=random.Random(5))
    values = [model.step(DT)["noise_0"] for _ in range(MINUTE)]
    assert statistics.fmean(values) == pytest.approx(0.0, abs=0.1)
    assert statistics.pstdev(values) == pytest.approx(2.0, rel=0.05)


def test_walk_moves_with_steps_scaled_by_the_square_root_of_dt() -> None:
    model = GenericModel(signals=2, shape="walk", amplitude=1.0, noise=0.0, rng=random.Random(6))
    rows = [model.step(DT) for _ in range(MINUTE)]
    walk = [row["walk_0"] for row in rows]
    steps = [b - a for a, b in itertools.pairwise(walk)]
    assert all(s != 0 for s in steps)
    assert statistics.pstdev(steps) == pytest.approx(math.sqrt(DT), rel=0.05)
    assert walk != [row["walk_1"] for row in rows]  # each signal walks on its own
    assert walk[-1] != 0.0


def test_generic_without_noise_and_the_same_seed_is_reproducible() -> None:
    a = GenericModel(signals=4, rng=random.Random(7))
    b = GenericModel(signals=4, rng=random.Random(7))
    assert [a.step(DT) for _ in range(100)] == [b.step(DT) for _ in range(100)]
