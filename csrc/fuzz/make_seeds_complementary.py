"""Writes the seed corpus of fuzz_complementary.c into corpus_complementary/ (committed).

    python3 csrc/fuzz/make_seeds_complementary.py

Each seed is a loop dt and a call sequence in the format documented at the
top of fuzz_complementary.c: a 100 Hz flight with a 25 Hz baro, the write-up's
per-sample coefficients, telemetry-like 0.1-4 s steps, steps from 0.1 ms to
10 s, baro outages past the baro timeout (and an infinite one), rejected inputs.
"""

import sys
from functools import partial
from pathlib import Path

from make_seeds_common import explicit_steps, f, loop_flight, telemetry_dts, write_corpus

CORPUS = Path(__file__).resolve().with_name("corpus_complementary")
INITIALISE, SETTINGS, RESET, UPDATE, UPDATE_LOOP = 0, 1, 2, 3, 4
NO_BARO = 8
PER_SAMPLE = 16


def settings(tau_a=0.02, tau_b=0.05, c_v=0.999, c_h=0.998, t_v=9.99, t_h=4.99, gap=0.5, timeout=2.0,
             per_sample=False) -> bytes:
    return bytes([SETTINGS | (PER_SAMPLE if per_sample else 0)]) + f(tau_a, tau_b, c_v, c_h, t_v, t_h, gap, timeout)


#: 100 Hz updates at the loop dt, a baro sample on every baro_every-th (make_seeds_common.loop_flight)
flight = partial(loop_flight, UPDATE_LOOP, NO_BARO, bias=0.1)
#: updates with explicit steps, a slow climb (make_seeds_common.explicit_steps)
steps = partial(explicit_steps, UPDATE, NO_BARO)


def seeds() -> dict:
    nan, inf = float("nan"), float("inf")
    return {
        "flight_100hz": f(0.01) + flight(300),
        "per_sample_coefficients": f(0.01) + settings(per_sample=True) + flight(200, 2),
        "telemetry_steps": f(0.1) + settings(gap=1.0) + flight(5, 1) + steps(telemetry_dts(150)),
        "steps_0_1_ms_to_10_s": f(0.01) + settings(gap=10.0) + flight(5, 1)
        + steps([1e-4 * 10 ** (5 * k / 60) for k in range(61)] + [10.0, 1e-4, 3.0, 0.02], 2),
        "baro_timeout_outage": f(0.01) + flight(50, 1) + settings(timeout=0.5) + flight(100, 1000) + flight(20, 1)
        + settings(timeout=inf) + flight(300, 1000) + flight(10, 1),
        "rejected_inputs": f(0.01) + flight(8) + bytes([UPDATE]) + f(inf, 1.0, 0.01) + bytes([UPDATE]) + f(0.0, -inf, 0.01)
        + bytes([UPDATE]) + f(0.0, 1.0, 0.0) + bytes([UPDATE]) + f(0.0, 1.0, nan) + bytes([RESET]) + f(nan)
        + settings(tau_a=-1.0) + settings(c_v=1.5) + settings(gap=0.0) + settings(timeout=nan) + flight(8),
        "reset_and_reinitialise": f(0.005) + flight(30, 8) + bytes([RESET]) + f(-20.0) + flight(30, 8)
        + bytes([INITIALISE]) + flight(30, 8),
    }


if __name__ == "__main__":
    sys.exit(write_corpus(CORPUS, seeds))
