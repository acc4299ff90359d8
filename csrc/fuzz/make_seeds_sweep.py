"""Writes the seed corpus of fuzz_sweep.c into corpus_sweep/ (committed).

    python3 csrc/fuzz/make_seeds_sweep.py

Each seed is a setting count, a time split, the gains and samples in the
format documented at the top of fuzz_sweep.c: the presets side by side over a
25 Hz baro, telemetry-like 0.1-4 s steps (the stability rule differs between
the settings), steps from 0.1 ms to 10 s and a baro outage past the timeout.
"""

import math
import sys
from pathlib import Path

from make_seeds_common import f, write_corpus

CORPUS = Path(__file__).resolve().with_name("corpus_sweep")
PRESETS = ((0.32, 0.0512, 0.0016), (0.8, 0.32, 0.025), (2.4, 2.88, 0.675), (8.0, 32.0, 25.0), (1.4, 1.0, 0.0))
NO_BARO, EXPLICIT_DT = 1, 2


def header(gains, split: int) -> bytes:
    return bytes([len(gains) - 1, split]) + b"".join(f(*g) for g in gains)


def sample(accel: float, baro, dt: float) -> bytes:
    control = EXPLICIT_DT | (NO_BARO if baro is None else 0)
    return bytes([control]) + f(accel) + (b"" if baro is None else f(baro)) + f(dt)


def flight(steps: int, dt: float = 0.01, baro_every: int = 4) -> bytes:
    return b"".join(sample(0.2 * math.sin(0.05 * k), 100.0 + 0.01 * k if k % baro_every == 0 else None, dt)
                    for k in range(steps))


def telemetry(count: int) -> bytes:
    out = b""
    altitude = 100.0
    for k in range(count):
        u = ((k * 7919) % 100) / 100.0
        dt = 0.1 if u < 0.6 else (0.1 + 0.9 * (u - 0.6) / 0.25 if u < 0.85 else 0.5 + 3.5 * (u - 0.85) / 0.15)
        altitude += 2.0 * dt
        out += sample(0.3, altitude if k % 10 else None, dt)
    return out


def seeds() -> dict:
    return {
        "presets_25hz_baro": header(PRESETS, 77) + flight(200),
        "telemetry_steps": header(PRESETS[:4], 33) + flight(5, 0.1, 1) + telemetry(150),
        "steps_0_1_ms_to_10_s": header(PRESETS[1:3], 10) + flight(5, 0.01, 1)
        + b"".join(bytes([k << 2]) + f(0.3, 100.0) for k in range(64)),
        "baro_outage": header(PRESETS[2:4], 200) + flight(50, 0.01, 1) + flight(300, 0.01, 1000) + flight(10, 0.01, 1),
    }


if __name__ == "__main__":
    sys.exit(write_corpus(CORPUS, seeds))
