"""What the seed scripts of the estimator fuzzers share (``make_seeds_<name>.py``, run as scripts from this folder).

- :func:`f`: floats as little-endian float32 bytes (a fuzzer's ``ReadFloat``);
- :func:`loop_flight` and :func:`explicit_steps`: the observer-shaped update streams of ``fuzz_observer.c`` and
  ``fuzz_complementary.c`` (opcode, accel m/s^2, baro m, and for explicit steps dt s; a no-baro bit);
- :func:`telemetry_dts`: a deterministic telemetry-like mix of steps, s;
- :func:`write_corpus`: writes the seeds into the fuzzer's corpus folder.
"""

from __future__ import annotations

import math
import struct
import sys
from pathlib import Path
from typing import Callable, Dict, Iterable


def f(*values: float) -> bytes:
    """The values as little-endian float32s."""
    return struct.pack(f"<{len(values)}f", *values)


def loop_flight(update_loop: int, no_baro: int, steps: int, baro_every: int = 4, bias: float = 0.2) -> bytes:
    """``steps`` updates at the loop dt: accel 0.5 sin(0.05 k) + bias (m/s^2), a baro sample 100 + 0.01 k (m) on every
    ``baro_every``-th, the others with the no-baro bit (baro 0)."""
    out = b""
    for k in range(steps):
        accel = 0.5 * math.sin(0.05 * k) + bias
        if k % baro_every == 0:
            out += bytes([update_loop]) + f(accel, 100.0 + 0.01 * k)
        else:
            out += bytes([update_loop | no_baro]) + f(accel, 0.0)
    return out


def explicit_steps(update: int, no_baro: int, dts: Iterable[float], baro_every: int = 1, accel: float = 0.3) -> bytes:
    """Updates with explicit steps ``dts`` (s): a slow climb (2 m/s from 100 m), a baro sample on every
    ``baro_every``-th step."""
    out = b""
    altitude = 100.0
    for k, dt in enumerate(dts):
        altitude += 2.0 * dt
        opcode = update if k % baro_every == 0 else update | no_baro
        out += bytes([opcode]) + f(accel, altitude, dt)
    return out


def telemetry_dts(count: int) -> list:
    """A deterministic telemetry-like mix of steps (s): mostly 0.1 s, some 0.1-1 s, some 0.5-4 s."""
    dts = []
    for k in range(count):
        u = ((k * 7919) % 100) / 100.0
        dts.append(0.1 if u < 0.6 else (0.1 + 0.9 * (u - 0.6) / 0.25 if u < 0.85 else 0.5 + 3.5 * (u - 0.85) / 0.15))
    return dts


def write_corpus(corpus: Path, seeds: Callable[[], Dict[str, bytes]], suffix: str = "") -> int:
    """Writes every seed as ``corpus/<name><suffix>`` and prints its size; the exit status (0)."""
    corpus.mkdir(exist_ok=True)
    for name, data in seeds().items():
        (corpus / f"{name}{suffix}").write_bytes(data)
        print(f"{name}{suffix}: {len(data)} bytes")
    return 0


if __name__ == "__main__":
    sys.exit("make_seeds_common.py is imported by the make_seeds_<name>.py scripts; run one of them")
