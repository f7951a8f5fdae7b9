"""A mass-spring-damper pushed by a force step, integrated with fixed-step RK4 (standard
library only): `python3 simulate.py CONFIG OUT.csv` writes time_s,position_m,velocity_mps."""

from __future__ import annotations

import csv
import json
import sys


def derivative(x: float, v: float, p: dict[str, float]) -> tuple[float, float]:
    return v, (p["force"] - p["damping"] * v - p["stiffness"] * x) / p["mass"]


def simulate(p: dict[str, float]) -> list[tuple[float, float, float]]:
    dt, steps, every = p["dt"], round(p["t_end"] / p["dt"]), int(p["output_every"])
    x = v = 0.0
    rows = [(0.0, x, v)]
    for i in range(1, steps + 1):
        k1 = derivative(x, v, p)
        k2 = derivative(x + dt / 2 * k1[0], v + dt / 2 * k1[1], p)
        k3 = derivative(x + dt / 2 * k2[0], v + dt / 2 * k2[1], p)
        k4 = derivative(x + dt * k3[0], v + dt * k3[1], p)
        x += dt / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
        v += dt / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        if i % every == 0 or i == steps:
            rows.append((i * dt, x, v))
    return rows


def main(config: str, out: str) -> None:
    with open(config, encoding="utf-8") as f:
        params = {k: float(v) for k, v in json.load(f).items()}
    rows = simulate(params)
    with open(out, "w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f)
        writer.writerow(["time_s", "position_m", "velocity_mps"])
        writer.writerows(rows)
    print(f"simulated {params['t_end']:g} s in {len(rows)} rows: {out}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: python3 simulate.py CONFIG OUT.csv")
    main(sys.argv[1], sys.argv[2])
