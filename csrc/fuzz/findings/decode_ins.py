"""Decode a fuzz_ins.c input (csrc/fuzz/fuzz_ins.c documents the format) into
the sequence of calls it makes, and write the INS update steps of one as a C
header for csrc/tests/test_ins.c.

    python csrc/fuzz/findings/decode_ins.py csrc/fuzz/findings/ins_negative_attitude_variance.bin \
        csrc/tests/ins_negative_attitude_variance.h
    python csrc/fuzz/findings/decode_ins.py csrc/fuzz/findings/ins_attitude_variance_growth.bin \
        csrc/tests/ins_attitude_variance_growth.h insGrowth

Calls: ("initialise", settings_list) | ("settings", settings_list) |
("update", gyro, accel, mag, baro, dt) with float32 values exactly as the
fuzzer passes them (settings_list: the fuzzer's working settings, 25 float32
in the C struct order). numpy only.
"""

import struct
import sys
from pathlib import Path

import numpy as np

f32 = np.float32
FIELDS = 23
# the settings in C struct order; the fuzzer edits the first FIELDS (baroTimeout and deadReckoningHorizon, added
# after the findings, keep their defaults there)
DEFAULTS = [3e-4, 1e-5, 0.05, 0.05, 2.0, 0.17, 5.0, 0.3, 0.05, 0.5, 1.0, 0.01, 0.05, 5.0, 2.0, 2.0, 0.05, 0.01, 0.5, 0.1, 0.5, 5.0, 1.0,
            1.5, 5.0]


def _scaled(raw: int, limit: float) -> np.float32:
    """fuzz_ins.c ReadScaled: ((float) raw / 32767.5f - 1.0f) * limit in float32."""
    return (f32(raw) / f32(32767.5) - f32(1.0)) * f32(limit)


def decode(data: bytes):
    """The calls of one fuzzer input, in order."""
    calls = []
    working = [f32(v) for v in DEFAULTS]
    at = 0

    def take(n):
        nonlocal at
        if at + n > len(data):
            raise EOFError
        chunk = data[at:at + n]
        at += n
        return chunk

    try:
        while at < len(data):
            opcode = take(1)[0] & 3
            if opcode == 0:
                calls.append(("initialise", list(working)))
            elif opcode == 1:
                field = take(1)[0] % FIELDS
                working[field] = np.frombuffer(take(4), dtype="<f4")[0]
                calls.append(("settings", list(working)))
            elif opcode == 2:
                values = np.frombuffer(take(44), dtype="<f4")
                calls.append(("update", values[0:3].copy(), values[3:6].copy(), values[6:9].copy(), values[9], values[10]))
            else:
                raws = [struct.unpack("<H", take(2))[0] for _ in range(9)]
                presence = take(1)[0]
                baro = _scaled(struct.unpack("<H", take(2))[0], 1e5)
                dt = _scaled(struct.unpack("<H", take(2))[0], 0.01)
                gyro = np.array([_scaled(r, 10.0) for r in raws[0:3]], dtype=f32)
                accel = np.array([_scaled(r, 160.0) for r in raws[3:6]], dtype=f32)
                mag = np.array([_scaled(r, 1e3) for r in raws[6:9]], dtype=f32)
                dt = f32(0.0105) + dt
                dt = f32(1e-3) if dt < f32(1e-3) else (f32(0.02) if dt > f32(0.02) else dt)
                if not presence & 1:
                    baro = f32(np.nan)
                if not presence & 2:
                    mag = np.full(3, np.nan, dtype=f32)
                calls.append(("update", gyro, accel, mag, baro, dt))
    except EOFError:
        pass
    return calls


def _literal(value: np.float32) -> str:
    value = f32(value)
    if np.isnan(value):
        return "NAN_"
    if np.isinf(value):
        return "(-INF_)" if value < 0 else "INF_"
    text = f"{float(value):.9g}"  # 9 significant digits: the float32 round-trips exactly
    assert f32(float(text)) == value and np.signbit(f32(float(text))) == np.signbit(value)
    return (text if ("." in text or "e" in text or "n" in text) else text + ".0") + "f"


POSITIVE = {3, 7, 11, 12, 13, 14, 15, 19, 21}  # accelAttitudeNoise, baroNoise, zeroRate/zeroVelocityNoise, time constants, gapPeriod, baroGate


def settings_valid(values) -> bool:
    """FusionAltitudeInsSettingsCheck: finite in [0, 1e6]; the POSITIVE fields > 0."""
    return all(np.isfinite(v) and 0 <= v <= 1e6 and (v > 0 or k not in POSITIVE) for k, v in enumerate(values))


def header(calls, name: str, table: str = "insFinding") -> str:
    """The update calls as a C table named <table>Steps, its length the macro
    <TABLE>_STEPS (insFinding: INS_FINDING_STEPS); every initialise / settings call
    must be rejected (or be a re-initialisation with the defaults before the first
    update: no effect)."""
    first_update = next(k for k, call in enumerate(calls) if call[0] == "update")
    defaults = [f32(v) for v in DEFAULTS]
    accepted = [k for k, call in enumerate(calls) if call[0] != "update" and settings_valid(call[1])
                and not (call[0] == "initialise" and k < first_update and call[1] == defaults)]
    if accepted:
        raise ValueError(f"{name}: {len(accepted)} initialise/settings calls are accepted; the table would not replay it")
    rows = [call for call in calls if call[0] == "update"]
    macro = "".join("_" + ch if ch.isupper() else ch.upper() for ch in table) + "_STEPS"
    lines = [f"/* Generated by csrc/fuzz/findings/decode_ins.py from {name}: the {len(rows)} update",
             " * calls of that fuzzer input in order (its initialise / settings calls are all",
             " * rejected or re-initialise with the defaults before any update, so the",
             " * INS runs with the default settings). Columns: gyro x y z",
             " * (rad/s), accel x y z (m/s^2), mag x y z, baro (m), dt (s); NAN_ = no sample. */",
             f"#define {macro} ({len(rows)})",
             f"static const float {table}Steps[{macro}][11] = {{"]
    for _, gyro, accel, mag, baro, dt in rows:
        values = [*gyro, *accel, *mag, baro, dt]
        lines.append("    {" + ", ".join(_literal(v) for v in values) + "},")
    lines.append("};")
    return "\n".join(lines) + "\n"


def run_in_effect(calls):
    """The settings in effect after the last accepted initialisation (its 25 float32
    values) and the update calls that follow it; raises if a settings call after it
    is accepted (the run would change settings mid-way)."""
    starts = [k for k, call in enumerate(calls) if call[0] == "initialise" and settings_valid(call[1])]
    start = starts[-1] if starts else -1
    settings = calls[start][1] if starts else [f32(v) for v in DEFAULTS]
    if not starts and any(call[0] == "settings" and settings_valid(call[1]) for call in calls):
        raise ValueError("settings change without an initialisation: not a single run")
    rest = calls[start + 1:]
    if any(call[0] == "settings" and settings_valid(call[1]) for call in rest):
        raise ValueError("an accepted settings call after the last initialisation")
    return settings, [call for call in rest if call[0] == "update"]


def encode(settings, updates) -> bytes:
    """A fuzz_ins.c input that makes exactly these calls: one settings edit (opcode 1)
    per field that differs from the defaults, an initialisation (opcode 0), then each
    update with its float32 arguments raw (opcode 2)."""
    out = bytearray()
    for field, (value, default) in enumerate(zip(settings, DEFAULTS)):
        if f32(value) != f32(default):
            out += bytes([1, field]) + np.float32(value).astype("<f4").tobytes()
    out.append(0)
    for _, gyro, accel, mag, baro, dt in updates:
        values = np.array([*gyro, *accel, *mag, baro, dt], dtype="<f4")
        out.append(2)
        out += values.tobytes()
    return bytes(out)


if __name__ == "__main__":
    source, target = Path(sys.argv[1]), Path(sys.argv[2])
    table = sys.argv[3] if len(sys.argv) > 3 else "insFinding"
    Path(target).write_text(header(decode(source.read_bytes()), f"csrc/fuzz/findings/{source.name}", table))
