"""Generates rocket_vectors.h: test vectors of the rocket estimator for the C replay.

Every record is one call on one FusionAltitudeRocket (initialise with
settings, update, update with a vertical accel) with its inputs, the expected
status and an FNV-1a hash of the full state after the call, computed by the
pure-Python reference (fusion_altitude.reference.rocket), never by the C
binding; every 128th record (and the last) carries the state words themselves
(format: vector_common.py). csrc/firmware/replay_rocket.c replays them on the
host (gcc, clang) and on an emulated Cortex-M4F (QEMU).

The flights are simulated rockets (fusion_altitude.rocket_sim: static-port
error, transonic bump, pyro spikes, saturation, tumbling) at 25 Hz, with
settings variations, baro dropouts, gaps and rejected inputs mixed in.

    python csrc/tests/vectors/generate_rocket.py           # rewrite rocket_vectors.h
    python csrc/tests/vectors/generate_rocket.py --check   # exit 1 if it is stale
"""

from __future__ import annotations

import random
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import vector_common as vc  # noqa: E402

from fusion_altitude._core._c_tables import ROCKET_SETTINGS, OBSERVER_SETTINGS  # noqa: E402
from fusion_altitude._rocket_glue import RocketStatus  # noqa: E402
from fusion_altitude.reference.rocket import RocketSettings  # noqa: E402
from fusion_altitude.reference import rocket as _rocket  # noqa: E402
from fusion_altitude.rocket_sim import RocketFlightModel, simulate_rocket_flight  # noqa: E402

HEADER_PATH = Path(__file__).resolve().with_name("rocket_vectors.h")
NAN = float("nan")
INF = float("inf")

OPS = ("INITIALISE_WITH", "UPDATE", "UPDATE_VERTICAL")
#: The settings words (csrc/tests/vectors/rocket_settings_words.h): FusionAltitudeRocketSettings in struct order, the
#: observer's settings (a nested FusionAltitudeSettings) flattened in theirs.
SETTINGS_FIELDS = tuple(name for python, _, kind, *_ in ROCKET_SETTINGS
                        for name in ([f"{python}.{sub}" for sub, *_ in OBSERVER_SETTINGS] if kind == "s" else [python]))
EVENT_FIELDS = ("occurred", "sample", "time", "height", "velocity")
EVENTS = ("launch", "burnout", "maxSpeed", "apogee", "main", "landed", "candidate")
#: The state words, in the order replay_rocket.c reads and writes them.
STATE_FIELDS = (tuple(f"settings.{name}" for name in SETTINGS_FIELDS)
                + ("observer.altitude", "observer.verticalVelocity", "observer.accelBias", "observer.baroResidual",
                   "observer.referenceSet", "observer.positionGain", "observer.velocityGain", "observer.biasGain",
                   "phase", "baro")
                + tuple(f"{event}.{field}" for event in EVENTS for field in EVENT_FIELDS)
                + ("sample", "gapCount", "windows", "windowSamples", "windowBaroSamples",
                   "time", "timeCompensation", "accelBias", "padAltitude", "windowTime", "windowAccelFirst",
                   "windowAccelSum", "windowBaroFirst", "windowBaroSum", "runTime", "spikeTime", "lastBaro",
                   "lastBaroAge", "baroOffset", "offsetApplied", "padBaroPrevious", "padBaroAge", "baroPeak",
                   "contradictionTime", "baroPeakAge",
                   "windowStationary", "padAltitudeSet", "lastBaroSet", "baroAdmitted", "lockout", "accelTrusted",
                   "padBaroPreviousSet", "baroLed"))
FLOAT_FIELDS = tuple(name for name in STATE_FIELDS
                     if not name.endswith(("occurred", "sample", "referenceSet", "Count", "windows", "Samples"))
                     and name != "settings.observer.baro_timeout"  # +infinity (never) by default: a setting, not a result
                     and name not in ("phase", "baro", "windowStationary", "padAltitudeSet", "lastBaroSet",
                                      "baroAdmitted", "lockout", "accelTrusted", "padBaroPreviousSet", "baroLed"))
#: What tools/make_replays.py cannot read from the header and STATE_FIELDS to write csrc/firmware/replay_rocket.c
#: (the keys: its SPECIAL_KEYS).
REPLAY = {
    "functions": {"INITIALISE_WITH": "FusionAltitudeRocketInitialise",
                  "UPDATE_VERTICAL": "FusionAltitudeRocketUpdateWithVerticalAccel"},
    "paths": {**{f"{event}.": f"events[FusionAltitudeRocketEvent{event[0].upper()}{event[1:]}]."
                 for event in EVENTS[:-1]},  # the candidate is a field of its own
              **{f"observer.{gain}": f"observer.settings.{gain}"
                 for gain in ("positionGain", "velocityGain", "biasGain")}},
    "getters": {"lockout": "FusionAltitudeRocketIsLockedOut(filter)"},
    "fields": ("accelBias",),  # FusionAltitudeRocketGetAccelBias is the observer's bias, not the pad's
    "restore": ["FusionAltitudeInitialise(&filter->observer);"],
    "checks": ["ReplayBits(FusionAltitudeRocketGetHeight(filter)) == "
               "ReplayBits(filter->observer.altitude + filter->offsetApplied)",
               "FusionAltitudeRocketIsCalibrated(filter) == (filter->windows > 0u)"],
}


def settings_words(settings: RocketSettings) -> tuple:
    """FusionAltitudeRocketSettings as its words (SETTINGS_FIELDS: floats as bits)."""
    values = settings.as_dict()
    return tuple(vc.bits(value) for python, _, kind, *_ in ROCKET_SETTINGS
                 for value in (values[python] if kind == "s" else (values[python],)))


class Recorder(vc.Recorder):
    OPS = OPS
    INPUTS = 3

    def __init__(self) -> None:
        super().__init__()
        self.rocket = _rocket.RocketEstimator()

    def state(self) -> tuple:
        r = self.rocket
        o = r._obs
        words = settings_words(r._settings)
        words += (vc.bits(o._h), vc.bits(o._v), vc.bits(o._b), vc.bits(o._r), int(o._reference_set))
        words += tuple(vc.bits(g) for g in o._settings._gains[:3])
        words += (int(r._phase), int(r._baro))
        for event in list(r._events) + [r._candidate]:
            words += (int(event[0]), int(event[1]), vc.bits(event[2]), vc.bits(event[3]), vc.bits(event[4]))
        words += (r._sample, r._gap_count, r._windows, r._window_samples, r._window_baro_samples)
        words += tuple(vc.bits(x) for x in (r._time, r._time_c, r._accel_bias, r._pad_altitude, r._window_time,
                                             r._window_accel_first, r._window_accel_sum, r._window_baro_first,
                                             r._window_baro_sum, r._run_time, r._spike_time, r._last_baro,
                                             r._last_baro_age, r._baro_offset, r._offset_applied,
                                             r._pad_baro_previous, r._pad_baro_age, r._baro_peak,
                                             r._contradiction_time, r._baro_peak_age))
        words += tuple(int(x) for x in (r._window_stationary, r._pad_altitude_set, r._last_baro_set,
                                         r._baro_admitted, r._lockout, r._accel_trusted, r._pad_baro_previous_set,
                                         r._baro_led))
        return words

    def initialise_with(self, settings: RocketSettings) -> None:
        self.rocket = _rocket.RocketEstimator(settings)
        self.record("INITIALISE_WITH", (self.settings_index(settings_words(settings)),), RocketStatus.OK)

    def update(self, accel: float, baro: float, dt: float, vertical: bool = False) -> None:
        a, z, t = (vc.as_f32(v) for v in (accel, baro, dt))
        phase = self.rocket._phase
        status = self.rocket._step(a, z, t, vertical)
        self.record("UPDATE_VERTICAL" if vertical else "UPDATE", (vc.bits(a), vc.bits(z), vc.bits(t)), status)
        if status == RocketStatus.OK:
            self.count(f"phase {int(self.rocket._phase)} baro {int(self.rocket._baro)}")
            if self.rocket._phase != phase:
                self.count(f"phase {int(phase)} -> {int(self.rocket._phase)}")


def _descent_baro(recorder: Recorder) -> float:
    """A baro altitude 0.2 m under the height the estimate has reached (pad at 1400 m), m."""
    return float(np.float32(np.float32(1400.0) + np.float32(recorder.rocket.height)) - np.float32(0.2))


#: The traced-path program csrc/firmware/cycles_rocket.c (tools/make_cycles.py writes it): set-up calls, set-up
#: runs (REPEAT; RAMP inputs follow the loop index i; WHILE/BEFORE counts come from the reference), a copy of the
#: estimator in slot 1 for the locked-out coast, and the traced calls (path name, (OP, arguments)) of
#: SizedFusionAltitudeRocketUpdate, on an estimator initialised with the default settings.
CYCLES = (
    ("REPEAT", ("BEFORE", "windows", 0), ("UPDATE", 0.1, 1400.0, 0.01)),  # one sample short of the first window
    ("pad, baro sample, a calibration window completes", ("UPDATE", 0.1, 1400.0, 0.01)),
    ("REPEAT", 160, ("UPDATE", 60.1, ("RAMP", 1400.0, 0.3), 0.01)),  # boost 1.6 s at 60 m/s^2 (96 m/s)
    ("REPEAT", 20, ("UPDATE", -9.7, ("RAMP", 1480.0, 0.9), 0.01)),  # coast
    ("COPY", 1),
    ("coast below the lockout speed, baro fused", ("UPDATE", -9.7, 1498.0, 0.01)),
    ("USE", 1),
    ("REPEAT", 100, ("UPDATE", 30.1, NAN, 0.01)),  # push the copy above the lockout speed
    ("SET", "phase", int(_rocket.Phase.COAST)),
    ("coast above the lockout speed, baro locked out", ("UPDATE", -9.7, 1500.0, 0.01)),
    ("USE", 0),
    ("REPEAT", ("WHILE", "phase", int(_rocket.Phase.COAST)),
     ("UPDATE", -9.7, ("RAMP", 1498.0, 80.0, -4.9, 0.01), 0.01)),  # to apogee: 80 m/s up at 1498 m
    ("descent, baro fused, accel ignored", ("UPDATE", 3.0, _descent_baro, 0.01)),
    ("rejected (accel infinite)", ("UPDATE", INF, 1400.0, 0.01)),
)
#: STATE_FIELDS names that CYCLES sets (SET) → the reference's attribute path in the Recorder
CYCLES_FIELDS = {"phase": "rocket._phase"}


def fly(recorder: Recorder, seed: int, settings: RocketSettings, rng: random.Random, vertical: bool = False,
        stride: int = 4, faults: bool = True) -> None:
    """A short flight (≈ 150 m/s, ≈ 1 km) at 100 Hz / stride."""
    flight = simulate_rocket_flight(seed, RocketFlightModel(burn_time=2.5, main_altitude=300.0))
    recorder.initialise_with(settings)
    dt = flight.dt * stride
    for k in range(0, len(flight.time), stride):
        accel, baro = float(flight.accel[k]), float(flight.baro_altitude[k])
        if faults:
            choice = rng.random()
            if choice < 0.003:
                recorder.update(rng.choice((INF, -INF)), baro, dt, vertical)  # rejected accel (NaN: no sample)
            elif choice < 0.006:
                recorder.update(accel, rng.choice((INF, -INF)), dt, vertical)  # rejected baro
            elif choice < 0.009:
                recorder.update(accel, baro, rng.choice((0.0, -dt, NAN, INF)), vertical)  # rejected dt
            elif choice < 0.011:
                recorder.update(accel, NAN, rng.choice((0.7, 1.3, 40.0)), vertical)  # a gap
                continue
            if rng.random() < 0.1:
                baro = NAN
        recorder.update(accel, baro, dt, vertical)


def fly_logged(recorder: Recorder, seed: int, settings: RocketSettings, accel: str = "live",
               telemetry: bool = False) -> None:
    """A short flight with the accelerometer ``"live"``, ``"none"`` (NaN: a baro-only log or a dead IMU) or
    ``"lost"`` (NaN from 1.5 s after launch: an accelerometer that ends or saturates), at 25 Hz or, with
    ``telemetry``, at 10 Hz with gaps of 0.6-4 s (fusion_altitude.rocket_sim.telemetry_indices)."""
    from fusion_altitude.rocket_sim import telemetry_indices

    flight = simulate_rocket_flight(seed, RocketFlightModel(burn_time=2.5, main_altitude=300.0))
    recorder.initialise_with(settings)
    indices = telemetry_indices(flight, seed, gap_probability=0.1) if telemetry else np.arange(0, len(flight.time), 4)
    values = flight.accel.copy()
    if accel == "none":
        values[:] = NAN
    elif accel == "lost":
        values[flight.time > flight.launch_time + 1.5] = NAN
    previous = indices[0]
    for k in indices:
        dt = float(flight.time[k] - flight.time[previous]) if k != previous else flight.dt * 4
        recorder.update(float(values[k]), float(flight.baro_altitude[k]), dt)
        previous = k


def build() -> Recorder:
    r = Recorder()
    rng = random.Random(20261123)
    r.section("seed 0, defaults, 25 Hz, faults: a whole flight pad to landed")
    fly(r, 0, RocketSettings(), rng)
    r.section("seed 1, vertical accel (INS hook), main at 400 m, lockout 80 m/s")
    fly(r, 1, RocketSettings(main_altitude=400.0, lockout_speed=80.0), rng, vertical=True)
    r.section("seed 2, bias gain 0.2, short gap period, lockout above Mach (capped)")
    fly(r, 2, RocketSettings(observer=(1.6, 1.28, 0.2), gap_period=0.1, lockout_speed=1000.0, spike_time=0.0), rng)
    r.section("seed 3, no accelerometer (NaN): launch from the baro, a baro-led flight")
    fly_logged(r, 3, RocketSettings(), accel="none")
    r.section("seed 4, the accelerometer lost 1.5 s after launch (ends or saturates): baro-led from there")
    fly_logged(r, 4, RocketSettings(), accel="lost")
    r.section("seed 5, telemetry: 10 Hz with gaps of 0.6-4 s, accel live")
    fly_logged(r, 5, RocketSettings(), telemetry=True)
    r.section("seed 6, telemetry without an accelerometer, baro launch at 20 m")
    fly_logged(r, 6, RocketSettings(baro_launch_height=20.0), accel="none", telemetry=True)
    return r


def render() -> str:
    """The text of rocket_vectors.h."""
    with np.errstate(over="ignore", invalid="ignore"):
        recorder = build()
    vc.check_finite(recorder.records, STATE_FIELDS, FLOAT_FIELDS, nan_allowed=("observer.baroResidual",))
    description = [
        "Each record is one call; floats are IEEE 754 binary32 bit patterns.",
        "input: update and update_vertical (accel m/s^2, baro altitude m or",
        "NaN, dt s); initialise_with (index into fusionAltitudeRocketVectorSettings).",
    ]
    return vc.render(recorder, file="rocket_vectors.h", header="fusion_altitude_rocket.h",
                     generator="generate_rocket.py", reference="fusion_altitude.reference.rocket",
                     type_prefix="FusionAltitudeRocket", macro_prefix="FUSION_ALTITUDE_ROCKET",
                     description=description, state_fields=STATE_FIELDS, settings_words=len(SETTINGS_FIELDS),
                     checkpoint_every=128)


if __name__ == "__main__":
    sys.exit(vc.main(HEADER_PATH, render, sys.argv[1:], __doc__))
