"""Writes the seed corpus of fuzz_kalman.c into corpus_kalman/ (committed).

    python3 csrc/fuzz/make_seeds_kalman.py

Each seed is a loop dt and a call sequence in the format documented at the
top of fuzz_kalman.c: 100 Hz flights with baro, rangefinder and GPS (first
samples, NaN gaps), gating rejections and resets after the timeout, a terrain
step, ground effect, bias estimation off, settings edits (accepted and
rejected) and rejected updates.
"""

import math
import struct
import sys
from pathlib import Path

from fusion_altitude._c_tables import KALMAN_SETTINGS
from make_seeds_common import f, write_corpus

CORPUS = Path(__file__).resolve().with_name("corpus_kalman")
INITIALISE, INITIALISE_WITH, SET_SETTINGS, EDIT, UPDATE, UPDATE_LOOP, UPDATE_NULL, DEFAULTS = range(8)
BARO, RANGE, GPS, GROUND_EFFECT, ACCURACY, SATELLITES = 1, 2, 4, 8, 16, 32
#: The settings words an EDIT reaches, in the struct's order: the C names of the generated table (the decoder,
#: FusionAltitudeKalmanSettingsSetWord in csrc/tests/vectors/kalman_settings_words.h, has the same order).
FIELDS = tuple(c_name for _, c_name, *_ in KALMAN_SETTINGS)
STEPPED = 0x80  # with UPDATE_LOOP or UPDATE_NULL: a step byte follows the opcode (fuzz_kalman.c StepFromByte)
#: fuzz_kalman.c StepFromByte's 16 base steps, s (the step byte's low nibble)
BASE_STEPS = (1e-4, 5e-4, 1e-3, 2e-3, 5e-3, 0.01, 0.02, 0.05, 0.1, 0.25, 0.5, 1.0, 2.0, 4.0, 7.0, 10.0)


def edit(field: str, value) -> bytes:
    index = FIELDS.index(field)
    word = struct.pack("<i", value) if isinstance(value, (bool, int)) else f(value)
    return bytes([EDIT, index]) + word


def flight(steps: int, baro_every=4, range_every=5, gps_every=20, baro_shift=0.0, gps_shift=0.0, terrain=0.0,
           ground_effect=False) -> bytes:
    out = b""
    for k in range(steps):
        h = 0.5 + 0.02 * k
        accel = 0.3 * math.sin(0.05 * k) + 0.1
        flags = GROUND_EFFECT if ground_effect else 0
        floats = []
        if baro_every and k % baro_every == 0:
            flags |= BARO
            floats.append(120.0 + h + baro_shift)
        if range_every and k % range_every == 0:
            flags |= RANGE
            floats.append(h - terrain)
        if gps_every and k % gps_every == 0:
            flags |= GPS | SATELLITES
            floats.append(160.0 + h + gps_shift)
        out += bytes([UPDATE_LOOP]) + f(accel) + bytes([flags]) + f(*floats)
        if flags & SATELLITES:
            out += struct.pack("<i", 9)
    return out


def stepped(step_bytes, baro_every=1, gps_every=2, range_every=0, dropout=None) -> bytes:
    """Updates at the steps of ``step_bytes`` (StepFromByte), baro on every baro_every-th, GPS on every
    gps_every-th, rangefinder on every range_every-th (0: none); no baro for the steps in ``dropout`` (a range)."""
    out = b""
    t = 0.0
    for k, code in enumerate(step_bytes):
        t += BASE_STEPS[code & 15] * (1 + (code >> 4) / 32)
        h = 2.0 + 0.5 * math.sin(0.3 * t)
        flags, floats = 0, []
        if baro_every and k % baro_every == 0 and not (dropout and k in dropout):
            flags |= BARO
            floats.append(120.0 + h)
        if range_every and k % range_every == 0:
            flags |= RANGE
            floats.append(h)
        if gps_every and k % gps_every == 0:
            flags |= GPS
            floats.append(160.0 + h)
        out += bytes([UPDATE_LOOP | STEPPED, code]) + f(0.1 * math.cos(0.3 * t)) + bytes([flags]) + f(*floats)
    return out


def seeds() -> dict:
    nan, inf = float("nan"), float("inf")
    return {
        "three_sensors_100hz": f(0.01) + flight(400),
        "gaps_and_null": f(0.01) + flight(40) + bytes([UPDATE_NULL]) + f(0.1) * 1 + bytes([UPDATE_NULL]) + f(0.1)
        + flight(40, baro_every=0, gps_every=0) + flight(40, range_every=0),
        "rejections_and_resets": f(0.01) + edit("rejectionTimeout", 0.1) + bytes([SET_SETTINGS]) + flight(60)
        + flight(30, baro_shift=25.0) + flight(60, gps_every=4, gps_shift=-12.0) + flight(40, terrain=1.5),
        "ground_effect_landing": f(0.01) + flight(60) + flight(80, ground_effect=True, baro_shift=-0.8),
        "bias_off_and_on": f(0.02) + flight(40) + edit("estimateAccelBias", 0) + bytes([SET_SETTINGS]) + flight(40)
        + edit("estimateAccelBias", 1) + bytes([SET_SETTINGS]) + flight(40),
        "settings_edits": f(0.005) + edit("baroNoise", 0.0) + bytes([SET_SETTINGS, INITIALISE_WITH])
        + edit("baroNoise", 0.3) + edit("rangeMaximum", 30.0) + edit("gpsMinimumSatellites", 6)
        + bytes([INITIALISE_WITH]) + flight(60) + edit("gate", nan) + bytes([SET_SETTINGS]) + bytes([DEFAULTS])
        + flight(20) + bytes([INITIALISE]) + flight(20),
        "rejected_updates": f(0.01) + flight(20)
        + bytes([UPDATE]) + f(inf, 0.01, 120.0, 1.0, 160.0, nan) + struct.pack("<i", 9) + bytes([0])
        + bytes([UPDATE]) + f(0.0, 0.0, 120.0, 1.0, 160.0, nan) + struct.pack("<i", 9) + bytes([0])
        + bytes([UPDATE]) + f(0.0, 0.01, -inf, 1.0, 160.0, nan) + struct.pack("<i", 9) + bytes([0])
        + bytes([UPDATE]) + f(0.0, 0.01, 120.0, 1.0, inf, nan) + struct.pack("<i", 9) + bytes([0])
        + bytes([UPDATE]) + f(0.0, 0.01, 120.0, 1.0, 160.0, -1.0) + struct.pack("<i", -1) + bytes([1])
        + bytes([UPDATE]) + f(0.0, 0.01, 120.5, 1.2, 160.5, 0.7) + struct.pack("<i", 3) + bytes([1]) + flight(20),
        # step fuzzing: telemetry-like 0.1-4 s mixes, 0.1 ms steps, 10 s steps, jitter; a baro dropout (timeouts)
        "steps_telemetry_mix": f(0.01) + stepped([8, 9, 10, 11, 12, 13, 0x98, 0x3A, 0xF9, 12, 8, 13, 10] * 4),
        "steps_fine_and_long": f(0.01) + stepped([0] * 50 + [15, 0x1F, 15] + [1, 2, 3, 4] * 10 + [14, 15]),
        "steps_baro_dropout_gps_carries": f(0.01) + flight(100) + stepped([5] * 600, gps_every=20, range_every=5,
                                                                          dropout=range(100, 400)),
        "steps_sensor_timeouts_edited": f(0.01) + edit("baroTimeout", 0.05) + edit("gpsTimeout", 0.2)
        + edit("rangeTimeout", 1e-3) + edit("gapPeriod", 20.0) + bytes([SET_SETTINGS])
        + stepped([5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15] * 3, gps_every=3, range_every=2)
        + bytes([UPDATE_NULL | STEPPED, 15]) + f(3.0) + bytes([UPDATE_NULL | STEPPED, 0]) + f(-1e3)
        + edit("baroTimeout", 0.0) + bytes([SET_SETTINGS]),
    }


if __name__ == "__main__":
    sys.exit(write_corpus(CORPUS, seeds))
