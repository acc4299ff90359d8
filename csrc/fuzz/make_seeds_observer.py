"""Writes the seed corpus of fuzz_observer.c into corpus_observer/ (committed).

    python3 csrc/fuzz/make_seeds_observer.py

Each seed is a loop dt and a call sequence in the format documented at the
top of fuzz_observer.c: a 100 Hz flight with a 25 Hz baro and a warm start,
baro gaps, rejected inputs, gain changes, presets, bandwidths and resets;
telemetry-like 0.1-4 s steps at the default and racing gains, steps from
0.1 ms to 10 s, and baro outages past the baro timeout (and an infinite one).
"""

import sys
from functools import partial
from pathlib import Path

from make_seeds_common import explicit_steps, f, loop_flight, telemetry_dts, write_corpus

CORPUS = Path(__file__).resolve().with_name("corpus_observer")
INITIALISE, SETTINGS, PRESET, BANDWIDTH, RESET, RESET_WITH_BIAS, UPDATE, UPDATE_LOOP = range(8)
NO_BARO = 8


#: 100 Hz updates at the loop dt, a baro sample on every baro_every-th (make_seeds_common.loop_flight)
flight = partial(loop_flight, UPDATE_LOOP, NO_BARO)
#: updates with explicit steps, a slow climb (make_seeds_common.explicit_steps)
steps = partial(explicit_steps, UPDATE, NO_BARO)


def seeds() -> dict:
    nan, inf = float("nan"), float("inf")
    return {
        "flight_100hz_warm_start": f(0.01) + bytes([RESET_WITH_BIAS]) + f(100.0, 0.2) + flight(200),
        "auto_zero_then_gap": f(0.01) + bytes([UPDATE_LOOP | NO_BARO]) + f(0.1, 0.0) + flight(40, 1)
        + flight(60, 1000),
        "rejected_inputs": f(0.01) + flight(8)
        + bytes([UPDATE]) + f(inf, 1.0, 0.01) + bytes([UPDATE]) + f(0.0, -inf, 0.01)
        + bytes([UPDATE]) + f(0.0, 1.0, 0.0) + bytes([UPDATE]) + f(0.0, 1.0, -0.01)
        + bytes([UPDATE]) + f(0.0, 1.0, nan) + bytes([RESET]) + f(nan) + bytes([RESET_WITH_BIAS]) + f(1.0, inf)
        + bytes([SETTINGS]) + f(-1.0, 1.0, 0.1) + bytes([SETTINGS]) + f(1.0, 1.0, 2.0)
        + bytes([BANDWIDTH]) + f(0.0, 0.7, 0.1) + bytes([PRESET, 9]) + flight(8),
        "retune_mid_flight": f(0.02) + flight(50, 5) + bytes([PRESET, 3]) + flight(50, 5)
        + bytes([BANDWIDTH]) + f(0.8, 0.7, 0.16) + flight(50, 5) + bytes([SETTINGS]) + f(1.0, 0.5, 0.0)
        + flight(50, 5),
        "reset_and_reinitialise": f(0.005) + flight(30, 8) + bytes([RESET]) + f(-20.0) + flight(30, 8)
        + bytes([INITIALISE]) + flight(30, 8),
        "pure_integration": f(0.1) + bytes([SETTINGS]) + f(0.0, 0.0, 0.0) + bytes([RESET]) + f(0.0)
        + flight(100, 1),
        "telemetry_steps_default": f(0.1) + flight(10, 1) + steps(telemetry_dts(150)),
        "telemetry_steps_racing": f(0.1) + bytes([PRESET, 3]) + flight(10, 1) + steps(telemetry_dts(150), 1, 2.0),
        "steps_0_1_ms_to_10_s": f(0.01) + flight(10, 1)
        + steps([1e-4 * 10 ** (5 * k / 60) for k in range(61)] + [10.0, 1e-4, 3.0, 0.02], 2),
        "baro_timeout_outage": f(0.01) + flight(50, 1) + bytes([SETTINGS | 16]) + f(0.5) + flight(100, 1000)
        + flight(20, 1) + bytes([SETTINGS | 16]) + f(inf) + flight(300, 1000) + flight(10, 1),
    }


if __name__ == "__main__":
    sys.exit(write_corpus(CORPUS, seeds))
