"""Writes the seed corpus of fuzz_flight.c: csrc/fuzz/corpus_flight/*.bin.

    python csrc/fuzz/make_seeds_flight.py

Each seed is a sequence of calls in fuzz_flight.c's format: simulated rocket
flights (fusion_altitude.rocket_sim, pad to landing) as scaled updates, with
and without the vertical-accel (INS) update, baro dropouts, settings edits,
and raw updates with NaN, infinite and zero inputs and a gap.
"""

from __future__ import annotations

import struct
import sys
from pathlib import Path

import numpy as np

CORPUS = Path(__file__).resolve().parent / "corpus_flight"
FIELDS = ("positionGain", "velocityGain", "biasGain", "observerGapPeriod", "stationaryAccel", "calibrationWindow",
          "launchAccel", "launchTime", "burnoutAccel", "burnoutTime", "apogeeMargin", "lockoutSpeed", "spikeThreshold",
          "spikeTime", "offsetRate", "mainAltitude", "landedSpeed", "landedTime", "gapPeriod")


def scaled(value: float, minimum: float, maximum: float) -> bytes:
    raw = int(round((min(max(value, minimum), maximum) - minimum) / (maximum - minimum) * 65535.0))
    return struct.pack("<H", raw)


def update(accel: float, baro: float, dt: float, vertical: bool = False) -> bytes:
    presence = 0 if np.isnan(baro) else 1
    return (bytes([3 | (4 if vertical else 0)]) + scaled(accel, -300.0, 300.0) + bytes([presence])
            + scaled(0.0 if np.isnan(baro) else baro, -1e4, 1e5) + scaled(dt, 1e-3, 0.05))


def raw_update(accel: float, baro: float, dt: float) -> bytes:
    return bytes([2]) + struct.pack("<fff", accel, baro, dt)


def edit(field: str, value: float) -> bytes:
    return bytes([1, FIELDS.index(field)]) + struct.pack("<f", value)


def flight(seed: int, stride: int, vertical: bool = False, dropout: int = 0) -> bytes:
    from fusion_altitude.rocket_sim import RocketFlightModel, simulate_rocket_flight

    sim = simulate_rocket_flight(seed, RocketFlightModel(burn_time=2.5, main_altitude=300.0))
    out = b""
    for k in range(0, len(sim.time), stride):
        baro = float(sim.baro_altitude[k])
        if dropout and (k // stride) % dropout == 0:
            baro = float("nan")
        out += update(float(sim.accel[k]), baro, float(sim.dt * stride), vertical)
    return out


def seeds() -> dict:
    return {
        "flight_25hz": bytes([0]) + flight(0, 4),
        "flight_vertical_main_400": edit("mainAltitude", 400.0) + edit("lockoutSpeed", 80.0) + bytes([0])
        + flight(1, 4, vertical=True),
        "flight_dropouts": bytes([4]) + flight(2, 5, dropout=3),
        "rejected_and_gap": bytes([0]) + raw_update(float("nan"), 100.0, 0.01) + raw_update(0.0, float("inf"), 0.01)
        + raw_update(0.0, 100.0, 0.0) + raw_update(0.0, 100.0, -0.01) + raw_update(0.0, float("nan"), 2.0)
        + b"".join(update(0.0, 100.0, 0.01) for _ in range(200)) + raw_update(0.0, 100.0, 5.0),
        "bad_settings": edit("offsetRate", 2.0) + bytes([0]) + edit("offsetRate", 0.5) + edit("gapPeriod", float("nan"))
        + bytes([0]) + edit("gapPeriod", 0.2) + bytes([0]) + b"".join(update(0.0, 50.0, 0.02) for _ in range(100)),
    }


def main() -> int:
    CORPUS.mkdir(exist_ok=True)
    for name, data in seeds().items():
        (CORPUS / f"{name}.bin").write_bytes(data)
        print(f"{name}.bin: {len(data)} bytes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
