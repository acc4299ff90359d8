"""Writes the seed corpus of fuzz_observer.c into corpus_observer/ (committed).

    python3 csrc/fuzz/make_seeds_observer.py

Each seed is a loop dt and a call sequence in the format documented at the
top of fuzz_observer.c: a 100 Hz flight with a 25 Hz baro and a warm start,
baro gaps, rejected inputs, gain changes, presets, bandwidths and resets;
telemetry-like 0.1-4 s steps at the default and racing gains, steps from
0.1 ms to 10 s, and baro outages past the baro timeout (and an infinite one).
"""

import math
import struct
from pathlib import Path

CORPUS = Path(__file__).resolve().with_name("corpus_observer")
INITIALISE, SETTINGS, PRESET, BANDWIDTH, RESET, RESET_WITH_BIAS, UPDATE, UPDATE_LOOP = range(8)
NO_BARO = 8


def f(*values: float) -> bytes:
    return struct.pack(f"<{len(values)}f", *values)


def flight(steps: int, baro_every: int = 4, bias: float = 0.2) -> bytes:
    out = b""
    for k in range(steps):
        accel = 0.5 * math.sin(0.05 * k) + bias
        if k % baro_every == 0:
            out += bytes([UPDATE_LOOP]) + f(accel, 100.0 + 0.01 * k)
        else:
            out += bytes([UPDATE_LOOP | NO_BARO]) + f(accel, 0.0)
    return out


def steps(dts, baro_every: int = 1, accel: float = 0.3) -> bytes:
    """Updates with explicit steps (opcode 6): a slow climb, a baro sample on every baro_every-th step."""
    out = b""
    altitude = 100.0
    for k, dt in enumerate(dts):
        altitude += 2.0 * dt
        opcode = UPDATE if k % baro_every == 0 else UPDATE | NO_BARO
        out += bytes([opcode]) + f(accel, altitude, dt)
    return out


def telemetry_dts(count: int) -> list:
    """A deterministic telemetry-like mix: mostly 0.1 s, some 0.1-1 s, some 0.5-4 s (no random module needed)."""
    dts = []
    for k in range(count):
        u = ((k * 7919) % 100) / 100.0
        dts.append(0.1 if u < 0.6 else (0.1 + 0.9 * (u - 0.6) / 0.25 if u < 0.85 else 0.5 + 3.5 * (u - 0.85) / 0.15))
    return dts


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
    CORPUS.mkdir(exist_ok=True)
    for name, data in seeds().items():
        (CORPUS / name).write_bytes(data)
        print(f"{name}: {len(data)} bytes")
