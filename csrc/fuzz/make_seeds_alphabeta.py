"""Writes the seed corpus of fuzz_alphabeta.c into corpus_alphabeta/ (committed).

    python3 csrc/fuzz/make_seeds_alphabeta.py

Each seed is a loop dt and a call sequence in the format documented at the
top of fuzz_alphabeta.c: a 100 Hz flight with baro, lidar and GPS, a baro
dropout the GPS carries (sensor timeouts), a glitching lidar beyond its gap
maximum, step sequences from 0.1 ms to 10 s (telemetry-like 0.1-4 s mixes,
alternating short and long steps: the interval rule), settings edits
(accepted and rejected) and rejected updates.
"""

import math
import struct
import sys
from pathlib import Path

from fusion_altitude._core._c_tables import ALPHABETA_SENSORS, ALPHABETA_SENSOR_FIELDS, ALPHABETA_SETTINGS
from make_seeds_common import f, write_corpus

CORPUS = Path(__file__).resolve().with_name("corpus_alphabeta")
INITIALISE, INITIALISE_WITH, SET_SETTINGS, EDIT, UPDATE, UPDATE_STEP, UPDATE_LOOP, DEFAULTS = range(8)
ACCEL, BARO, LIDAR, SONAR, GPS = 1, 2, 4, 8, 16
#: The settings words of csrc/tests/vectors/alphabeta_settings_words.h (an edit's index): each sensor's fields, in
#: FusionAltitudeAlphaBetaSensorIndex order, then the other fields (the gap period).
WORDS = tuple(f"{sensor}.{c_name}" for sensor in ALPHABETA_SENSORS for _, c_name, *_ in ALPHABETA_SENSOR_FIELDS) + tuple(
    c_name for _, c_name, *_ in ALPHABETA_SETTINGS)
#: fuzz_alphabeta.c StepFromByte's 16 base steps, s (the step byte's low nibble)
BASE_STEPS = (1e-4, 5e-4, 1e-3, 2e-3, 5e-3, 0.01, 0.02, 0.05, 0.1, 0.25, 0.5, 1.0, 2.0, 4.0, 7.0, 10.0)


def edit(word: str, value) -> bytes:
    """Sets one settings word ("baro.qualityMin", "gapPeriod"): an int as int32, else float32 bits."""
    packed = struct.pack("<i", value) if isinstance(value, int) else f(value)
    return bytes([EDIT, WORDS.index(word)]) + packed


def present(accel, baro=None, lidar=None, sonar=None, gps=None) -> bytes:
    flags, floats = 0, []
    for bit, value in ((ACCEL, accel), (BARO, baro), (LIDAR, lidar), (SONAR, sonar), (GPS, gps)):
        if value is not None:
            flags |= bit
            floats.append(value)
    return bytes([flags]) + f(*floats)


def flight(steps: int, baro_every=4, lidar_every=5, gps_every=20, baro_from=None, lidar_shift=0.0) -> bytes:
    """100 Hz updates at the loop dt: a climb from 0.5 m with baro, lidar and GPS (None: that sensor off)."""
    out = b""
    for k in range(steps):
        h = 0.5 + 0.02 * k
        out += bytes([UPDATE_LOOP]) + present(
            0.3 * math.sin(0.05 * k),
            baro=120.0 + h if baro_every and k % baro_every == 0 and (baro_from is None or k < baro_from) else None,
            lidar=h + lidar_shift if lidar_every and k % lidar_every == 0 else None,
            gps=120.0 + h + 1.0 if gps_every and k % gps_every == 0 else None)
    return out


def stepped(codes, every=1) -> bytes:
    """Updates at the steps of ``codes`` (StepFromByte), a baro sample on every ``every``-th, GPS on every 3rd."""
    out = b""
    t = 0.0
    for k, code in enumerate(codes):
        t += BASE_STEPS[code & 15] * (1 + (code >> 4) / 32)
        h = 50.0 + 2.0 * math.sin(0.2 * t)
        out += bytes([UPDATE_STEP, code]) + present(
            -0.08 * math.sin(0.2 * t), baro=h if k % every == 0 else None, gps=h + 3.0 if k % 3 == 0 else None)
    return out


def seeds() -> dict:
    nan, inf = float("nan"), float("inf")
    return {
        "three_sensors_100hz": f(0.01) + flight(400),
        "baro_dropout_gps_carries": f(0.01) + flight(100) + flight(500, baro_from=0, lidar_every=0, gps_every=10),
        "lidar_glitch_beyond_gap": f(0.01) + flight(100) + flight(60, lidar_shift=10.0) + flight(100),
        "steps_telemetry_mix": f(0.01) + stepped([8, 9, 10, 11, 12, 13, 0x98, 0x3A, 0xF9, 12, 8, 13, 10] * 4),
        "steps_alternating_short_long": f(0.01) + edit("gapPeriod", 20.0)
        + b"".join(edit(f"{s}.timeout", 20.0) for s in ALPHABETA_SENSORS) + bytes([INITIALISE_WITH])
        + stepped([0, 12] * 60) + stepped([2, 0x7C] * 30),
        "steps_fine_and_long": f(0.01) + stepped([0] * 50 + [15, 0x1F, 15] + [1, 2, 3, 4] * 10 + [14, 15], every=2),
        "settings_edits": f(0.005) + edit("baro.qualityMin", 1) + bytes([SET_SETTINGS, INITIALISE_WITH])
        + edit("baro.qualityMin", 3) + edit("lidar.altitudeMax", 30.0) + edit("gps.confidence", 0.01)
        + bytes([INITIALISE_WITH]) + flight(60) + edit("imu.threshold", nan) + bytes([SET_SETTINGS])
        + edit("gapPeriod", inf) + bytes([DEFAULTS]) + flight(20) + bytes([INITIALISE]) + flight(20),
        "rejected_updates": f(0.01) + flight(20)
        + bytes([UPDATE]) + f(inf, 0.01, 120.0, 1.0, nan, 121.0)
        + bytes([UPDATE]) + f(0.0, 0.0, 120.0, 1.0, nan, 121.0)
        + bytes([UPDATE]) + f(0.0, 0.01, -inf, 1.0, nan, 121.0)
        + bytes([UPDATE]) + f(0.0, 0.01, 120.0, inf, nan, 121.0)
        + bytes([UPDATE]) + f(0.0, 0.01, 120.0, 1.0, -inf, 121.0)
        + bytes([UPDATE]) + f(0.0, 0.01, 120.0, 1.0, nan, inf)
        + bytes([UPDATE]) + f(nan, 0.02, 120.1, nan, 1.1, 121.1) + flight(20),
    }


if __name__ == "__main__":
    sys.exit(write_corpus(CORPUS, seeds))
