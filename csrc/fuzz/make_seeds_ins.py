"""Writes the seed corpus of fuzz_ins.c: csrc/fuzz/corpus_ins/*.bin.

    python csrc/fuzz/make_seeds_ins.py

Each seed is a sequence of calls in fuzz_ins.c's format: simulated raw-IMU
flights (fusion_altitude.imu_sim: a stationary start, then the `realistic`
motion with rocking) as scaled updates with the baro and a magnetometer on
every 10th step, a rest long enough for stationary learning, settings edits,
and raw updates with NaN, infinite and out-of-range inputs and gaps.
"""

from __future__ import annotations

import struct
import sys
from pathlib import Path

import numpy as np
from make_seeds_common import write_corpus

CORPUS = Path(__file__).resolve().parent / "corpus_ins"
LEVEL = (0.0, 0.0, 9.80665)


def scaled(value: float, limit: float) -> bytes:
    raw = int(round((min(max(value / limit, -1.0), 1.0) + 1.0) * 32767.5))
    return struct.pack("<H", min(raw, 65535))


def update(gyro, accel, mag=None, baro=float("nan"), dt=0.01) -> bytes:
    presence = (0 if np.isnan(baro) else 1) | (0 if mag is None else 2)
    mag = (0.0, 0.0, 0.0) if mag is None else mag
    return (bytes([3]) + b"".join(scaled(g, 10.0) for g in gyro) + b"".join(scaled(a, 160.0) for a in accel)
            + b"".join(scaled(m, 1e3) for m in mag) + bytes([presence]) + scaled(0.0 if np.isnan(baro) else baro, 1e5)
            + scaled(dt - 0.0105, 0.01))


def raw_update(gyro, accel, mag, baro, dt) -> bytes:
    return bytes([2]) + struct.pack("<11f", *gyro, *accel, *mag, baro, dt)


def edit(field: int, value: float) -> bytes:
    return bytes([1, field]) + struct.pack("<f", value)


def flight(seed: int, rest: float, steps: int) -> bytes:
    from fusion_altitude.imu_sim import simulate_raw_imu

    sim = simulate_raw_imu("realistic", seed=seed, rest_duration=rest, rocking_deg=15.0)
    out = b""
    for k in range(min(steps, len(sim.gyro))):
        mag = tuple(float(x) for x in sim.mag[k]) if k % 10 == 3 else None
        out += update(tuple(float(x) for x in sim.gyro[k]), tuple(float(x) for x in sim.accel[k]), mag,
                      float(sim.baro_altitude[k]), float(sim.dt))
    return out


def stepped(steps, seed: int = 0) -> bytes:
    """Raw updates (opcode 2) of a level IMU rocking slowly at the steps given (s), the baro on every other one:
    step fuzzing (fuzz_ins.c: 0.1 ms to 10 s are sane, |gyro| dt <= 0.2 rad on integrated steps)."""
    rng = np.random.default_rng(seed)
    out = b""
    for k, dt in enumerate(steps):
        gyro = (0.01 * float(rng.standard_normal()), 0.01 * float(rng.standard_normal()), 0.0)
        accel = (0.05 * float(rng.standard_normal()), 0.05 * float(rng.standard_normal()), 9.9)
        out += raw_update(gyro, accel, (float("nan"),) * 3, 100.0 + 0.3 * float(rng.standard_normal())
                          if k % 2 == 0 else float("nan"), float(dt))
    return out


def seeds() -> dict:
    nan, inf = float("nan"), float("inf")
    return {
        "rest_then_rocking": bytes([0]) + flight(0, 1.5, 600),
        "rocking_no_rest": bytes([0]) + flight(1, 0.0, 400),
        "stationary_learning": edit(10, 0.2) + bytes([0]) + b"".join(
            update((0.001, 0.0, 0.0), LEVEL, (300.0, 0.0, -400.0) if k % 10 == 0 else None,
                   100.0 if k % 4 == 0 else nan, 0.01) for k in range(300)),
        "rejected_and_gaps": bytes([0]) + update((0.0, 0.0, 0.0), LEVEL)
        + raw_update((nan, 0, 0), LEVEL, (nan, nan, nan), nan, 0.01)
        + raw_update((0, 0, 0), (inf, 0, 0), (nan, nan, nan), nan, 0.01)
        + raw_update((0, 0, 0), LEVEL, (1.0, nan, 0.0), nan, 0.01)
        + raw_update((0, 0, 0), LEVEL, (nan, nan, nan), inf, 0.01)
        + raw_update((0, 0, 0), LEVEL, (nan, nan, nan), nan, 0.0)
        + raw_update((0, 0, 0), LEVEL, (nan, nan, nan), 100.0, 0.5)
        + b"".join(update((0.0, 0.0, 0.0), LEVEL, None, 100.0, 0.01) for _ in range(50)),
        "accel_rejection_recovery": edit(6, 0.2) + edit(5, 0.1) + bytes([0]) + update((0.0, 0.0, 0.0), LEVEL)
        + b"".join(update((0.0, 0.0, 0.0), (4.9, 0.0, 8.49)) for _ in range(60))
        + b"".join(update((0.0, 0.0, 0.0), (0.0, 0.0, 14.0)) for _ in range(20)),
        # step fuzzing: telemetry-like 0.1-4 s mixes (gaps at the default 0.1 s gap period, integrated with a 5 s
        # one: field 19), 0.1 ms steps, 10 s steps, and a baro that stops (timeout, dead-reckoning horizon)
        "steps_telemetry_mix": bytes([0]) + stepped([0.1, 0.2, 0.5, 1.0, 2.0, 4.0, 0.3, 1.5, 0.1, 3.0] * 6),
        "steps_telemetry_mix_integrated": edit(19, 5.0) + bytes([0]) + stepped([0.1, 0.2, 0.5, 1.0, 2.0, 4.0, 0.3] * 6),
        "steps_fine_and_long": bytes([0]) + stepped([1e-4] * 100 + [10.0, 1e-4, 10.0] + [1e-3, 0.01, 0.05] * 20),
        "baro_stops": bytes([0]) + flight(2, 1.0, 300) + b"".join(
            update((0.002, 0.0, 0.0), (0.0, 0.0, 10.1)) for _ in range(800)),
    }


if __name__ == "__main__":
    sys.exit(write_corpus(CORPUS, seeds, ".bin"))
