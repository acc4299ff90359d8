"""Generates ins_vectors.h: test vectors of the INS (fusion_altitude_ins.h) for the C replay.

Every record is one call on one FusionAltitudeIns (initialise with settings,
set settings, update) with its inputs, the expected status and an FNV-1a hash
of the full state after the call, computed by the pure-Python reference
(fusion_altitude.reference.ins), never by the C binding; every 64th record
(and the last) carries the state words themselves (format: vector_common.py).
csrc/firmware/replay_ins.c replays them on the host (gcc, clang) and on an
emulated Cortex-M4F (QEMU).

Covered: updates before alignment (ignored), alignment (upright, tilted and
upside down), simulated raw-IMU flights (fusion_altitude.imu_sim: a stationary
start with baro-bias, accel-z-bias, zero-rate and zero-velocity learning, then
the `realistic` motion with rocking) with the simulator's baro and a
magnetometer on every 10th step, acceleration rejection by norm and by direction and the recovery
that lifts the direction gate, the local yaw variance cap, gaps (dt above the
gap period), the magnetometer's degenerate branches (field along up; the yaw
filter cancelling to zero), every rejected input (gyro, accel, mag, baro, dt:
NaN, ±inf, above 1e6, and their precedence), NaN payloads as "no sample",
settings changes mid-flight, every rejected setting through SetSettings and
InitialiseWith, and random steps with jittered dt.

    python csrc/tests/vectors/generate_ins.py           # rewrite ins_vectors.h
    python csrc/tests/vectors/generate_ins.py --check   # exit 1 if it is stale
"""

from __future__ import annotations

import random
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import vector_common as vc  # noqa: E402

from fusion_altitude._ins_glue import INS_SETTINGS, INS_SETTINGS_NAMES, InsStatus, check_step  # noqa: E402
from fusion_altitude.imu_sim import simulate_raw_imu  # noqa: E402
from fusion_altitude.reference import ins as _ins  # noqa: E402

HEADER_PATH = Path(__file__).resolve().with_name("ins_vectors.h")
NAN = float("nan")
INF = float("inf")
#: Specific force of a level body at rest, m/s² (z up).
LEVEL = (0.0, 0.0, 9.80665)
f32 = np.float32

OPS = ("INITIALISE_WITH", "SET_SETTINGS", "UPDATE")
#: update inputs: gyro x y z (rad/s), accel x y z (m/s^2), mag x y z, baro altitude (m), dt (s)
INPUT_FIELDS = ("gyro.x", "gyro.y", "gyro.z", "accel.x", "accel.y", "accel.z", "mag.x", "mag.y", "mag.z", "baro", "dt")
C_SETTINGS = tuple(row[1] for row in INS_SETTINGS)
N = _ins.N_STATES
#: The state words, in the order replay_ins.c reads and writes them: the settings, the nominal state, the upper
#: triangle of P (row by row), the other fields of FusionAltitudeIns, then the two computed getters.
STATE_FIELDS = (tuple(f"settings.{name}" for name in C_SETTINGS)
                + ("q.w", "q.x", "q.y", "q.z", "gyroBias.x", "gyroBias.y", "gyroBias.z", "distance", "velocity")
                + tuple(f"P[{i}][{j}]" for i in range(N) for j in range(i, N))
                + ("accelZBias", "baroBias", "yawCos", "yawSin", "stationaryTime", "rejectionTime", "baroElapsed",
                   "magElapsed", "stationaryHalfTime", "stationaryBaroSum", "stationaryBaroCount",
                   "stationaryBaroPrevious", "baroRejectingFor", "gapCount", "baroRejections", "baroResets",
                   "baroTimeouts", "aligned",
                   "baroInitialised", "magInitialised", "stationary", "stationaryHalfDone", "stationaryHasPrevious",
                   "stationaryBaroStill", "accelRejected", "baroRejecting")
                + ("localToGlobal.w", "localToGlobal.x", "localToGlobal.y", "localToGlobal.z",
                   "globalQuaternion.w", "globalQuaternion.x", "globalQuaternion.y", "globalQuaternion.z"))
INTEGER_FIELDS = ("gapCount", "baroRejections", "baroResets", "baroTimeouts", "aligned", "baroInitialised", "magInitialised",
                  "stationary", "stationaryHalfDone", "stationaryHasPrevious", "stationaryBaroStill", "accelRejected",
                  "baroRejecting")
FLOAT_FIELDS = tuple(name for name in STATE_FIELDS if name not in INTEGER_FIELDS)
#: What tools/make_replays.py cannot read from the header and STATE_FIELDS to write csrc/firmware/replay_ins.c
#: (the keys: its SPECIAL_KEYS).
REPLAY = {
    "vector": "FusionAltitudeInsReplay",  # the type prefix given to vc.render (FusionAltitudeInsVector is the 3-vector)
    "paths": {**{f"q.{axis}": f"q[{i}]" for i, axis in enumerate("wxyz")},
              **{f"gyroBias.{axis}": f"gyroBias[{i}]" for i, axis in enumerate("xyz")}},
    "getters": {**{f"q.{axis}": f"FusionAltitudeInsGetQuaternion(filter).{axis}" for axis in "wxyz"},
                **{f"gyroBias.{axis}": f"FusionAltitudeInsGetGyroBias(filter).{axis}" for axis in "xyz"},
                "distance": "FusionAltitudeInsGetAltitude(filter)",
                "velocity": "FusionAltitudeInsGetVerticalVelocity(filter)"},
    "derived": {f"{name}.{axis}": ("float", f"FusionAltitudeInsGet{getter}(filter).{axis}")
                for name, getter in (("localToGlobal", "LocalToGlobal"), ("globalQuaternion", "GlobalQuaternion"))
                for axis in "wxyz"},
}
DEFAULTS = {name: f32(default) for name, _, default, _ in INS_SETTINGS}


def settings_check(values: dict) -> int:
    """FusionAltitudeInsSettingsCheck on float32 values: every field finite in [0, 1e6], the '>0' ones > 0."""
    for name, _, _, rule in INS_SETTINGS:
        value = f32(values[name])
        ok = bool(np.isfinite(value)) and value <= f32(1e6) and (value > 0 if rule == ">0" else value >= 0)
        if not ok:
            return int(InsStatus.INVALID_SETTINGS)
    return int(InsStatus.OK)


def settings_words(values: dict) -> tuple:
    return tuple(vc.bits(values[name]) for name in INS_SETTINGS_NAMES)


#: The traced-path program csrc/firmware/cycles_ins.c (tools/make_cycles.py writes it): a warm-up in motion and a
#: rest of 1.2 s (REPEAT, not traced) before the stationary step, and the traced calls (path name, (OP, gyro rad/s,
#: accel m/s^2, dt s, baro m, mag)) of SizedFusionAltitudeInsUpdate, on an INS initialised with the default
#: settings; the path names are INS_CALLS of csrc/firmware/size_table.py (ins_cycles.py, tests/test_ins_c.py).
CYCLES = (
    ("REPEAT", 20, ("UPDATE", (0.3, -0.2, 0.1), (0.2, -0.1, 9.9), 0.002, 100.0, (0.4, 0.0, -0.3))),
    ("predict + accel (no baro, no mag)", ("UPDATE", (0.3, -0.2, 0.1), (0.2, -0.1, 9.9), 0.002)),
    ("predict + accel + baro", ("UPDATE", (0.3, -0.2, 0.1), (0.2, -0.1, 9.9), 0.002, 100.1)),
    ("predict + accel + mag", ("UPDATE", (0.3, -0.2, 0.1), (0.2, -0.1, 9.9), 0.002, NAN, (0.4, 0.0, -0.3))),
    ("REPEAT", 600, ("UPDATE", (0.001, 0.0, 0.0), (0.0, 0.0, 9.8), 0.002, 100.0)),  # come to rest
    ("stationary: + zero rate, zero velocity, baro bias", ("UPDATE", (0.001, 0.0, 0.0), (0.0, 0.0, 9.8), 0.002, 100.0)),
    ("predict only (accel rejected by its norm)", ("UPDATE", (0.3, -0.2, 0.1), (0.2, -0.1, 14.0), 0.002)),
    ("rejected input (gyro NaN)", ("UPDATE", (NAN, 0.0, 0.0), (0.2, -0.1, 9.9), 0.002, 100.0)),
)


class Recorder(vc.Recorder):
    OPS = OPS
    INPUTS = len(INPUT_FIELDS)

    def __init__(self) -> None:
        super().__init__()
        self.ins = _ins.InsEstimator()

    def state(self) -> tuple:
        e = self.ins
        words = tuple(vc.bits(e.settings.f32(name)) for name in INS_SETTINGS_NAMES)
        words += tuple(vc.bits(x) for x in e.q) + tuple(vc.bits(x) for x in e.gyro_bias_)
        words += (vc.bits(e.distance), vc.bits(e.velocity))
        words += tuple(vc.bits(e.P[i, j]) for i in range(N) for j in range(i, N))
        words += tuple(vc.bits(x) for x in (e.accel_z_bias_, e.baro_bias_, e.yaw_cos, e.yaw_sin, e.stationary_time,
                                             e.rejection_time, e.baro_elapsed, e.mag_elapsed,
                                             e.stationary_half_time, e.stationary_baro_sum, e.stationary_baro_count,
                                             e.stationary_baro_previous, e.baro_rejecting_for))
        words += tuple(x & 0xFFFFFFFF for x in (e.gap_count_, e.baro_rejections_, e.baro_resets_, e.baro_timeouts_))
        words += tuple(int(x) for x in (e.aligned, e.baro_initialised, e.mag_initialised, e.stationary,
                                        e.stationary_half_done, e.stationary_has_previous, e.stationary_baro_still,
                                        e.accel_rejected, e.baro_rejecting))
        with np.errstate(all="ignore"):
            words += tuple(vc.bits(x) for x in e.local_to_global) + tuple(vc.bits(x) for x in e.global_quaternion)
        return words

    def initialise_with(self, **changes) -> None:
        values = {**DEFAULTS, **{k: f32(v) for k, v in changes.items()}}
        status = settings_check(values)
        if status == InsStatus.OK:
            self.ins = _ins.InsEstimator(_ins.InsSettings(**{k: float(v) for k, v in values.items()}))
        self.record("INITIALISE_WITH", (self.settings_index(settings_words(values)),), status)

    def set_settings(self, **changes) -> None:
        values = {**{name: self.ins.settings.f32(name) for name in INS_SETTINGS_NAMES},
                  **{k: f32(v) for k, v in changes.items()}}
        status = settings_check(values)
        if status == InsStatus.OK:
            self.ins.settings = _ins.InsSettings(**{k: float(v) for k, v in values.items()})
        self.record("SET_SETTINGS", (self.settings_index(settings_words(values)),), status)

    def update(self, gyro, accel, dt, baro=NAN, mag=None) -> int:
        g = np.array([vc.as_f32(x) for x in gyro], dtype=f32)
        a = np.array([vc.as_f32(x) for x in accel], dtype=f32)
        m = np.full(3, np.nan, dtype=f32) if mag is None else np.array([vc.as_f32(x) for x in mag], dtype=f32)
        b, t = vc.as_f32(baro), vc.as_f32(dt)
        with np.errstate(all="ignore"):
            status = int(check_step(g, a, m, b, t))
            e = self.ins
            before = (e.aligned, e.accel_rejected, e.stationary, e.gap_count_, e.mag_initialised, e.baro_initialised)
            if status == InsStatus.OK:
                e._step(g, a, m, b, t)
        inputs = tuple(vc.bits(x) for x in g) + tuple(vc.bits(x) for x in a) + tuple(vc.bits(x) for x in m)
        self.record("UPDATE", inputs + (vc.bits(b), vc.bits(t)), status)
        if status == InsStatus.OK:
            self.classify(before, g, a, m, b, t)
        return status

    def classify(self, before, g, a, m, b, t) -> None:
        """Counts the paths an accepted update took (the test checks each occurs)."""
        e = self.ins
        was_aligned, _, _, gaps, mag_initialised, _ = before
        if not was_aligned:
            self.count("aligned now" if e.aligned else "waiting for alignment")
            return
        if e.gap_count_ != gaps:
            self.count("gap")
        self.count("accel rejected" if e.accel_rejected else "accel fused")
        if e.stationary:
            self.count("stationary")
        elif e.stationary_time >= e.settings.f32("stationary_window"):
            self.count("still, baro vetoes stationary")
        if not np.isnan(b):
            self.count("baro " + ("bias learning" if e.stationary else "fused"))
        if e._baro_silent_for(e.settings.f32("dead_reckoning_horizon")):
            self.count("height held")
        elif e._baro_silent_for(e.settings.f32("baro_timeout")):
            self.count("baro timed out")
        if not np.isnan(m).all():
            self.count("mag " + ("initialised" if (e.mag_initialised and not mag_initialised) else "filtered"))


def flight(r: Recorder, seed: int, rest: float, duration: float, rng: random.Random, mag_every: int = 10,
           faults: bool = True) -> None:
    """A simulated raw-IMU flight (stationary start, then the `realistic` motion with rocking) at the simulator's
    IMU rate, with its baro (NaN between samples) and the magnetometer on every mag_every-th step."""
    sim = simulate_raw_imu("realistic", seed=seed, rest_duration=rest, rocking_deg=15.0)
    steps = int(round(duration / sim.dt))
    for k in range(steps):
        gyro, accel, mag = sim.gyro[k], sim.accel[k], sim.mag[k]
        baro = float(sim.baro_altitude[k])  # NaN on steps without a sample
        m = mag if k % mag_every == 3 else None
        if faults:
            choice = rng.random()
            if choice < 0.004:
                r.update((NAN, 0.0, 0.0), accel, sim.dt, baro, m)
            elif choice < 0.008:
                r.update(gyro, accel, rng.choice((0.0, -sim.dt, NAN, INF)), baro, m)
        r.update(gyro, accel, sim.dt, baro, m)


def build() -> Recorder:
    """All scenarios, in order, on one filter (state carries over between sections)."""
    r = Recorder()
    rng = random.Random(20261123)
    _alignment(r, rng)
    _rejected_inputs(r, rng)
    _accel_rejection_and_gaps(r)
    _stationary_baro(r)
    _baro_gate(r)
    _baro_timeout(r)
    _magnetometer(r)
    _settings_changes(r, rng)
    _random_steps(r, rng)
    return r


def _alignment(r: Recorder, rng: random.Random) -> None:
    """Alignment (upright, tilted, upside down), then seed 0: 1.5 s at rest and rocking motion with faults."""
    r.section("defaults; before alignment: accel norm far from g (ignored), then an upright alignment")
    r.initialise_with()
    for accel in ((0.0, 0.0, 0.0), (0.0, 0.0, 20.0), (30.0, 0.0, 0.0), (0.0, 0.0, -3.0)):
        r.update((0.1, 0.0, 0.0), accel, 0.01, 100.0, (0.3, 0.0, 0.4))
    r.update((0.0, 0.0, 0.0), LEVEL, 0.01, 100.0, (0.3, 0.0, 0.4))
    for k in range(30):
        r.update((0.0, 0.0, 0.0), LEVEL, 0.01, 100.0 if k % 4 == 0 else NAN, (0.3, 0.0, 0.4) if k % 10 == 0 else None)

    r.section("alignment tilted and upside down (accel along -z)")
    r.initialise_with()
    r.update((0.0, 0.0, 0.0), (3.0, -4.0, 8.3), 0.01)
    r.initialise_with()
    r.update((0.0, 0.0, 0.0), (0.0, 0.0, -9.8), 0.01)
    for k in range(10):
        r.update((0.01, 0.0, 0.0), (0.0, 0.0, -9.8), 0.01, 50.0 if k % 2 == 0 else NAN)

    r.section("seed 0: 1.5 s at rest (stationary learning), then rocking motion; 25 Hz baro, 10 Hz mag, faults")
    r.initialise_with()
    flight(r, 0, rest=1.5, duration=6.0, rng=rng)


def _rejected_inputs(r: Recorder, rng: random.Random) -> None:
    """Inputs the C refuses and their precedence (state unchanged); NaN payloads as no sample."""
    r.section("rejected inputs and their precedence (state unchanged)")
    good = ((0.01, -0.02, 0.03), (0.1, 0.2, 9.7), (0.3, 0.1, -0.4), 101.0, 0.01)
    bad_values = (NAN, INF, -INF, 2e6, -1.5e6)
    for field in range(5):
        for bad in bad_values:
            args = [list(good[0]), list(good[1]), list(good[2]), good[3], good[4]]
            if field < 3:
                args[field][rng.randrange(3)] = bad
            elif field == 3:
                if np.isnan(bad):
                    continue  # NaN baro is "no sample"
                args[3] = bad
            else:
                args[4] = bad
            r.update(*args[:2], args[4], args[3], args[2])
    for dt in (0.0, -0.0, -0.01, -1e-45):
        r.update(good[0], good[1], dt, good[3], good[2])
    r.update((NAN, 0.0, 0.0), (INF, 0.0, 0.0), -1.0, INF, (0.0, NAN, 0.0))  # gyro first
    r.update((0.0, 0.0, 0.0), (INF, 0.0, 0.0), -1.0, INF, (0.0, NAN, 0.0))  # then accel
    r.update((0.0, 0.0, 0.0), LEVEL, -1.0, INF, (0.0, NAN, 0.0))  # then mag (partly NaN)
    r.update((0.0, 0.0, 0.0), LEVEL, -1.0, INF, None)  # then baro
    r.update((1e6, -1e6, 1e6), (0.0, 0.0, 1e6), 0.01)  # at the bound: accepted
    r.section("NaN payloads are 'no sample' for baro and mag")
    for payload in (0x7FC00001, 0xFFC00000, 0x7F800001, 0xFFFFFFFF):
        nan = vc.from_bits(payload)
        r.update(good[0], good[1], 0.01, nan, (nan, nan, nan))
    r.update(good[0], good[1], 0.01, NAN, (vc.from_bits(0x7FC00001), NAN, vc.from_bits(0xFFC00000)))


def _accel_rejection_and_gaps(r: Recorder) -> None:
    """Acceleration rejection by norm and direction, the recovery; time gaps (dt above gapPeriod, s)."""
    r.section("acceleration rejection: by norm, by direction, recovery after recoveryTriggerPeriod 0.2 s")
    r.initialise_with(recovery_trigger_period=0.2, accel_rejection=0.1)
    r.update((0.0, 0.0, 0.0), LEVEL, 0.01)
    for k in range(10):
        r.update((0.0, 0.0, 0.0), (0.0, 0.0, 14.0), 0.01, 100.0 if k % 4 == 0 else NAN)  # norm
    for k in range(40):  # 30 degrees off (direction gate 0.1 rad) for 0.4 s: rejected, then the recovery fuses
        r.update((0.0, 0.0, 0.0), (4.9, 0.0, 8.49), 0.01, 100.0 if k % 4 == 0 else NAN)
    for k in range(20):
        r.update((0.0, 0.0, 0.0), (4.9, 0.0, 8.49), 0.01)

    r.section("gaps (dt above gapPeriod), a gap with baro and mag, a gap while stationary")
    for dt in (0.1000001, 0.5, 40.0):
        r.update((0.0, 0.0, 0.0), LEVEL, dt)
    r.update((0.0, 0.0, 0.0), LEVEL, 0.2, 100.5, (0.3, 0.0, 0.4))
    r.initialise_with(stationary_window=0.05)
    for k in range(12):
        r.update((0.001, 0.0, 0.0), LEVEL, 0.01, 100.0 if k % 2 == 0 else NAN)
    r.update((0.001, 0.0, 0.0), LEVEL, 0.3, 100.0)
    for k in range(8):
        r.update((0.001, 0.0, 0.0), LEVEL, 0.01, 100.0 if k % 2 == 0 else NAN)


def _stationary_baro(r: Recorder) -> None:
    """Stationary detection with the baro veto: still IMU, baro climbing at 2 m/s then holding, then no baro."""
    r.section("stationary and the baro: a constant-velocity climb still to the IMU (the baro vetoes), "
              "then the baro holds, then no baro (IMU only); stationaryBaroRate 0.5 m/s, window 0.2 s")
    r.initialise_with(stationary_window=0.2, stationary_baro_rate=0.5)
    r.update((0.0, 0.0, 0.0), LEVEL, 0.01)
    altitude = 100.0
    for k in range(60):  # 2 m/s climb: half-window means 0.2 m apart, above 0.5 * 0.1 = 0.05 m
        altitude += 2.0 * 0.01
        r.update((0.001, 0.0, 0.0), LEVEL, 0.01, altitude if k % 2 == 0 else NAN)
    for k in range(60):  # holding: stationary after the next half-window test
        r.update((0.001, 0.0, 0.0), LEVEL, 0.01, altitude + (0.01 if k % 4 == 0 else -0.01) if k % 2 == 0 else NAN)
    for k in range(30):  # climbing again while stationary: the veto ends it
        altitude += 2.0 * 0.01
        r.update((0.001, 0.0, 0.0), LEVEL, 0.01, altitude if k % 2 == 0 else NAN)
    for k in range(40):  # no baro: the IMU alone
        r.update((0.001, 0.0, 0.0), LEVEL, 0.01)
    r.update((0.5, 0.0, 0.0), LEVEL, 0.01, altitude)  # moving: restarts detection


def _baro_gate(r: Recorder) -> None:
    """The baro innovation gate: a glitch burst rejected, a lasting step reset after the timeout, a gap."""
    r.section("baro innovation gate 3 sigma, timeout 0.2 s (never stationary): a 0.1 s 80 m burst rejected, "
              "a 30 m step rejected for 0.2 s then the height reset from the baro, a streak ended by a gap")
    r.initialise_with(baro_gate=3.0, baro_rejection_timeout=0.2, stationary_gyro_threshold=0.0)
    r.update((0.0, 0.0, 0.0), LEVEL, 0.01)
    for k in range(40):  # the baro sets its bias, then agrees
        r.update((0.002, 0.0, 0.0), LEVEL, 0.01, 100.0 + (0.05 if k % 4 == 0 else -0.05) if k % 2 == 0 else NAN)
    for k in range(10):  # glitch burst: rejected, the INS coasts
        r.update((0.002, 0.0, 0.0), LEVEL, 0.01, 180.0 if k % 2 == 0 else NAN)
    for k in range(10):  # back: accepted, the streak ends
        r.update((0.002, 0.0, 0.0), LEVEL, 0.01, 100.0 if k % 2 == 0 else NAN)
    for k in range(50):  # a lasting 30 m step: rejected until the streak is older than 0.2 s, then reset and fused
        r.update((0.002, 0.0, 0.0), LEVEL, 0.01, 130.0 if k % 2 == 0 else NAN)
    for k in range(6):  # another streak (back to 100 m) ...
        r.update((0.002, 0.0, 0.0), LEVEL, 0.01, 100.0 if k % 2 == 0 else NAN)
    r.update((0.002, 0.0, 0.0), LEVEL, 0.5, 100.0)  # ... ended by a gap: d decorrelated, the reading sets it
    for k in range(10):
        r.update((0.002, 0.0, 0.0), LEVEL, 0.01, 100.0 if k % 2 == 0 else NAN)


def _baro_timeout(r: Recorder) -> None:
    """The baro stops: not baro-aided after baroTimeout, dead reckoning stopped after the horizon, then back."""
    r.section("baro timeout 0.2 s, dead-reckoning horizon 0.5 s (never stationary): 25 Hz baro, 1 s of silence "
              "with a 0.3 m/s^2 accel error (timed out, then v decays, d held), the baro back")
    r.initialise_with(baro_timeout=0.2, dead_reckoning_horizon=0.5, stationary_gyro_threshold=0.0)
    r.update((0.0, 0.0, 0.0), LEVEL, 0.01)
    for k in range(40):
        r.update((0.002, 0.0, 0.0), LEVEL, 0.01, 100.0 if k % 4 == 0 else NAN)
    for _ in range(100):
        r.update((0.002, 0.0, 0.0), (0.0, 0.0, LEVEL[2] + 0.3), 0.01)
    for k in range(20):
        r.update((0.002, 0.0, 0.0), LEVEL, 0.01, 100.0 if k % 4 == 0 else NAN)


def _magnetometer(r: Recorder) -> None:
    """Magnetometer: a field along up (no horizontal part), the filter cancelling to zero."""
    r.section("magnetometer: field along up (no horizontal part), filter cancelling to zero (k = 0.5)")
    r.initialise_with(mag_time_constant=0.01)
    r.update((0.0, 0.0, 0.0), LEVEL, 0.01)
    r.update((0.0, 0.0, 0.0), LEVEL, 0.01, NAN, (0.0, 0.0, 0.5))  # horizontal 0: ignored
    r.update((0.0, 0.0, 0.0), LEVEL, 0.01, NAN, (0.4, 0.0, 0.3))  # first: yaw offset (1, 0)
    r.update((0.0, 0.0, 0.0), LEVEL, 0.01, NAN, (-0.4, 0.0, 0.3))  # opposite, k = 0.01/0.02: cancels
    for k in range(6):
        r.update((0.0, 0.0, 0.2), LEVEL, 0.01, NAN, (0.4, 0.1 * k, 0.3))


def _settings_changes(r: Recorder, rng: random.Random) -> None:
    """Settings changed mid-flight; every rejected setting through both entry points."""
    r.section("settings changes mid-flight, every rejected setting through both entry points")
    r.initialise_with(gyro_noise=1e-3, accel_noise=0.2, baro_noise=1.0, initial_velocity_sigma=0.0)
    for k in range(20):
        r.update((0.05, -0.02, 0.1), (0.3, -0.2, 9.9), 0.005, 100.0 + 0.01 * k if k % 3 == 0 else NAN)
    r.set_settings(baro_noise=0.05, accel_norm_rejection=0.0, stationary_window=0.0)
    for k in range(10):
        r.update((0.0, 0.0, 0.0), LEVEL, 0.005, 100.0 if k % 3 == 0 else NAN)
    for name, _, _, rule in INS_SETTINGS:
        for bad in (NAN, INF, -1.0, 2e6) + ((0.0, -0.0) if rule == ">0" else ()):
            if rng.random() < 0.5:
                r.set_settings(**{name: bad})
            else:
                r.initialise_with(**{name: bad})
        r.update((0.0, 0.01, 0.0), LEVEL, 0.005, 100.0)
    r.set_settings(gyro_noise=0.0, gyro_bias_random_walk=0.0, accel_noise=0.0, initial_attitude_sigma=0.0,
                   initial_gyro_bias_sigma=0.0, recovery_trigger_period=0.0, stationary_accel_threshold=0.0)
    for k in range(10):
        r.update((0.0, 0.01, 0.0), LEVEL, 0.005, 100.0 if k % 3 == 0 else NAN)


def _random_steps(r: Recorder, rng: random.Random) -> None:
    """Seed 1 (no rest, no mag, no faults), then 800 random steps: jittered dt, random rates and sensors."""
    r.section("seed 1: no rest, defaults, no mag, no faults")
    r.initialise_with()
    flight(r, 1, rest=0.0, duration=3.0, rng=rng, mag_every=10 ** 9, faults=False)

    r.section("random steps: jittered dt, random rates, accel, baro and mag presence")
    r.initialise_with(stationary_window=0.1, recovery_trigger_period=0.5)
    r.update((0.0, 0.0, 0.0), LEVEL, 0.01)
    for k in range(800):
        if rng.random() < 0.1:
            gyro = (rng.gauss(0, 0.003), rng.gauss(0, 0.003), rng.gauss(0, 0.003))
            accel = (rng.gauss(0, 0.05), rng.gauss(0, 0.05), 9.80665 + rng.gauss(0, 0.05))
        else:
            gyro = (rng.gauss(0, 0.5), rng.gauss(0, 0.5), rng.gauss(0, 0.5))
            accel = (rng.gauss(0, 2.0), rng.gauss(0, 2.0), rng.gauss(9.8, 3.0))
        dt = rng.uniform(0.001, 0.02) if rng.random() < 0.98 else rng.uniform(0.1, 1.0)
        baro = rng.gauss(100.0, 2.0) if rng.random() < 0.3 else NAN
        mag = (rng.gauss(0.3, 0.1), rng.gauss(0.0, 0.1), rng.gauss(-0.4, 0.1)) if rng.random() < 0.1 else None
        r.update(gyro, accel, dt, baro, mag)


def render() -> str:
    """The text of ins_vectors.h (types prefixed FusionAltitudeInsReplay: FusionAltitudeInsVector is the 3-vector)."""
    recorder = build()
    vc.check_finite(recorder.records, STATE_FIELDS, FLOAT_FIELDS)
    description = [
        "Each record is one call; floats are IEEE 754 binary32 bit patterns.",
        "input: update (gyro x, y, z rad/s; accel x, y, z m/s^2; mag x, y, z or",
        "all NaN; baro altitude m or NaN; dt s); initialise_with and set_settings",
        "(index into fusionAltitudeInsReplayVectorSettings, the 23 settings in struct order).",
    ]
    return vc.render(recorder, file="ins_vectors.h", header="fusion_altitude_ins.h",
                     generator="generate_ins.py", reference="fusion_altitude.reference.ins",
                     type_prefix="FusionAltitudeInsReplay", macro_prefix="FUSION_ALTITUDE_INS",
                     description=description, state_fields=STATE_FIELDS, settings_words=len(INS_SETTINGS_NAMES),
                     checkpoint_every=64)


if __name__ == "__main__":
    sys.exit(vc.main(HEADER_PATH, render, sys.argv[1:], __doc__))
