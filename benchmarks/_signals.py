"""Realistic, seeded inputs shared by the benchmarks.

A 100 Hz IMU (vertical acceleration, m/s², +up, gravity removed, with a bias
and white noise) and a 25 Hz barometer (altitude, m, with white noise): the
baro array holds a sample on every 4th step and NaN in between, as
``update_batch`` expects.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

#: IMU sample period, s (100 Hz).
DT = 0.01
#: One baro sample every this many IMU samples (25 Hz).
BARO_EVERY = 4


class Signals(NamedTuple):
    accel: np.ndarray  # float32, m/s²
    baro_altitude: np.ndarray  # float32, m; NaN between baro samples
    dt: float  # s, one value for all samples
    dt_array: np.ndarray  # float32, s, per-sample with timestamp jitter


def make_signals(n: int, seed: int = 20240607, baro_every: int = BARO_EVERY) -> Signals:
    """n samples of a vertical flight profile (slow climb/descent plus bobbing).

    The baro altitude is NaN except on every ``baro_every``-th sample.
    """
    rng = np.random.default_rng(seed)
    t = np.arange(n, dtype=np.float64) * DT
    w1, w2 = 2 * np.pi * 0.02, 2 * np.pi * 0.4
    a1, a2 = 30.0, 1.5
    altitude = 100.0 + a1 * np.sin(w1 * t) + a2 * np.sin(w2 * t)
    accel_true = -a1 * w1**2 * np.sin(w1 * t) - a2 * w2**2 * np.sin(w2 * t)
    accel = accel_true + 0.15 + rng.normal(0.0, 0.3, n)  # 0.15 m/s² bias, 0.3 m/s² noise
    baro = altitude + rng.normal(0.0, 0.4, n)  # 0.4 m noise
    baro[np.arange(n) % baro_every != 0] = np.nan
    dt_array = DT + rng.uniform(-2e-4, 2e-4, n)  # ±0.2 ms jitter
    return Signals(accel.astype(np.float32), baro.astype(np.float32), DT, dt_array.astype(np.float32))
