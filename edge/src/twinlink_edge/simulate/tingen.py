"""The Tingen cantilever as an inverted pendulum, sensed the way the thesis's rig senses it.

Beam (thesis code listing C.4): steel, L = 0.300 m, height 0.025 m, thickness 0.001 m,
E = 210 GPa, so EI = E * h * t^3 / 12 = 0.4375 N m^2. The tip swings as a damped oscillator
that someone plucks now and then. The IMU at the tip gives a gyroscope rate and an
accelerometer angle, both noisy and clipped to the sensor's full scale (245 deg/s, +/-2 g;
code listing C.2). The rig smooths them with the complementary filter of equation 4.2,

    theta[i+1] = K * (theta[i] + rate * dt) + (1 - K) * theta_acc      (K = 0.85 in eq. 4.2)

and computes the tip force from the angle by the inverse method of equation 4.1,

    F = theta * 2 EI / L^2   (about 9.72 N per radian).

The swing frequency, damping and pluck sizes are the simulator's choices (the thesis reports
peaks of about 0.8 rad but not the frequency); they keep the raw IMU signals inside the
sensor ranges the Tingen DT document declares.
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass, field

LENGTH_M = 0.300
HEIGHT_M = 0.025
THICKNESS_M = 0.001
E_PA = 210e9
EI = E_PA * HEIGHT_M * THICKNESS_M**3 / 12
FORCE_PER_RAD = 2 * EI / LENGTH_M**2  # equation 4.1
GYRO_FULL_SCALE = math.radians(245)
ACC_FULL_SCALE = 2 * 9.81


@dataclass
class TingenModel:
    k: float = 0.85  # complementary filter weight (equation 4.2)
    frequency_hz: float = 1.2
    damping: float = 0.03
    pluck_every_s: tuple[float, float] = (8.0, 15.0)
    pluck_rad: tuple[float, float] = (0.2, 0.5)
    gyro_noise: float = 0.02  # rad/s, one sigma
    acc_angle_noise: float = 0.03  # rad, one sigma (the accelerometer angle is noisy)
    rng: random.Random = field(default_factory=random.Random)
    theta: float = 0.0  # true tip angle, rad (signed)
    omega: float = 0.0  # true angular rate, rad/s
    filtered: float = 0.0  # the rig's filtered angle (signed)
    _next_pluck: float = 0.5
    _time: float = 0.0

    def step(self, dt: float) -> dict[str, float]:
        """Advance `dt` seconds; the values the rig would send at the end of it."""
        self._advance(dt)
        rate = _clip(self.omega + self.rng.gauss(0.0, self.gyro_noise), GYRO_FULL_SCALE)
        acceleration = _clip(self._tip_acceleration(), ACC_FULL_SCALE)
        acc_angle = self.theta + self.rng.gauss(0.0, self.acc_angle_noise)
        self.filtered = self.k * (self.filtered + rate * dt) + (1 - self.k) * acc_angle
        angle = min(abs(self.filtered), 1.0)
        return {
            "Cantilever_Angle_radians": angle,
            "Input_F_in": angle * FORCE_PER_RAD,
            "Tip_Acceleration_X_mps2": acceleration,
            "Tip_Angular_Rate_Y_radps": rate,
        }

    def _advance(self, dt: float) -> None:
        self._time += dt
        if self._time >= self._next_pluck:
            sign = self.rng.choice((-1.0, 1.0))
            self.theta = sign * self.rng.uniform(*self.pluck_rad)
            self.omega = 0.0
            self._next_pluck = self._time + self.rng.uniform(*self.pluck_every_s)
        w = 2 * math.pi * self.frequency_hz
        # Semi-implicit Euler in small sub-steps: stable and cheap at any send rate.
        steps = max(1, math.ceil(dt / 0.001))
        h = dt / steps
        for _ in range(steps):
            self.omega += (-(w * w) * self.theta - 2 * self.damping * w * self.omega) * h
            self.theta += self.omega * h

    def _tip_acceleration(self) -> float:
        w = 2 * math.pi * self.frequency_hz
        angular = -(w * w) * self.theta - 2 * self.damping * w * self.omega
        return angular * LENGTH_M


def _clip(value: float, limit: float) -> float:
    return max(-limit, min(limit, value))
