"""Generates kalman_vectors.h: shared test vectors of the Kalman filter for the C replay.

Every record is one call on one filter (initialise, initialise with settings,
set settings, update, update without measurements) with its inputs, the
expected status and a 32-bit hash of the full state after the call, computed
by the pure-Python reference (fusion_altitude.reference.kalman), never by the
C binding. Every CHECKPOINT_EVERY-th record (and the last) also carries the
full state, word for word. csrc/firmware/replay_kalman.c replays them on the
host (gcc, clang) and on an emulated Cortex-M4F (QEMU), which must reproduce
every bit.

The state, as binary32/integer words (STATE_FIELDS, the same order in
replay_kalman.c): the settings (KALMAN_SETTINGS: the header's struct, in its
order; replay_kalman.c decodes them with the generated
kalman_settings_words.h), x (5), the upper triangle of P (15), the
altitude h + ob and its variance (the getters), per sensor (baro, range, GPS)
innovation, innovation variance, NIS, rejecting-for, rejections, resets,
result, rejecting (8 each), the baro/GPS initialised flags, the gap count and
the time since any sample was fused. The hash is
word-wise FNV-1a: h = 2166136261; for each word, h = (h ^ word) * 16777619
(mod 2^32). One changed word always changes it (the multiplier is odd).

    python csrc/tests/vectors/generate_kalman.py           # rewrite kalman_vectors.h
    python csrc/tests/vectors/generate_kalman.py --check   # exit 1 if it is stale

The random-looking parts come from random.Random with a fixed seed.
"""

from __future__ import annotations

import math
import random
import sys
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import vector_common as vc  # noqa: E402

from fusion_altitude._kalman_glue import KALMAN_SETTINGS, KALMAN_SETTINGS_DEFAULTS, KalmanStatus
from fusion_altitude.reference import kalman as _kalman

HEADER_PATH = Path(__file__).resolve().with_name("kalman_vectors.h")
f32 = np.float32
NAN = float("nan")
INF = float("inf")
CHECKPOINT_EVERY = 64

# Operation codes, equal to FusionAltitudeKalmanVectorOp in kalman_vectors.h.
OPS = ("INITIALISE", "INITIALISE_WITH", "SET_SETTINGS", "UPDATE", "UPDATE_NO_MEASUREMENTS")
OP = {name: index for index, name in enumerate(OPS)}
NULL_SETTINGS = 0xFFFFFFFF
QUIET_NAN_BITS = 0x7FC00000

SENSOR_FIELDS = ("innovation", "innovationVariance", "nis", "rejectingFor", "sinceSample", "rejections", "resets",
                 "timeouts", "result", "rejecting", "sampled", "timedOut")
STATE_FIELDS = ([f"settings.{name}" for name, *_ in KALMAN_SETTINGS] + [f"x[{i}]" for i in range(5)]
                + [f"P[{i}][{j}]" for i in range(5) for j in range(i, 5)] + ["altitude", "altitudeVariance"]
                + [f"{sensor}.{field}" for sensor in ("baro", "range", "gps") for field in SENSOR_FIELDS]
                + ["baroInitialised", "gpsInitialised", "gapCount", "sinceFused"])
NAN_ALLOWED = {f"{sensor}.{field}" for sensor in ("baro", "range", "gps")
               for field in ("innovation", "innovationVariance", "nis")}
#: What tools/make_replays.py cannot read from the header and STATE_FIELDS to write csrc/firmware/replay_kalman.c
#: (the keys: its SPECIAL_KEYS).
_C_STATES = ("Height", "Velocity", "BaroOffset", "GpsOffset", "AccelBias")
_C_SENSORS = ("Baro", "Range", "Gps")
REPLAY = {
    "functions": {"UPDATE_NO_MEASUREMENTS": "FusionAltitudeKalmanUpdate"},
    "nulls": {"UPDATE_NO_MEASUREMENTS": ("measurements",)},
    "null_settings": {"INITIALISE_WITH": NULL_SETTINGS},
    "paths": {f"{sensor.lower()}.": f"sensors[FusionAltitudeKalmanSensor{sensor}]." for sensor in _C_SENSORS},
    "getters": {**{f"x[{i}]": f"FusionAltitudeKalmanGet{getter}(filter)" for i, getter in
                   enumerate(("HeightAboveGround", "VerticalVelocity", "BaroOffset", "GpsOffset", "AccelBias"))},
                **{f"P[{i}][{j}]": f"FusionAltitudeKalmanGetCovariance(filter, FusionAltitudeKalmanState"
                                   f"{_C_STATES[i]}, FusionAltitudeKalmanState{_C_STATES[j]})"
                   for i in range(5) for j in range(i, 5)}},
    "derived": {"altitude": ("float", "FusionAltitudeKalmanGetAltitude(filter)"),
                "altitudeVariance": ("float", "FusionAltitudeKalmanGetAltitudeVariance(filter)"),
                **{f"{sensor.lower()}.nis": ("float", f"FusionAltitudeKalmanGetNis(filter, "
                                                      f"FusionAltitudeKalmanSensor{sensor})") for sensor in _C_SENSORS}},
}


def bits(value) -> int:
    """The binary32 bit pattern of a float32."""
    return int(np.array(value, dtype=np.float32).view(np.uint32))


def from_bits(pattern: int) -> np.float32:
    """The float32 with bit pattern ``pattern`` (keeps NaN payloads and signed zeros)."""
    return np.array(pattern, dtype=np.uint32).view(np.float32)[()]


def as_f32(value) -> np.float32:
    return value if isinstance(value, np.float32) else f32(value)


def settings_words(values: Dict[str, object]) -> Tuple[int, ...]:
    """The C struct FusionAltitudeKalmanSettings as words (floats as bits, bool 0/1, int32 two's complement)."""
    words = []
    for name, _, kind, _, _ in KALMAN_SETTINGS:
        value = values[name]
        if kind == "f":
            words.append(bits(as_f32(value)))
        elif kind == "b":
            words.append(int(bool(value)))
        else:
            words.append(int(value) & 0xFFFFFFFF)
    return tuple(words)


def state_words(e: _kalman.KalmanEstimator) -> Tuple[int, ...]:
    words = list(settings_words(e._settings.as_dict()))
    words += [bits(v) for v in e._x]
    words += [bits(e._P[i][j]) for i in range(5) for j in range(i, 5)]
    P = e._P
    words += [bits(e._x[0] + e._x[2]), bits(P[0][0] + f32(2) * P[0][2] + P[2][2])]
    for s in e._sensors:
        words += [bits(s.innovation), bits(s.innovation_variance), bits(s.nis), bits(s.rejecting_for),
                  bits(s.since_sample), s.rejections & 0xFFFFFFFF, s.resets & 0xFFFFFFFF, s.timeouts & 0xFFFFFFFF,
                  int(s.result), int(bool(s.rejecting)), int(bool(s.sampled)), int(bool(s.timed_out))]
    words += [int(e._baro_initialised), int(e._gps_initialised), e._gap_count & 0xFFFFFFFF, bits(e._since_fused)]
    assert len(words) == len(STATE_FIELDS)
    return tuple(words)


def fnv1a(words: Sequence[int]) -> int:
    h = 2166136261
    for word in words:
        h = ((h ^ word) * 16777619) & 0xFFFFFFFF
    return h


def settings(**changes) -> Dict[str, object]:
    """Default settings with some changed, as float32-rounded Python values (not checked)."""
    values = dict(KALMAN_SETTINGS_DEFAULTS)
    unknown = set(changes) - set(values)
    assert not unknown, unknown
    values.update(changes)
    with np.errstate(over="ignore"):
        return {name: (float(f32(v)) if kind == "f" else v) for (name, _, kind, _, _), v in
                zip(KALMAN_SETTINGS, values.values())}


#: The traced-path program csrc/firmware/cycles_kalman.c (tools/make_cycles.py writes it): the filter initialised
#: with a terrain reset on the second rejected range sample (rejection timeout 0 s), a warm-up with every sensor
#: (REPEAT, not traced), then the traced calls (path name, (OP, accel m/s^2, dt s, baro m, range m, GPS m, GPS
#: accuracy m, satellites)) of SizedFusionAltitudeKalmanUpdate; the untraced update between the last two starts the
#: rejection streak (the ground dropped by 2 m).
CYCLES = (
    ("INITIALISE_WITH", settings(rejection_timeout=0.0)),
    ("REPEAT", 10, ("UPDATE", 0.0, 0.01, 120.0, 1.0, 160.0, NAN, 9)),
    ("baro, rangefinder and GPS fused", ("UPDATE", 0.0, 0.01, 120.0, 1.0, 160.0, NAN, 9)),
    ("baro only, fused", ("UPDATE", 0.0, 0.01, 120.0)),
    ("no sample (prediction only)", ("UPDATE", 0.0, 0.01)),
    ("UPDATE", 0.0, 0.01, NAN, 3.0),
    ("terrain reset (range) with baro and GPS fused", ("UPDATE", 0.0, 0.01, 120.0, 3.0, 160.0, NAN, 9)),
    ("rejected (accel not finite)", ("UPDATE", INF, 0.01, 120.0, 3.0, 160.0, NAN, 9)),
)


class Recorder:
    """Applies operations to a reference filter, mirroring the C calls, and records them."""

    def __init__(self) -> None:
        self.estimator = _kalman.KalmanEstimator()
        self.records: List[Tuple[int, int, Tuple[int, ...], Tuple[int, ...]]] = []
        self.settings_table: List[Tuple[int, ...]] = []
        self.comments: List[str] = []
        self.counts: Dict[str, int] = {}

    def _record(self, op: str, inputs: Sequence[int], status: KalmanStatus) -> None:
        patterns = tuple(inputs) + (0,) * (8 - len(inputs))
        self.records.append((OP[op], int(status), patterns, state_words(self.estimator)))
        if status == KalmanStatus.OK and op in ("UPDATE", "UPDATE_NO_MEASUREMENTS"):
            for name, sensor in zip(("baro", "range", "gps"), self.estimator._sensors):
                key = f"{name} {sensor.result.name.lower()}"
                self.counts[key] = self.counts.get(key, 0) + 1
        else:
            key = f"{op.lower()} status {int(status)}"
            self.counts[key] = self.counts.get(key, 0) + 1

    def section(self, text: str) -> None:
        """Labels the next record in the generated header."""
        self.comments.append(f"{len(self.records)}: {text}")

    def _settings_index(self, values: Dict[str, object]) -> int:
        words = settings_words(values)
        if words not in self.settings_table:
            self.settings_table.append(words)
        return self.settings_table.index(words)

    # FusionAltitudeKalmanInitialise
    def initialise(self) -> None:
        self.estimator = _kalman.KalmanEstimator()
        self._record("INITIALISE", (), KalmanStatus.OK)

    # FusionAltitudeKalmanInitialiseWith (values None: NULL, the defaults)
    def initialise_with(self, values: Optional[Dict[str, object]]) -> KalmanStatus:
        if values is None:
            self.estimator = _kalman.KalmanEstimator()
            self._record("INITIALISE_WITH", (NULL_SETTINGS,), KalmanStatus.OK)
            return KalmanStatus.OK
        status = _kalman._check(values)
        if status == KalmanStatus.OK:
            self.estimator = _kalman.KalmanEstimator(_kalman.KalmanSettings(**values))
        self._record("INITIALISE_WITH", (self._settings_index(values),), status)
        return status

    # FusionAltitudeKalmanSetSettings
    def set_settings(self, values: Dict[str, object]) -> KalmanStatus:
        status = _kalman._check(values)
        if status == KalmanStatus.OK:
            self.estimator.settings = _kalman.KalmanSettings(**values)
        self._record("SET_SETTINGS", (self._settings_index(values),), status)
        return status

    # FusionAltitudeKalmanUpdate with measurements
    def update(self, accel, dt, baro=NAN, rng=NAN, gps=NAN, accuracy=NAN, satellites: int = -1,
               ground_effect: bool = False) -> KalmanStatus:
        a, t, zb, zr, zg, acc = (as_f32(v) for v in (accel, dt, baro, rng, gps, accuracy))
        status = self.estimator._update(a, t, zb, zr, zg, acc, int(satellites), bool(ground_effect))
        self._record("UPDATE", (bits(a), bits(t), bits(zb), bits(zr), bits(zg), bits(acc),
                                int(satellites) & 0xFFFFFFFF, int(bool(ground_effect))), status)
        return status

    # FusionAltitudeKalmanUpdate with measurements NULL
    def update_no_measurements(self, accel, dt) -> KalmanStatus:
        a, t = as_f32(accel), as_f32(dt)
        status = self.estimator._update(a, t, f32(NAN), f32(NAN), f32(NAN), f32(NAN), -1, False)
        self._record("UPDATE_NO_MEASUREMENTS", (bits(a), bits(t)), status)
        return status


class Flight:
    """A simulated vertical flight over terrain, sampled into Recorder.update calls."""

    def __init__(self, recorder: Recorder, rng: random.Random, dt: float = 0.01, bias: float = 0.1,
                 baro_origin: float = 120.0, gps_origin: float = 160.0) -> None:
        self.r, self.rng, self.dt, self.bias = recorder, rng, dt, bias
        self.h = self.v = self.t = 0.0
        self.terrain = 0.0            # ground height under the vehicle, m (range reads h - terrain)
        self.baro_origin, self.gps_origin = baro_origin, gps_origin
        self.k = 0

    def noise(self, sigma: float) -> float:
        return sigma * (self.rng.random() + self.rng.random() + self.rng.random() - 1.5) * 2.0

    def fly(self, steps: int, profile: str = "hover", baro_every: int = 4, range_every: int = 5,
            gps_every: int = 20, satellites: int = 9, accuracy: float = NAN, baro_shift: float = 0.0,
            gps_shift: float = 0.0, ground_effect: bool = False, baro_drop: float = 0.0) -> None:
        for _ in range(steps):
            if profile == "hover":
                a_true = 0.0
            elif profile == "climb":
                a_true = 1.5 if (self.t % 8.0) < 2.0 else (-1.5 if (self.t % 8.0) < 4.0 else 0.0)
            elif profile == "descend":
                a_true = -1.0 if (self.t % 6.0) < 1.0 else (1.0 if (self.t % 6.0) < 2.0 else 0.0)
            else:  # "sine"
                a_true = 2.0 * math.sin(0.9 * self.t)
            self.v += a_true * self.dt
            self.h += self.v * self.dt
            self.t += self.dt
            accel = a_true + self.bias + self.noise(0.05)
            k = self.k
            self.k += 1
            baro = (self.baro_origin + self.h + baro_shift - baro_drop + self.noise(0.3)
                    if baro_every and k % baro_every == 0 else NAN)
            height = self.h - self.terrain
            rng = height + self.noise(0.02) if range_every and k % range_every == 0 else NAN
            gps = self.gps_origin + self.h + gps_shift + self.noise(1.0) if gps_every and k % gps_every == 0 else NAN
            self.r.update(accel, self.dt, baro, rng, gps, accuracy, satellites, ground_effect)


def build() -> Recorder:
    """All scenarios, in order, on one filter (state carries over between sections)."""
    r = Recorder()
    rng = random.Random(20261123)
    default = settings()
    flight = _start_and_climb(r, rng)
    _rejected_updates(r, flight)
    _gps_model(r, flight, default)
    _gating(r, flight)
    _resets(r, flight)
    _terrain_reset_without_offsets(r, rng)
    flight = _ground_effect(r, rng)
    flight = _bias_estimation(r, rng, flight)
    bad = _rejected_settings(r, flight)
    _time_gaps(r, flight, default)
    _random_steps(r, rng, default, bad)
    return r


def _start_and_climb(r: Recorder, rng: random.Random) -> Flight:
    """Predict-only steps, initialise with NULL settings, then all three sensors in a climb; returns the flight."""
    r.section("initialise; predict-only steps (NULL measurements, then all-NaN measurements)")
    r.initialise()
    for _ in range(3):
        r.update_no_measurements(0.2, 0.01)
    for _ in range(3):
        r.update(0.2, 0.01)
    r.section("initialise with NULL settings (the defaults), then the first baro, range and GPS samples")
    r.initialise_with(None)
    flight = Flight(r, rng)
    flight.fly(300, "hover", baro_every=4, range_every=5, gps_every=20)
    r.section("all three sensors, 100 Hz, 25 Hz baro, 20 Hz range, 5 Hz GPS, climbing out of range (8 m)")
    flight.fly(900, "climb")
    return flight


def _rejected_updates(r: Recorder, flight: Flight) -> None:
    """Updates the C refuses (state unchanged, precedence) and the oddities it accepts."""
    r.section("rejected updates (state unchanged): accel inf/NaN, dt 0/-0/negative/NaN/inf/negative subnormal, "
              "baro +-inf, GPS +-inf, GPS accuracy 0/negative/inf/-0 with a GPS sample; precedence")
    for accel in (INF, -INF, NAN, from_bits(0x7F800001), from_bits(0xFFC00000)):
        r.update(accel, 0.01, 120.0)
        r.update_no_measurements(accel, 0.01)
    for dt in (0.0, -0.0, -0.01, NAN, INF, -INF, from_bits(0x80000001)):
        r.update(0.1, dt, 120.0)
        r.update_no_measurements(0.1, dt)
    for baro in (INF, -INF):
        r.update(0.1, 0.01, baro, 1.0, 170.0)
    for gps in (INF, -INF):
        r.update(0.1, 0.01, 120.0, 1.0, gps)
    for accuracy in (0.0, -0.0, -1.0, INF, -INF):
        r.update(0.1, 0.01, 120.0, 1.0, 170.0, accuracy, 9)
    r.update(INF, NAN, INF, 1.0, INF, -1.0)   # accel first
    r.update(0.1, 0.0, INF, 1.0, INF, -1.0)   # dt before baro
    r.update(0.1, 0.01, INF, 1.0, INF, -1.0)  # baro before GPS
    r.update(0.1, 0.01, 120.0, 1.0, INF, -1.0)  # GPS altitude before accuracy
    r.section("accepted oddities: bad GPS accuracy without a GPS sample, range +-inf/NaN payloads/out of limits "
              "(unusable), NaN payloads as 'no sample', subnormal dt and accel")
    flight.h = flight.v = 0.0
    flight.fly(40, "hover")
    r.update(0.1, 0.01, NAN, NAN, NAN, -1.0, 9)
    r.update(0.1, 0.01, NAN, NAN, NAN, INF, 9)
    for distance in (INF, -INF, -1.0, 0.0, 0.05, 8.5, 1e30):
        r.update(0.1, 0.01, rng=distance)
    for pattern in (0x7FC00000, 0xFFC00000, 0x7F800001, 0x7FFFFFFF, 0xFFFFFFFF, 0x7FC12345):
        nan = from_bits(pattern)
        r.update(0.1, 0.01, nan, nan, nan, nan, 9)
    r.update(from_bits(0x00000001), from_bits(0x00000001))
    r.update(from_bits(0x807FFFFF), 0.01, 120.0)


def _gps_model(r: Recorder, flight: Flight, default: dict) -> None:
    """GPS satellites (too few, unknown, 0, > 64) and reported accuracy (m)."""
    r.section("GPS model: too few satellites (unusable), unknown (-1: the minimum), 0 and > 64 with minimum 0, "
              "reported accuracy")
    for satellites in (3, 0, -1, -7, 4, 12, 64, 65, 1000, 2**31 - 1):
        flight.fly(20, "hover", gps_every=10, satellites=satellites)
    flight.fly(40, "hover", gps_every=10, accuracy=0.8)
    flight.fly(20, "hover", gps_every=10, accuracy=25.0, satellites=3)
    r.set_settings(settings(gps_min_satellites=0))
    for satellites in (0, 1, 2, -1):
        flight.fly(10, "hover", gps_every=5, satellites=satellites)
    r.set_settings(default)


def _gating(r: Recorder, flight: Flight) -> None:
    """Short baro, range and GPS spikes (m) rejected by the gate, then fused again."""
    r.section("gating: short baro, range and GPS spikes rejected, then fused again")
    flight.fly(100, "hover")
    for spike in (30.0, -30.0):
        flight.fly(12, "hover", baro_shift=spike, gps_every=0, range_every=0)
        flight.fly(40, "hover")
        flight.fly(6, "hover", gps_every=3, gps_shift=spike, baro_every=0, range_every=0)
        flight.fly(40, "hover")
    r.update(0.0, 0.01, rng=flight.h + 2.0)
    r.update(0.0, 0.01, rng=flight.h - 0.5)
    flight.fly(40, "hover")


def _resets(r: Recorder, flight: Flight) -> None:
    """Resets after the rejection timeout (0.2 s): baro step, GPS jump, terrain steps (m)."""
    r.section("resets after the rejection timeout (0.2 s): baro step +20 m, GPS jump -15 m, terrain step +1.5 m "
              "(range: ground reset, offsets take up the difference)")
    r.set_settings(settings(rejection_timeout=0.2))
    flight.baro_origin += 20.0
    flight.fly(150, "hover")
    flight.gps_origin -= 15.0
    flight.fly(200, "hover", gps_every=5)
    flight.terrain += 1.5
    flight.fly(150, "hover")
    flight.terrain -= 3.0
    flight.fly(150, "sine")


def _terrain_reset_without_offsets(r: Recorder, rng: random.Random) -> None:
    """Terrain resets before the GPS offset exists, and before the baro offset (timeout 0 s)."""
    r.section("terrain reset before the GPS offset exists (baro and range only), and before the baro offset "
              "(range only), timeout 0")
    r.initialise_with(settings(rejection_timeout=0.0))
    flight = Flight(r, rng, baro_origin=-40.0, gps_origin=300.0)
    flight.fly(100, "hover", gps_every=0)
    flight.terrain = -2.0
    flight.fly(60, "hover", gps_every=0)
    r.initialise_with(settings(rejection_timeout=0.05))
    flight.fly(40, "hover", baro_every=0, gps_every=0)
    flight.terrain = 0.5
    flight.fly(60, "hover", baro_every=0, gps_every=0)
    flight.fly(100, "hover")


def _ground_effect(r: Recorder, rng: random.Random) -> Flight:
    """Landing with the baro reading low (dead zone 0.5 m), take-off; returns the flight."""
    r.section("ground effect: landing with the baro reading low (dead zone 0.5 m: inside and beyond), "
              "take-off with a wider baro sigma")
    r.initialise_with(settings(ground_effect_noise_scale=2.0, ground_effect_dead_zone=0.5))
    flight = Flight(r, rng)
    flight.fly(100, "hover")
    flight.fly(100, "hover", ground_effect=True, baro_drop=0.3)
    flight.fly(100, "hover", ground_effect=True, baro_drop=1.2)
    flight.fly(60, "hover", ground_effect=True, baro_drop=-0.4)
    flight.fly(60, "hover")
    return flight


def _bias_estimation(r: Recorder, rng: random.Random, flight: Flight) -> Flight:
    """Bias estimation off and on mid-flight, and a filter initialised with it off; returns that flight."""
    r.section("bias estimation off mid-flight (b = 0, row cleared), flown, on again (initial sigma), "
              "and a filter initialised with it off")
    r.set_settings(settings(estimate_accel_bias=False))
    flight.bias = 0.3
    flight.fly(150, "climb")
    r.set_settings(settings(estimate_accel_bias=False, baro_noise=0.8))
    flight.fly(50, "climb")
    r.set_settings(settings(estimate_accel_bias=True, accel_bias_initial_sigma=0.5))
    flight.fly(200, "climb")
    r.initialise_with(settings(estimate_accel_bias=False, accel_bias_random_walk=0.0))
    flight = Flight(r, rng, bias=0.2)
    flight.fly(150, "sine")
    return flight


def _rejected_settings(r: Recorder, flight: Flight) -> list:
    """Every invalid setting (state unchanged) and edge settings accepted; returns the bad settings."""
    r.section("rejected settings (state unchanged), every status group, by SetSettings and InitialiseWith")
    bad = [settings(accel_noise=-0.1), settings(accel_bias_random_walk=NAN), settings(accel_bias_initial_sigma=INF),
           settings(baro_noise=0.0), settings(baro_offset_random_walk=-1e-9), settings(range_noise=-0.0),
           settings(gps_offset_random_walk=NAN), settings(initial_height_sigma=-1.0),
           settings(initial_velocity_sigma=INF), settings(range_min=-0.1), settings(range_max=NAN),
           settings(range_min=5.0, range_max=5.0), settings(range_min=INF, range_max=INF),
           settings(gps_noise_base=-1.0), settings(gps_noise_satellite=NAN),
           settings(gps_noise_base=0.0, gps_noise_satellite=0.0), settings(gps_min_satellites=-1),
           settings(gate=0.0), settings(gate=NAN), settings(rejection_timeout=-0.5), settings(rejection_timeout=INF),
           settings(ground_effect_noise_scale=0.99), settings(ground_effect_noise_scale=NAN),
           settings(ground_effect_dead_zone=-0.1), settings(accel_noise=NAN, range_min=-1.0, gate=0.0),
           settings(gap_period=0.0), settings(gap_period=-1.0), settings(gap_period=NAN)]
    for values in bad:
        r.set_settings(values)
        r.initialise_with(values)
    r.section("edge settings accepted: zero noises and random walks, timeout 0, minimum 0, huge gate")
    r.set_settings(settings(accel_noise=0.0, accel_bias_random_walk=0.0, baro_offset_random_walk=0.0,
                            gps_offset_random_walk=0.0, gps_noise_base=0.0, rejection_timeout=0.0, gate=1e6))
    flight.fly(60, "sine")
    r.set_settings(settings(gps_noise_satellite=0.0, gate=1.0, initial_height_sigma=0.0))
    flight.fly(60, "sine")
    return bad


def _time_gaps(r: Recorder, flight: Flight, default: dict) -> None:
    """dt at and above the gap period (s), an accel glitch burst, streaks past the timeout, gap period +inf."""
    r.section("time gaps: dt at the gap period (predicted), above it (no prediction: h and v inflated, streaks "
              "ended) with and without samples, in a climb; an accel glitch burst recovered through the timeout "
              "(h, v and b inflated with the reset); gap period +infinity")
    r.set_settings(default)
    flight.fly(200, "climb")
    r.update(0.2, 0.5)
    r.update(3.0, 2.0)
    flight.t += 2.0
    flight.fly(300, "climb")
    r.update(0.0, 1.2, 120.0 + flight.h, flight.h if flight.h > 0.1 else NAN, 160.0 + flight.h, NAN, 9, False)
    flight.fly(200, "climb")
    for _ in range(40):
        r.update(25.0, 0.01, 120.0 + flight.h)
    flight.fly(500, "hover")
    r.section("a streak past the timeout with nothing else fused (baro only, then GPS only): h, v and b inflated "
              "and the sample fused with that covariance, not its offset re-based")
    for _ in range(150):
        r.update(8.0, 0.01, 120.0 + flight.h)
    flight.fly(300, "hover", gps_every=0, range_every=0)
    flight.gps_origin += 25.0
    for _ in range(60):
        r.update(-6.0, 0.05, NAN, NAN, flight.gps_origin + flight.h, NAN, 9, False)
    flight.fly(300, "hover")
    r.set_settings(settings(gap_period=INF))
    r.update(0.0, 30.0, 120.0 + flight.h)
    flight.fly(100, "hover")


def _random_steps(r: Recorder, rng: random.Random, default: dict, bad: list) -> None:
    """1500 random-ish steps: jittered dt, sensors, spikes, ground effect, rejected inputs, retunes."""
    r.section("random-ish steps: jittered dt, random sensor presence, spikes, ground effect, rejected inputs, "
              "retunes and re-initialisations")
    r.initialise()
    flight = Flight(r, rng)
    tunings = [default, settings(rejection_timeout=0.1), settings(gate=3.0, baro_noise=0.3),
               settings(estimate_accel_bias=False), settings(range_max=30.0, range_noise=0.1),
               settings(accel_noise=0.2, gps_min_satellites=6), settings(gps_noise_base=0.0, gps_noise_satellite=5.0)]
    bad_floats = (INF, -INF, NAN, from_bits(0xFFC00000))
    for _ in range(1500):
        choice = rng.random()
        dt = 0.01 * (0.5 + rng.random())
        if choice > 0.996:
            dt = rng.uniform(0.3, 3.0)  # sometimes a time gap
        flight.dt = dt
        if choice < 0.01:
            r.update(rng.choice(bad_floats), dt, 120.0)
        elif choice < 0.02:
            r.update(0.0, rng.choice((0.0, -dt, NAN, INF)), 120.0)
        elif choice < 0.025:
            r.update(0.0, dt, rng.choice((INF, -INF)), gps=170.0)
        elif choice < 0.03:
            r.update(0.0, dt, gps=rng.choice((INF, -INF, 170.0)), accuracy=rng.choice((-1.0, 0.0, INF)))
        elif choice < 0.035:
            r.set_settings(rng.choice(tunings))
        elif choice < 0.037:
            r.set_settings(rng.choice(bad))
        elif choice < 0.038:
            r.initialise_with(rng.choice(tunings + bad[:3]))
            flight = Flight(r, rng, dt=dt)
        elif choice < 0.045:
            r.update_no_measurements(flight.noise(0.1), dt)
        elif choice < 0.055:
            r.update(flight.noise(0.1), dt, 120.0 + flight.h + rng.uniform(-40.0, 40.0),
                     rng.uniform(-1.0, 40.0), 160.0 + flight.h + rng.uniform(-60.0, 60.0),
                     rng.choice((NAN, rng.uniform(0.1, 30.0))), rng.randint(-1, 20), rng.random() < 0.3)
        else:
            flight.fly(1, rng.choice(("hover", "climb", "sine", "descend")),
                       baro_every=rng.choice((1, 0, 2)), range_every=rng.choice((1, 0, 0)),
                       gps_every=rng.choice((0, 0, 0, 1)), satellites=rng.randint(-1, 15),
                       accuracy=NAN if rng.random() < 0.8 else rng.uniform(0.2, 5.0),
                       ground_effect=rng.random() < 0.1)


def check_representable(records) -> None:
    """Refuses vectors whose bits could depend on the FPU's NaN or overflow handling."""
    float_fields = [i for i, name in enumerate(STATE_FIELDS)
                    if not name.endswith(("rejections", "resets", "result", "rejecting", "Initialised",
                                          "estimate_accel_bias", "gps_min_satellites", "gapCount"))]
    for index, (_, _, _, state) in enumerate(records):
        for field in float_fields:
            name, pattern = STATE_FIELDS[field], state[field]
            if name.startswith("settings."):
                continue  # settings are copied from the inputs: any accepted bit pattern is exact
            if (pattern & 0x7F800000) == 0x7F800000 and not (name in NAN_ALLOWED and pattern == QUIET_NAN_BITS):
                raise AssertionError(f"record {index}: {name} = {pattern:#010x} is not finite")


def word(pattern: int) -> str:
    return str(pattern) if pattern < 10 else f"0x{pattern:08x}"


def _file_comment(recorder: Recorder) -> list:
    """The opening comment of kalman_vectors.h, up to the coverage counts (without its closing line)."""
    counts = ", ".join(f"{key} {value}" for key, value in sorted(recorder.counts.items()))
    lines = [
        "/**",
        " * @file kalman_vectors.h",
        " * @brief Test vectors of fusion_altitude_kalman.h generated by",
        " * csrc/tests/vectors/generate_kalman.py from the pure-Python reference",
        " * (fusion_altitude.reference.kalman). Do not edit: regenerate.",
        " *",
        " * Each record is one call; floats are IEEE 754 binary32 bit patterns.",
        " * input: update (accel m/s^2, dt s, baro altitude m, range distance m, GPS",
        " * altitude m, GPS vertical accuracy m, GPS satellites int32, ground effect 0/1);",
        " * update without measurements (accel, dt; measurements NULL); initialise with",
        " * and set settings (index into fusionAltitudeKalmanVectorSettings, 0xffffffff:",
        " * NULL). hash: FNV-1a over the 67 state words after the call (see",
        " * generate_kalman.py); checkpoints: the state words themselves.",
        " *",
        " * Sections (record index: description):",
    ]
    lines += [f" *   {comment}" for comment in recorder.comments]
    lines += [" *", " * Coverage (sensor results of accepted updates; statuses of other calls):"]
    text = ""
    for item in counts.split(", "):
        if len(text) + len(item) > 72:
            lines.append(f" *   {text.rstrip(', ')}")
            text = ""
        text += item + ", "
    lines.append(f" *   {text.rstrip(', ')}")
    return lines


def render() -> str:
    """The text of kalman_vectors.h."""
    with np.errstate(over="ignore", invalid="ignore"):
        recorder = build()
    records = recorder.records
    check_representable(records)
    checkpoints = [i for i in range(len(records)) if i % CHECKPOINT_EVERY == 0 or i == len(records) - 1]
    lines = _file_comment(recorder)
    lines += [
        " */",
        "",
        "#ifndef FUSION_ALTITUDE_KALMAN_VECTORS_H",
        "#define FUSION_ALTITUDE_KALMAN_VECTORS_H",
        "",
        "#include <stdint.h>",
        "",
        "typedef enum {",
    ]
    lines += [f"    FusionAltitudeKalmanVectorOp{''.join(w.title() for w in name.split('_'))} = {index},"
              for index, name in enumerate(OPS)]
    lines += [
        "} FusionAltitudeKalmanVectorOp;",
        "",
        "typedef struct {",
        "    uint8_t op;        /**< FusionAltitudeKalmanVectorOp */",
        "    uint8_t status;    /**< expected FusionAltitudeKalmanStatus */",
        "    uint32_t input[8]; /**< arguments (unused ones 0) */",
        "    uint32_t hash;     /**< FNV-1a of the state words after the call */",
        "} FusionAltitudeKalmanVector;",
        "",
        "typedef struct {",
        "    uint32_t record;                                          /**< index of the record */",
        "    uint32_t state[FUSION_ALTITUDE_KALMAN_VECTOR_STATE_WORDS]; /**< state words after it */",
        "} FusionAltitudeKalmanVectorCheckpoint;",
        "",
    ]
    # The state-word count must precede the checkpoint struct: insert it above.
    lines.insert(lines.index("typedef struct {", lines.index("} FusionAltitudeKalmanVectorOp;")),
                 f"#define FUSION_ALTITUDE_KALMAN_VECTOR_STATE_WORDS ({len(STATE_FIELDS)})\n")
    lines += [f"#define FUSION_ALTITUDE_KALMAN_VECTOR_SETTINGS_COUNT ({len(recorder.settings_table)})", "",
              "static const uint32_t fusionAltitudeKalmanVectorSettings[FUSION_ALTITUDE_KALMAN_VECTOR_SETTINGS_COUNT]"
              f"[{len(KALMAN_SETTINGS)}] = {{"]
    for words in recorder.settings_table:
        lines.append("    {" + ",".join(word(p) for p in words) + "},")
    lines += ["};", "", f"#define FUSION_ALTITUDE_KALMAN_VECTOR_COUNT ({len(records)})", "",
              "static const FusionAltitudeKalmanVector fusionAltitudeKalmanVectors[FUSION_ALTITUDE_KALMAN_VECTOR_COUNT]"
              " = {"]
    for op, status, inputs, state in records:
        lines.append(f"    {{{op},{status},{{{','.join(word(p) for p in inputs)}}},0x{fnv1a(state):08x}}},")
    lines += ["};", "", f"#define FUSION_ALTITUDE_KALMAN_VECTOR_CHECKPOINT_COUNT ({len(checkpoints)})", "",
              "static const FusionAltitudeKalmanVectorCheckpoint "
              "fusionAltitudeKalmanVectorCheckpoints[FUSION_ALTITUDE_KALMAN_VECTOR_CHECKPOINT_COUNT] = {"]
    for index in checkpoints:
        lines.append(f"    {{{index},{{{','.join(word(p) for p in records[index][3])}}}}},")
    lines += ["};", "", "#endif", ""]
    return "\n".join(lines)



if __name__ == "__main__":
    sys.exit(vc.main(HEADER_PATH, render, sys.argv[1:], __doc__))
