"""Writes the seed corpus of fuzz_rocket.c: csrc/fuzz/corpus_rocket/*.bin.

    python csrc/fuzz/make_seeds_rocket.py

Each seed is a sequence of calls in fuzz_rocket.c's format: simulated rocket
flights (fusion_altitude.rocket_sim, pad to landing) as scaled updates, with
and without the vertical-accel (INS) update, baro dropouts, settings edits,
and raw updates with NaN, infinite and zero inputs and a gap.
"""

from __future__ import annotations

import struct
import sys
from pathlib import Path

import numpy as np

from fusion_altitude._core._c_tables import ROCKET_SETTINGS, OBSERVER_SETTINGS
from make_seeds_common import write_corpus

CORPUS = Path(__file__).resolve().parent / "corpus_rocket"
#: The settings words of csrc/tests/vectors/rocket_settings_words.h (an edit's index): FusionAltitudeRocketSettings in
#: struct order, the nested observer settings flattened ("observer.positionGain", ...).
FIELDS = tuple(name for _, c_name, kind, *_ in ROCKET_SETTINGS
               for name in ([f"{c_name}.{sub}" for _, sub, *_ in OBSERVER_SETTINGS] if kind == "s" else [c_name]))

#: dt ranges of fuzz_rocket.c's scaled update (flags bits 2-3), s.
DT_RANGES = ((1e-3, 0.05), (1e-4, 10.0), (0.1, 4.0), (1e-4, 0.05))


def scaled(value: float, minimum: float, maximum: float) -> bytes:
    raw = int(round((min(max(value, minimum), maximum) - minimum) / (maximum - minimum) * 65535.0))
    return struct.pack("<H", raw)


def update(accel: float, baro: float, dt: float, vertical: bool = False, dt_range: int = 0) -> bytes:
    """A scaled update; accel NaN: no accelerometer sample; ``dt_range`` indexes DT_RANGES."""
    flags = (0 if np.isnan(baro) else 1) | (2 if np.isnan(accel) else 0) | (dt_range << 2)
    return (bytes([3 | (4 if vertical else 0)]) + scaled(0.0 if np.isnan(accel) else accel, -300.0, 300.0)
            + bytes([flags]) + scaled(0.0 if np.isnan(baro) else baro, -1e4, 1e5) + scaled(dt, *DT_RANGES[dt_range]))


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


def telemetry_flight(seed: int, accel: bool = True) -> bytes:
    """A flight as a 10 Hz telemetry log with gaps of 0.6-4 s (rocket_sim.telemetry_indices), dt range [0.1, 4] s;
    without ``accel`` every accel is NaN (a baro-only log: launch from the baro)."""
    from fusion_altitude.rocket_sim import RocketFlightModel, simulate_rocket_flight, telemetry_indices

    sim = simulate_rocket_flight(seed, RocketFlightModel(burn_time=2.5, main_altitude=300.0))
    indices = telemetry_indices(sim, seed, gap_probability=0.1)
    out = b""
    for previous, k in zip(indices[:-1], indices[1:]):
        value = float(sim.accel[k]) if accel else float("nan")
        out += update(value, float(sim.baro_altitude[k]), float(sim.time[k] - sim.time[previous]), dt_range=2)
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
        "telemetry_gaps": bytes([0]) + telemetry_flight(3),
        "telemetry_baro_only": bytes([0]) + telemetry_flight(4, accel=False),
        "accel_lost_long_steps": bytes([0]) + flight(5, 4)[:3000] + b"".join(
            update(float("nan"), 1400.0 + 300.0 - 9.0 * i, 2.5 if i % 3 else 7.0, dt_range=1) for i in range(60)),
        "bad_settings": edit("offsetRate", 2.0) + bytes([0]) + edit("offsetRate", 0.5) + edit("gapPeriod", float("nan"))
        + bytes([0]) + edit("gapPeriod", 0.2) + bytes([0]) + b"".join(update(0.0, 50.0, 0.02) for _ in range(100)),
    }


if __name__ == "__main__":
    sys.exit(write_corpus(CORPUS, seeds, ".bin"))
