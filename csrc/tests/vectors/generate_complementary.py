"""Generates complementary_vectors.h: test vectors of the two-stage complementary filter for the C replay.

Every record is one call on one filter (initialise, set settings, reset,
update) with its inputs, the expected status and an FNV-1a hash of the full
state after the call, computed by the pure-Python reference
(fusion_altitude.reference.complementary), never by the C binding; every
64th record (and the last) carries the state words themselves (format:
vector_common.py). csrc/firmware/replay_complementary.c replays them on the
host (gcc, clang) and on an emulated Cortex-M4F (QEMU).

The state, as 14 words (STATE_FIELDS, the same order in
replay_complementary.c): the 7 settings, altitude, vertical velocity,
low-passed accel, low-passed baro, baro velocity (the quiet NaN on a step
without baro), time since the latest baro sample, reference set.

    python csrc/tests/vectors/generate_complementary.py           # rewrite complementary_vectors.h
    python csrc/tests/vectors/generate_complementary.py --check   # exit 1 if it is stale

The random-looking parts come from random.Random with a fixed seed.
"""

from __future__ import annotations

import math
import random
import sys
from pathlib import Path
from typing import Dict, Optional

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import vector_common as vc  # noqa: E402

from fusion_altitude._complementary_glue import (COMPLEMENTARY_SETTINGS, COMPLEMENTARY_SETTINGS_DEFAULTS,  # noqa: E402
                                                 ComplementaryStatus)
from fusion_altitude.reference import complementary as _complementary  # noqa: E402

HEADER_PATH = Path(__file__).resolve().with_name("complementary_vectors.h")
NAN = float("nan")
INF = float("inf")

OPS = ("INITIALISE", "SET_SETTINGS", "RESET", "UPDATE")
SETTINGS_FIELDS = tuple(f"settings.{name}" for name, _, _ in COMPLEMENTARY_SETTINGS)
STATE_FIELDS = SETTINGS_FIELDS + ("altitude", "verticalVelocity", "accelFiltered", "baroFiltered", "baroVelocity",
                                  "sinceBaro", "referenceSet", "gapTime", "gapCount", "baroTimeouts", "baroTimedOut")
FLOAT_FIELDS = tuple(f for f in STATE_FIELDS[len(SETTINGS_FIELDS):]
                     if f not in ("referenceSet", "gapCount", "baroTimeouts", "baroTimedOut"))


def settings_words(values: Dict[str, object]) -> tuple:
    """FusionAltitudeComplementarySettings as words (floats as bits, the bool 0/1)."""
    return tuple(int(bool(values[name])) if kind == "b" else vc.bits(values[name])
                 for name, _, kind in COMPLEMENTARY_SETTINGS)


def settings(**changes) -> Dict[str, object]:
    """Default settings with some changed, float32-rounded (not checked)."""
    values = dict(COMPLEMENTARY_SETTINGS_DEFAULTS)
    assert not set(changes) - set(values), changes
    values.update(changes)
    return {name: bool(values[name]) if kind == "b" else float(vc.as_f32(values[name]))
            for name, _, kind in COMPLEMENTARY_SETTINGS}


#: The traced-path program csrc/firmware/cycles_complementary.c (tools/make_cycles.py writes it): set-up calls
#: (OP, arguments of the Recorder's method) and traced calls (path name, (OP, arguments)) of
#: SizedFusionAltitudeComplementaryUpdate, one per path, on the filter initialised with the default settings.
CYCLES = (
    ("RESET", 100.0),
    ("baro sample, time-constant blend (default)", ("UPDATE", 0.2, 100.5, 0.01)),
    ("SET_SETTINGS", settings(per_sample_coefficients=True)),
    ("baro sample, per-sample coefficients", ("UPDATE", 0.2, 100.5, 0.01)),
    ("no baro sample (prediction only)", ("UPDATE", 0.2, NAN, 0.01)),
    ("rejected (accel not finite)", ("UPDATE", INF, 100.5, 0.01)),
)


class Recorder(vc.Recorder):
    OPS = OPS
    INPUTS = 3

    def __init__(self) -> None:
        super().__init__()
        self.filter = _complementary.ComplementaryFilter()

    def state(self) -> tuple:
        f = self.filter
        words = settings_words(f.settings.as_dict())
        words += tuple(vc.bits(x) for x in (f._h, f._v, f._a, f._zf, f._vb, f._since))
        return words + (int(f._reference_set), vc.bits(f._gap_time), f._gap_count, f._baro_timeouts,
                        int(f._baro_timed_out))

    # FusionAltitudeComplementaryInitialise
    def initialise(self) -> None:
        self.filter = _complementary.ComplementaryFilter()
        self.record("INITIALISE", (), ComplementaryStatus.OK)

    # FusionAltitudeComplementarySetSettings
    def set_settings(self, values: Dict[str, object]) -> None:
        status = _complementary._check(values)
        if status == ComplementaryStatus.OK:
            self.filter.settings = _complementary.ComplementarySettings(**values)
        self.record("SET_SETTINGS", (self.settings_index(settings_words(values)),), status)

    # FusionAltitudeComplementaryReset
    def reset(self, baro) -> None:
        z = vc.as_f32(baro)
        status = self.filter._reset(z)
        self.record("RESET", (vc.bits(z),), status)

    # FusionAltitudeComplementaryUpdate
    def update(self, accel, baro, dt) -> None:
        a, z, t = (vc.as_f32(v) for v in (accel, baro, dt))
        was_set = self.filter._reference_set
        status = self.filter._update(a, z, t)
        self.record("UPDATE", (vc.bits(a), vc.bits(z), vc.bits(t)), status)
        if status == ComplementaryStatus.OK:
            baro_sample = bool(np.isfinite(z))
            self.count(f"update {'reference set' if was_set else 'before reference'}, "
                       f"{'baro' if baro_sample else 'no baro'}")


class Flight:
    """A simulated vertical flight: true height h, an accelerometer with bias, a noisy baro."""

    def __init__(self, recorder: Recorder, rng: random.Random, dt: float = 0.01, bias: float = 0.05,
                 origin: float = 120.0) -> None:
        self.r, self.rng, self.dt, self.bias, self.origin = recorder, rng, dt, bias, origin
        self.h = self.v = self.t = 0.0
        self.k = 0

    def noise(self, sigma: float) -> float:
        return sigma * (self.rng.random() + self.rng.random() + self.rng.random() - 1.5) * 2.0

    def fly(self, steps: int, profile: str = "hover", baro_every: int = 4, baro_shift: float = 0.0) -> None:
        for _ in range(steps):
            if profile == "hover":
                a_true = 0.0
            elif profile == "climb":
                a_true = 1.5 if (self.t % 8.0) < 2.0 else (-1.5 if (self.t % 8.0) < 4.0 else 0.0)
            else:  # "sine"
                a_true = 2.0 * math.sin(0.9 * self.t)
            self.v += a_true * self.dt
            self.h += self.v * self.dt
            self.t += self.dt
            k = self.k
            self.k += 1
            baro = (self.origin + self.h + baro_shift + self.noise(0.3)
                    if baro_every and k % baro_every == 0 else NAN)
            self.r.update(a_true + self.bias + self.noise(0.05), baro, self.dt)


def build() -> Recorder:
    """All scenarios, in order, on one filter (state carries over between sections)."""
    r = Recorder()
    rng = random.Random(20261124)
    default = settings()
    flight = _start_and_fly(r, rng)
    _rejected_updates(r, flight)
    _resets(r, flight)
    _retunes_and_baro_faults(r, flight, default)
    bad = _rejected_settings(r, flight, default)
    _time_gaps(r, flight, default)
    _baro_timeout(r, flight, default)
    flight = _reinitialise(r, rng)
    _random_steps(r, rng, flight, default, bad)
    return r


def _start_and_fly(r: Recorder, rng: random.Random) -> Flight:
    """Initialise, steps before the reference, then 100 Hz flights with 25 Hz, 100 Hz and 10 Hz baro."""
    r.section("initialise; steps before the reference (no baro: only the baro velocity changes), "
              "then the first baro sample sets it")
    r.initialise()
    for _ in range(3):
        r.update(0.2, NAN, 0.01)
    r.update(0.2, 120.0, 0.01)
    r.section("100 Hz, 25 Hz baro (NaN gaps), hover then climbs, default time constants")
    flight = Flight(r, rng)
    flight.fly(300, "hover")
    flight.fly(700, "climb")
    r.section("baro every step, then every 10th, sine")
    flight.fly(200, "sine", baro_every=1)
    flight.fly(300, "sine", baro_every=10)
    return flight


def _rejected_updates(r: Recorder, flight: Flight) -> None:
    """Updates the C refuses (state unchanged) and the oddities it accepts (NaN payloads, subnormals, -0)."""
    r.section("rejected updates (state unchanged): accel inf/NaN, baro +-inf, dt 0/-0/negative/NaN/inf/negative "
              "subnormal; precedence")
    for accel in (INF, -INF, NAN, vc.from_bits(0x7F800001), vc.from_bits(0xFFC00000)):
        r.update(accel, 120.0, 0.01)
    for baro in (INF, -INF):
        r.update(0.1, baro, 0.01)
    for dt in (0.0, -0.0, -0.01, NAN, INF, -INF, vc.from_bits(0x80000001)):
        r.update(0.1, 120.0, dt)
        r.update(0.1, NAN, dt)
    r.update(INF, INF, NAN)   # accel first
    r.update(0.1, INF, 0.0)   # baro before dt
    r.section("accepted oddities: NaN payloads as 'no sample', subnormal dt and accel, -0 baro")
    for pattern in (0x7FC00000, 0xFFC00000, 0x7F800001, 0x7FFFFFFF, 0xFFFFFFFF, 0x7FC12345):
        r.update(0.1, vc.from_bits(pattern), 0.01)
    r.update(vc.from_bits(0x00000001), 120.0, vc.from_bits(0x00000001))
    r.update(vc.from_bits(0x807FFFFF), NAN, 0.01)
    r.update(0.0, -0.0, 0.01)
    flight.fly(100, "hover")


def _resets(r: Recorder, flight: Flight) -> None:
    """Accepted and rejected resets (altitude, m), with updates in between."""
    r.section("resets: accepted (any finite altitude, -0) and rejected (inf, NaN); updates in between")
    for baro in (130.0, -0.0, INF, -INF, NAN, vc.from_bits(0xFFC00000), -25.5, 1e5):
        r.reset(baro)
        flight.origin = float(vc.as_f32(baro)) if math.isfinite(baro) else flight.origin
        flight.h = flight.v = 0.0
        flight.fly(20, "hover")
    flight.origin = 120.0
    r.reset(120.0)


def _retunes_and_baro_faults(r: Recorder, flight: Flight, default: dict) -> None:
    """Settings changed mid-flight (coefficients, time constants, 50 Hz); a baro spike, step and 2 s dropout."""
    r.section("settings: per-sample coefficients (the write-up's 0.999/0.998, then 0 and 1), no low-pass "
              "(time constants 0), long and zero blend time constants, at 100 and 50 Hz")
    r.set_settings(settings(per_sample_coefficients=True))
    flight.fly(200, "climb")
    r.set_settings(settings(per_sample_coefficients=True, velocity_coefficient=0.0, altitude_coefficient=1.0))
    flight.fly(60, "climb")
    r.set_settings(settings(per_sample_coefficients=True, velocity_coefficient=1.0, altitude_coefficient=0.0))
    flight.fly(60, "climb")
    r.set_settings(settings(accel_time_constant=0.0, baro_time_constant=0.0))
    flight.fly(100, "sine", baro_every=1)
    r.set_settings(settings(velocity_time_constant=0.0, altitude_time_constant=0.0))
    flight.fly(60, "sine")
    r.set_settings(settings(velocity_time_constant=1e4, altitude_time_constant=100.0, baro_time_constant=1.0))
    flight.fly(100, "sine")
    r.set_settings(default)
    flight.dt = 0.02
    flight.fly(200, "climb", baro_every=2)
    flight.dt = 0.01
    r.section("baro spike and step, then a dropout of 2 s (sinceBaro grows, D = 2 s at the next sample)")
    flight.fly(12, "hover", baro_shift=30.0, baro_every=4)
    flight.fly(100, "hover")
    flight.fly(200, "hover", baro_every=0)
    flight.fly(100, "hover", baro_shift=5.0)


def _rejected_settings(r: Recorder, flight: Flight, default: dict) -> list:
    """Every invalid setting (state unchanged) and the edge values accepted; returns the bad settings."""
    r.section("rejected settings (state unchanged): every time constant and coefficient, NaN/inf/negative/> 1; "
              "edge values accepted")
    bad = [settings(accel_time_constant=-0.1), settings(baro_time_constant=NAN), settings(velocity_time_constant=INF),
           settings(altitude_time_constant=-1e-9), settings(velocity_coefficient=1.0000001),
           settings(altitude_coefficient=-0.1), settings(velocity_coefficient=NAN), settings(altitude_coefficient=INF),
           settings(per_sample_coefficients=True, velocity_coefficient=2.0),
           settings(accel_time_constant=NAN, velocity_coefficient=NAN), settings(gap_period=0.0)]
    for values in bad:
        r.set_settings(values)
    r.set_settings(settings(accel_time_constant=-0.0, baro_time_constant=0.0, velocity_coefficient=0.0,
                            altitude_coefficient=1.0))
    flight.fly(40, "hover")
    r.set_settings(default)
    return bad


def _time_gaps(r: Recorder, flight: Flight, default: dict) -> None:
    """dt at and above the gap period (s) with and without baro, a reset while pending, the gap period's limits."""
    r.section("time gaps: dt at the gap period (integrated), above it without baro (frozen; the next baro sample "
              "restarts with the mean velocity), with baro (restarts on it), a reset while one is pending; "
              "gap period rejected (0, negative, NaN), +infinity accepted")
    flight.fly(100, "climb")
    r.update(0.2, NAN, 0.5)
    r.update(9.0, NAN, 2.0)
    r.update(0.2, NAN, 0.01)
    r.update(0.2, flight.origin + flight.h + 6.0, 0.01)
    flight.fly(100, "sine")
    r.update(-4.0, flight.origin + flight.h - 3.0, 1.5)
    flight.fly(50, "sine")
    r.update(0.0, NAN, 3.0)
    r.reset(flight.origin + flight.h)
    flight.fly(50, "hover")
    for values in (settings(gap_period=0.0), settings(gap_period=-1.0), settings(gap_period=NAN)):
        r.set_settings(values)
    r.set_settings(settings(gap_period=INF))
    r.update(0.0, NAN, 50.0)
    r.update(0.0, flight.origin + flight.h, 5.0)
    r.set_settings(default)
    flight.fly(50, "hover")


def _baro_timeout(r: Recorder, flight: Flight, default: dict) -> None:
    """The baro timeout (s): rejected and accepted values; an outage past it (decay, no dead reckoning), the restart."""
    r.section("baro timeout: rejected (0, negative, NaN), +infinity (dead reckoning through a 3 s outage), then 2 s: "
              "a 3 s outage times out (v decays), the next baro sample restarts h at it; a timeout while a gap is "
              "pending")
    for values in (settings(baro_timeout=0.0), settings(baro_timeout=-1.0), settings(baro_timeout=NAN)):
        r.set_settings(values)
    r.set_settings(settings(baro_timeout=INF))
    flight.fly(50)
    for _ in range(60):
        r.update(0.4, NAN, 0.05)
    r.set_settings(default)
    flight.fly(60)
    for k in range(60):
        r.update(0.5 + 0.05 * k, NAN, 0.05)
    r.update(0.2, flight.origin + flight.h, 0.01)
    flight.fly(100)
    r.update(0.1, NAN, 1.5)
    r.update(0.1, NAN, 1.0)
    r.update(0.1, flight.origin + flight.h, 0.01)
    flight.fly(20)


def _reinitialise(r: Recorder, rng: random.Random) -> Flight:
    """Re-initialise: steps before the reference, the first sample after a gap; returns the new flight."""
    r.section("re-initialise: steps before the reference, first sample after a gap")
    r.initialise()
    r.update(0.5, NAN, 0.01)
    r.update(0.5, NAN, 0.02)
    flight = Flight(r, rng, origin=-40.0)
    flight.fly(100, "climb")
    return flight


def _random_steps(r: Recorder, rng: random.Random, flight: Flight, default: dict, bad: list) -> None:
    """1100 random-ish steps: jittered dt, random baro, spikes, rejected inputs, resets, retunes, re-initialisations."""
    r.section("random-ish steps: jittered dt, random baro presence, spikes, rejected inputs, resets, retunes "
              "and re-initialisations")
    tunings = [default, settings(per_sample_coefficients=True), settings(accel_time_constant=0.0),
               settings(baro_time_constant=0.2, velocity_time_constant=3.0, altitude_time_constant=1.0),
               settings(per_sample_coefficients=True, velocity_coefficient=0.95, altitude_coefficient=0.9)]
    bad_floats = (INF, -INF, NAN, vc.from_bits(0xFFC00000))
    for _ in range(1100):
        choice = rng.random()
        dt = 0.01 * (0.5 + rng.random())
        if choice > 0.996:
            dt = rng.uniform(0.3, 3.0)  # sometimes a time gap
        flight.dt = dt
        if choice < 0.01:
            r.update(rng.choice(bad_floats), 120.0, dt)
        elif choice < 0.02:
            r.update(0.0, 120.0, rng.choice((0.0, -dt, NAN, INF)))
        elif choice < 0.025:
            r.update(0.0, rng.choice((INF, -INF)), dt)
        elif choice < 0.03:
            r.set_settings(rng.choice(tunings))
        elif choice < 0.033:
            r.set_settings(rng.choice(bad))
        elif choice < 0.036:
            r.reset(rng.choice((flight.origin + flight.h, INF, NAN)))
        elif choice < 0.038:
            r.initialise()
            flight = Flight(r, rng, dt=dt)
        elif choice < 0.05:
            r.update(flight.noise(0.1), flight.origin + flight.h + rng.uniform(-20.0, 20.0), dt)
        else:
            flight.fly(1, rng.choice(("hover", "climb", "sine")), baro_every=rng.choice((1, 0, 0, 2)))


def render() -> str:
    """The text of complementary_vectors.h."""
    with np.errstate(over="ignore", invalid="ignore"):
        recorder = build()
    vc.check_finite(recorder.records, STATE_FIELDS, FLOAT_FIELDS, nan_allowed=("baroVelocity",))
    description = [
        "Each record is one call; floats are IEEE 754 binary32 bit patterns.",
        "input: update (accel m/s^2, baro altitude m or NaN, dt s); reset (baro",
        "altitude m); set settings (index into",
        "fusionAltitudeComplementaryVectorSettings); initialise (none).",
    ]
    return vc.render(recorder, file="complementary_vectors.h", header="fusion_altitude_complementary.h",
                     generator="generate_complementary.py", reference="fusion_altitude.reference.complementary",
                     type_prefix="FusionAltitudeComplementary", macro_prefix="FUSION_ALTITUDE_COMPLEMENTARY",
                     description=description, state_fields=STATE_FIELDS, settings_words=len(SETTINGS_FIELDS))


if __name__ == "__main__":
    sys.exit(vc.main(HEADER_PATH, render, sys.argv[1:], __doc__))
