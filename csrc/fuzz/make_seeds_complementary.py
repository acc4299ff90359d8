"""Writes the seed corpus of fuzz_complementary.c into corpus_complementary/ (committed).

    python3 csrc/fuzz/make_seeds_complementary.py

Each seed is a loop dt and a call sequence in the format documented at the
top of fuzz_complementary.c: a 100 Hz flight with a 25 Hz baro, the write-up's
per-sample coefficients, telemetry-like 0.1-4 s steps, steps from 0.1 ms to
10 s, baro outages past the baro timeout (and an infinite one), rejected inputs.
"""

import math
import struct
from pathlib import Path

CORPUS = Path(__file__).resolve().with_name("corpus_complementary")
INITIALISE, SETTINGS, RESET, UPDATE, UPDATE_LOOP = 0, 1, 2, 3, 4
NO_BARO = 8
PER_SAMPLE = 16


def f(*values: float) -> bytes:
    return struct.pack(f"<{len(values)}f", *values)


def settings(tau_a=0.02, tau_b=0.05, c_v=0.999, c_h=0.998, t_v=9.99, t_h=4.99, gap=0.5, timeout=2.0,
             per_sample=False) -> bytes:
    return bytes([SETTINGS | (PER_SAMPLE if per_sample else 0)]) + f(tau_a, tau_b, c_v, c_h, t_v, t_h, gap, timeout)


def flight(steps: int, baro_every: int = 4, bias: float = 0.1) -> bytes:
    out = b""
    for k in range(steps):
        accel = 0.5 * math.sin(0.05 * k) + bias
        if k % baro_every == 0:
            out += bytes([UPDATE_LOOP]) + f(accel, 100.0 + 0.01 * k)
        else:
            out += bytes([UPDATE_LOOP | NO_BARO]) + f(accel, 0.0)
    return out


def steps(dts, baro_every: int = 1, accel: float = 0.3) -> bytes:
    out = b""
    altitude = 100.0
    for k, dt in enumerate(dts):
        altitude += 2.0 * dt
        opcode = UPDATE if k % baro_every == 0 else UPDATE | NO_BARO
        out += bytes([opcode]) + f(accel, altitude, dt)
    return out


def telemetry_dts(count: int) -> list:
    dts = []
    for k in range(count):
        u = ((k * 7919) % 100) / 100.0
        dts.append(0.1 if u < 0.6 else (0.1 + 0.9 * (u - 0.6) / 0.25 if u < 0.85 else 0.5 + 3.5 * (u - 0.85) / 0.15))
    return dts


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
    CORPUS.mkdir(exist_ok=True)
    for name, data in seeds().items():
        (CORPUS / name).write_bytes(data)
        print(f"{name}: {len(data)} bytes")
