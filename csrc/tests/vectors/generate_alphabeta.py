"""Generates alphabeta_vectors.h: test vectors of the quality-weighted alpha-beta fusion for the C replay.

Every record is one call on one fusion (initialise, initialise with settings,
set settings, update) with its inputs, the expected status and an FNV-1a
hash of the full state after the call, computed by the pure-Python reference
(fusion_altitude.reference.alphabeta), never by the C binding; every 64th
record (and the last) carries the state words themselves (format:
vector_common.py). csrc/firmware/replay_alphabeta.c replays them on the host
(gcc, clang) and on an emulated Cortex-M4F (QEMU).

The state, as 79 words (STATE_FIELDS, the same order in replay_alphabeta.c):
per sensor (IMU, baro, lidar, sonar, GPS) its 8 settings (threshold, quality
minimum and maximum, confidence, altitude band, gap maximum, timeout), then
per sensor its filter (altitude, velocity, time since its sample, gap,
weight, quality, started), then the fused altitude, vertical velocity, total
weight and started flag.

    python csrc/tests/vectors/generate_alphabeta.py           # rewrite alphabeta_vectors.h
    python csrc/tests/vectors/generate_alphabeta.py --check   # exit 1 if it is stale

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

from fusion_altitude._alphabeta_glue import (ALPHABETA_SENSORS, AlphaBetaSensorSettings,  # noqa: E402
                                             AlphaBetaStatus, convert_alphabeta_settings)
from fusion_altitude.reference import alphabeta as _alphabeta  # noqa: E402

HEADER_PATH = Path(__file__).resolve().with_name("alphabeta_vectors.h")
NAN = float("nan")
INF = float("inf")

OPS = ("INITIALISE", "INITIALISE_WITH", "SET_SETTINGS", "UPDATE")
FILTER_FIELDS = ("altitude", "velocity", "sinceSample", "gap", "weight", "quality", "started")
SETTINGS_FIELDS = tuple(f"settings.{sensor}.{field}" for sensor in ALPHABETA_SENSORS
                        for field in AlphaBetaSensorSettings._fields) + ("settings.gapPeriod",)
STATE_FIELDS = (SETTINGS_FIELDS + tuple(f"{sensor}.{field}" for sensor in ALPHABETA_SENSORS for field in FILTER_FIELDS)
                + ("altitude", "verticalVelocity", "totalWeight", "started", "coastingFor", "gapTime", "gapCount"))
FLOAT_FIELDS = tuple(f"{sensor}.{field}" for sensor in ALPHABETA_SENSORS for field in FILTER_FIELDS[:5]) + (
    "altitude", "verticalVelocity", "totalWeight", "coastingFor", "gapTime")
#: What tools/make_replays.py cannot read from the header and STATE_FIELDS to write csrc/firmware/replay_alphabeta.c
#: (the keys: its SPECIAL_KEYS).
REPLAY = {
    "paths": {f"{sensor}.": f"filters[FusionAltitudeAlphaBetaSensor{sensor.capitalize()}]."
              for sensor in ALPHABETA_SENSORS},
    "getters": {f"{sensor}.{field}": f"FusionAltitudeAlphaBeta{getter}(filter, "
                                     f"FusionAltitudeAlphaBetaSensor{sensor.capitalize()})"
                for sensor in ALPHABETA_SENSORS
                for field, getter in (("weight", "GetWeight"), ("quality", "GetQuality"))},
}


def settings_words(values: Dict[str, AlphaBetaSensorSettings]) -> tuple:
    """FusionAltitudeAlphaBetaSettings as words (floats as bits, int32 two's complement)."""
    return tuple((int(value) & 0xFFFFFFFF) if field.startswith("quality") else vc.bits(value)
                 for sensor in ALPHABETA_SENSORS
                 for field, value in zip(AlphaBetaSensorSettings._fields, values[sensor])) + (
        vc.bits(values["gap_period"]),)


def settings(**sensors) -> Dict[str, AlphaBetaSensorSettings]:
    """Default settings with some sensors' fields changed ({sensor: {field: value}}), converted, not checked."""
    return convert_alphabeta_settings(sensors)


def check(values: Dict[str, AlphaBetaSensorSettings]) -> AlphaBetaStatus:
    """FusionAltitudeAlphaBetaSettingsCheck: the first failing sensor's status."""
    for sensor in ALPHABETA_SENSORS:
        status = _alphabeta._sensor_status(values[sensor])
        if status != AlphaBetaStatus.OK:
            return status
    return _alphabeta._gap_period_status(values["gap_period"])


#: The traced-path program csrc/firmware/cycles_alphabeta.c (tools/make_cycles.py writes it): a warm-up with all
#: four sensors (REPEAT, not traced), then the traced calls (path name, (OP, accel m/s^2, dt s, baro, lidar, sonar,
#: GPS altitudes m)) of SizedFusionAltitudeAlphaBetaUpdate, on a filter initialised with the default settings.
CYCLES = (
    ("REPEAT", 10, ("UPDATE", 0.0, 0.01, 2.1, 2.0, 2.05, 1.5)),
    ("IMU and all four sensors", ("UPDATE", 0.0, 0.01, 2.1, 2.0, 2.05, 1.5)),
    ("IMU and baro", ("UPDATE", 0.0, 0.01, 2.1)),
    ("IMU only (the other filters predict)", ("UPDATE", 0.0, 0.01)),
    ("rejected (accel infinite)", ("UPDATE", INF, 0.01)),
)


class Recorder(vc.Recorder):
    OPS = OPS
    INPUTS = 6

    def __init__(self) -> None:
        super().__init__()
        self.fusion = _alphabeta.AlphaBetaFusion()

    def state(self) -> tuple:
        f = self.fusion
        words = settings_words(f.settings.as_dict())
        for flt in f._filters:
            words += tuple(vc.bits(x) for x in (flt.x, flt.v, flt.since, flt.gap, flt.weight))
            words += (int(flt.quality) & 0xFFFFFFFF, int(flt.started))
        return words + (vc.bits(f._h), vc.bits(f._v), vc.bits(f._total), int(f._started), vc.bits(f._coasting),
                        vc.bits(f._gap_time), f._gap_count)

    # FusionAltitudeAlphaBetaInitialise
    def initialise(self) -> None:
        self.fusion = _alphabeta.AlphaBetaFusion()
        self.record("INITIALISE", (), AlphaBetaStatus.OK)

    # FusionAltitudeAlphaBetaInitialiseWith
    def initialise_with(self, values) -> None:
        status = check(values)
        if status == AlphaBetaStatus.OK:
            self.fusion = _alphabeta.AlphaBetaFusion(_alphabeta.AlphaBetaSettings(**values))
        self.record("INITIALISE_WITH", (self.settings_index(settings_words(values)),), status)

    # FusionAltitudeAlphaBetaSetSettings
    def set_settings(self, values) -> None:
        status = check(values)
        if status == AlphaBetaStatus.OK:
            self.fusion.settings = _alphabeta.AlphaBetaSettings(**values)
        self.record("SET_SETTINGS", (self.settings_index(settings_words(values)),), status)

    # FusionAltitudeAlphaBetaUpdate
    def update(self, accel, dt, baro=NAN, lidar=NAN, sonar=NAN, gps=NAN) -> None:
        a, t, *z = (vc.as_f32(v) for v in (accel, dt, baro, lidar, sonar, gps))
        f = self.fusion
        before = [(flt.started, bool(flt.weight > 0)) for flt in f._filters]
        was_started = f._started
        status = f._update(a, t, tuple(z))
        self.record("UPDATE", tuple(vc.bits(v) for v in (a, t, *z)), status)
        if status != AlphaBetaStatus.OK:
            return
        if not was_started:
            self.count("update start" if f._started else "update waiting")
            return
        if not f._total > 0:
            self.count("update dead reckoning")
        samples = [bool(np.isfinite(a))] + [bool(np.isfinite(v)) for v in z]
        for sensor, flt, sampled, (was, weighted) in zip(ALPHABETA_SENSORS, f._filters, samples, before):
            if flt.weight > 0:
                self.count(f"{sensor} weighted")
            elif flt.started:
                self.count(f"{sensor} dropped")
            if sampled and not weighted and flt.weight > 0:
                self.count(f"{sensor} recovered")
            if sampled and was and flt.since == 0 and flt.quality == getattr(f.settings, sensor).quality_min:
                self.count(f"{sensor} at quality min")
            if flt.quality == getattr(f.settings, sensor).quality_max:
                self.count(f"{sensor} at quality max")


class Flight:
    """A simulated vertical flight: true height h over flat ground, accel with bias, five sensors."""

    def __init__(self, recorder: Recorder, rng: random.Random, dt: float = 0.01, bias: float = 0.05,
                 baro_origin: float = 0.0, gps_origin: float = 0.0) -> None:
        self.r, self.rng, self.dt, self.bias = recorder, rng, dt, bias
        self.baro_origin, self.gps_origin = baro_origin, gps_origin
        self.h = self.v = self.t = 0.0
        self.k = 0

    def noise(self, sigma: float) -> float:
        return sigma * (self.rng.random() + self.rng.random() + self.rng.random() - 1.5) * 2.0

    def fly(self, steps: int, profile: str = "hover", imu: bool = True, baro_every: int = 4, lidar_every: int = 5,
            sonar_every: int = 10, gps_every: int = 20, shift: Optional[Dict[str, float]] = None,
            rate: float = 1.5) -> None:
        shift = shift or {}
        start = self.t
        for _ in range(steps):
            if profile == "hover":
                a_true = 0.0
            elif profile == "climb":  # from the start of fly(): up to `rate` m/s in 1 s, 3 s at it, stop in 1 s
                phase = (self.t - start) % 8.0
                a_true = rate if phase < 1.0 else (-rate if 4.0 <= phase < 5.0 else 0.0)
            elif profile == "descend":
                phase = (self.t - start) % 8.0
                a_true = -rate if phase < 1.0 else (rate if 4.0 <= phase < 5.0 else 0.0)
            else:  # "sine"
                a_true = 1.0 * math.sin(0.9 * self.t)
            self.v += a_true * self.dt
            self.h += self.v * self.dt
            self.t += self.dt
            k = self.k
            self.k += 1

            def sample(every: int, value: float, sigma: float, name: str) -> float:
                return value + shift.get(name, 0.0) + self.noise(sigma) if every and k % every == 0 else NAN

            accel = a_true + self.bias + self.noise(0.05) if imu else NAN
            self.r.update(accel, self.dt, sample(baro_every, self.baro_origin + self.h, 0.3, "baro"),
                          sample(lidar_every, self.h, 0.03, "lidar"), sample(sonar_every, self.h, 0.05, "sonar"),
                          sample(gps_every, self.gps_origin + self.h, 1.0, "gps"))


def build() -> Recorder:
    """All scenarios, in order, on one fusion (state carries over between sections)."""
    r = Recorder()
    rng = random.Random(20261125)
    default = settings()
    flight = _start_and_climb(r, rng)
    slow = dict(baro_every=2, lidar_every=2, sonar_every=5, gps_every=10)
    _drops_and_disagreement(r, flight, slow)
    _rejected_updates(r, flight, slow)
    _retunes(r, flight, slow, default)
    bad = _rejected_settings(r)
    _time_gaps(r, rng, default)
    flight = _initialise_with(r, rng, default)
    _random_steps(r, rng, flight, default, bad)
    return r


def _start_and_climb(r: Recorder, rng: random.Random) -> Flight:
    """Initialise, wait, start; 100 Hz hover with every sensor; a 25 Hz climb and descent through the bands."""
    r.section("initialise; waiting (accel only, all NaN), then the start on the first baro sample")
    r.initialise()
    r.update(0.1, 0.01)
    r.update(NAN, 0.01)
    r.update(0.1, 0.01, baro=0.4)
    r.section("100 Hz IMU, 25 Hz baro, 20 Hz lidar, 10 Hz sonar, 5 Hz GPS at 1 m: qualities climb to their maxima")
    flight = Flight(r, rng, baro_origin=0.3, gps_origin=-0.5)
    flight.h = 1.0
    flight.fly(300, "hover")
    r.section("25 Hz steps, climb at 5.5 m/s out of the sonar band (5 m) and the lidar band (40 m), then back down")
    flight.dt = 0.04
    fast = dict(baro_every=1, lidar_every=1, sonar_every=2, gps_every=5)
    flight.fly(400, "climb", rate=5.5, **fast)
    flight.fly(400, "descend", rate=5.5, **fast)
    flight.dt = 0.02
    return flight


def _drops_and_disagreement(r: Recorder, flight: Flight, slow: dict) -> None:
    """Sensors dropping out and recovering, a baro offset, spikes, dead reckoning (50 Hz steps)."""
    r.section("50 Hz steps; sensor drop and recovery: lidar silent 2 s (beyond its 1.5 s timeout: weight 0, "
              "restart), GPS silent 1 s (within it), baro and sonar silent together, IMU (accel NaN) missing 0.5 s")
    flight.fly(100, "hover", **{**slow, "lidar_every": 0})
    flight.fly(50, "hover", **slow)
    flight.fly(50, "hover", **{**slow, "gps_every": 0})
    flight.fly(50, "hover", **slow)
    flight.fly(90, "hover", **{**slow, "baro_every": 0, "sonar_every": 0})
    flight.fly(50, "hover", **slow)
    flight.fly(25, "hover", imu=False, **slow)
    flight.fly(50, "hover", **slow)
    r.section("disagreement: baro offset 3 m (quality falls to its minimum), spikes beyond the gap maxima "
              "(weight 0 until the next close sample restarts the filter)")
    flight.fly(150, "hover", shift={"baro": 3.0}, **slow)
    flight.fly(50, "hover", **slow)
    flight.fly(10, "hover", shift={"baro": 15.0, "lidar": 8.0, "sonar": -7.0, "gps": 25.0}, **slow)
    flight.fly(50, "hover", **slow)
    r.section("dead reckoning: every sensor silent past its timeout, accel only; then all come back")
    flight.fly(100, "climb", rate=0.5, baro_every=0, lidar_every=0, sonar_every=0, gps_every=0)
    flight.fly(10, "hover", imu=False, baro_every=0, lidar_every=0, sonar_every=0, gps_every=0)
    flight.fly(100, "hover", **slow)


def _rejected_updates(r: Recorder, flight: Flight, slow: dict) -> None:
    """Updates the C refuses (state unchanged) and the oddities it accepts (NaN payloads, subnormal dt, -0)."""
    r.section("rejected updates (state unchanged): accel +-inf, dt 0/-0/negative/NaN/inf/negative subnormal, "
              "each sensor +-inf; precedence")
    for accel in (INF, -INF):
        r.update(accel, 0.01, baro=1.0)
    for dt in (0.0, -0.0, -0.01, NAN, INF, -INF, vc.from_bits(0x80000001)):
        r.update(0.1, dt, baro=1.0)
    for index in range(4):
        for value in (INF, -INF):
            z = [1.0, 1.0, 1.0, 1.0]
            z[index] = value
            r.update(0.1, 0.01, *z)
    r.update(INF, NAN, INF, INF, INF, INF)   # accel first
    r.update(0.1, 0.0, INF, INF, INF, INF)   # dt before the sensors
    r.update(0.1, 0.01, INF, INF, INF, INF)  # baro before lidar
    r.update(0.1, 0.01, 1.0, INF, INF, INF)  # lidar before sonar
    r.update(0.1, 0.01, 1.0, 1.0, INF, INF)  # sonar before GPS
    r.section("accepted oddities: NaN payloads as 'no sample' (accel included), subnormal dt, -0 samples")
    for pattern in (0x7FC00000, 0xFFC00000, 0x7F800001, 0x7FFFFFFF, 0xFFFFFFFF, 0x7FC12345):
        nan = vc.from_bits(pattern)
        r.update(nan, 0.01, nan, nan, nan, nan)
    r.update(vc.from_bits(0x00000001), 0.01, -0.0, -0.0, NAN, NAN)
    flight.fly(30, "hover", **slow)


def _retunes(r: Recorder, flight: Flight, slow: dict, default: dict) -> None:
    """Settings changed mid-flight: clamped qualities, narrow thresholds, bands excluding everything."""
    r.section("settings: retuned mid-flight (qualities clamped into the new ranges), narrow thresholds, "
              "no confidence in the baro, short timeouts, altitude bands excluding everything")
    r.set_settings(settings(baro={"quality_min": 2, "quality_max": 5}, gps={"quality_min": 50, "quality_max": 60},
                            lidar={"threshold": 0.01}))
    flight.fly(60, "sine", **slow)
    r.set_settings(settings(baro={"confidence": 0.0}, imu={"confidence": 0.0}, sonar={"timeout": 0.05},
                            lidar={"gap_max": INF}))
    flight.fly(60, "sine", **slow)
    r.set_settings(settings(**{s: {"altitude_min": 100.0, "altitude_max": 200.0} for s in ALPHABETA_SENSORS}))
    flight.fly(40, "sine", **slow)
    r.set_settings(settings(**{s: {"quality_min": 10000, "quality_max": 10000, "altitude_min": -INF}
                               for s in ALPHABETA_SENSORS}))
    flight.fly(40, "sine", **slow)
    r.set_settings(default)
    flight.fly(60, "hover", **slow)


def _rejected_settings(r: Recorder) -> list:
    """Every invalid setting by SetSettings and InitialiseWith (state unchanged); returns the bad settings."""
    r.section("rejected settings (state unchanged), every status, by SetSettings and InitialiseWith; the "
              "first failing sensor wins")
    bad = [settings(imu={"threshold": 0.0}), settings(baro={"threshold": NAN}), settings(gps={"threshold": INF}),
           settings(lidar={"quality_min": 1}), settings(sonar={"quality_min": 9, "quality_max": 8}),
           settings(gps={"quality_max": 10001}), settings(baro={"quality_min": -5}),
           settings(imu={"confidence": -0.1}), settings(gps={"confidence": INF}), settings(lidar={"confidence": NAN}),
           settings(baro={"altitude_min": 5.0, "altitude_max": 5.0}), settings(sonar={"altitude_min": NAN}),
           settings(gps={"altitude_max": NAN}), settings(imu={"altitude_min": INF, "altitude_max": INF}),
           settings(lidar={"gap_max": 0.0}), settings(baro={"gap_max": NAN}), settings(gps={"gap_max": -INF}),
           settings(sonar={"timeout": 0.0}), settings(imu={"timeout": INF}), settings(gps={"timeout": NAN}),
           settings(baro={"timeout": 0.0}, imu={"threshold": -1.0}), settings(gap_period=0.0),
           settings(gap_period=NAN), settings(gap_period=-2.0)]
    for values in bad:
        r.set_settings(values)
        r.initialise_with(values)
    return bad


def _time_gaps(r: Recorder, rng: random.Random, default: dict) -> None:
    """dt above the gap period with and without samples, bounded dead reckoning, an infinite gap period."""
    r.section("time gaps: dt above the gap period with samples (restart on them, mean velocity), without "
              "(held until the next samples); bounded dead reckoning: the IMU alone for longer than the gap period "
              "stops the fusion until the next samples; gap period +infinity")
    flight = Flight(r, rng)
    flight.h = 3.0
    flight.fly(200, "climb")
    flight.h += 4.0
    r.update(2.0, 2.0, baro=flight.h + 0.1, gps=flight.h - 0.5)
    flight.fly(100, "climb")
    r.update(0.5, 1.6)
    r.update(0.5, 0.01)
    r.update(0.5, 0.01, lidar=flight.h)
    flight.fly(100, "sine")
    flight.fly(400, "hover", baro_every=0, lidar_every=0, sonar_every=0, gps_every=0)
    flight.fly(100, "hover")
    r.set_settings(settings(gap_period=INF))
    r.update(0.0, 30.0, baro=flight.h)
    flight.fly(50, "hover")
    r.set_settings(default)


def _initialise_with(r: Recorder, rng: random.Random, default: dict) -> Flight:
    """A balloon (1 Hz baro, 3 s timeouts) initialised with settings, then the defaults; returns the flight."""
    r.section("initialise with settings: a balloon (1 Hz baro, 3 s timeouts), then the defaults")
    r.initialise_with(settings(**{s: {"timeout": 3.0} for s in ALPHABETA_SENSORS}))
    flight = Flight(r, rng, dt=0.1, baro_origin=500.0, gps_origin=480.0)
    flight.h = 500.0
    flight.fly(60, "sine", baro_every=10, lidar_every=0, sonar_every=0, gps_every=5)
    r.initialise_with(default)
    r.update(NAN, 0.01, gps=12.0)
    flight = Flight(r, rng)
    flight.h = 2.0
    flight.fly(50, "hover")
    return flight


def _random_steps(r: Recorder, rng: random.Random, flight: Flight, default: dict, bad: list) -> None:
    """700 random-ish steps: jittered dt, random sensors and spikes, rejected inputs, retunes, re-initialisations."""
    r.section("random-ish steps: jittered dt, random sensor presence and spikes, rejected inputs, retunes and "
              "re-initialisations")
    tunings = [default, settings(lidar={"threshold": 0.1}, baro={"quality_max": 20}),
               settings(**{s: {"timeout": 0.3} for s in ALPHABETA_SENSORS}),
               settings(gps={"confidence": 5.0, "gap_max": 3.0}), settings(imu={"confidence": 0.5, "quality_max": 40})]
    for _ in range(700):
        choice = rng.random()
        dt = 0.01 * (0.5 + rng.random())
        if choice > 0.996:
            dt = rng.uniform(1.0, 3.0)  # sometimes a time gap
        flight.dt = dt
        if choice < 0.01:
            r.update(rng.choice((INF, -INF)), dt, baro=1.0)
        elif choice < 0.02:
            r.update(0.0, rng.choice((0.0, -dt, NAN, INF)), baro=1.0)
        elif choice < 0.025:
            z = [rng.choice((NAN, 1.0, INF, -INF)) for _ in range(4)]
            r.update(0.0, dt, *z)
        elif choice < 0.03:
            r.set_settings(rng.choice(tunings))
        elif choice < 0.033:
            r.set_settings(rng.choice(bad))
        elif choice < 0.035:
            r.initialise_with(rng.choice(tunings + bad[:2]))
        elif choice < 0.036:
            r.initialise()
        elif choice < 0.05:
            r.update(flight.noise(0.1), dt, *(flight.h + rng.uniform(-30.0, 30.0) if rng.random() < 0.5 else NAN
                                             for _ in range(4)))
        else:
            flight.fly(1, rng.choice(("hover", "climb", "sine", "descend")), imu=rng.random() < 0.95,
                       baro_every=rng.choice((1, 0, 2)), lidar_every=rng.choice((1, 0, 0)),
                       sonar_every=rng.choice((1, 0, 0, 0)), gps_every=rng.choice((0, 0, 0, 1)))


def render() -> str:
    """The text of alphabeta_vectors.h."""
    with np.errstate(over="ignore", invalid="ignore"):
        recorder = build()
    vc.check_finite(recorder.records, STATE_FIELDS, FLOAT_FIELDS)
    description = [
        "Each record is one call; floats are IEEE 754 binary32 bit patterns.",
        "input: update (accel m/s^2 or NaN, dt s, baro, lidar, sonar and GPS",
        "altitudes m or NaN); initialise with and set settings (index into",
        "fusionAltitudeAlphaBetaVectorSettings); initialise (none).",
    ]
    return vc.render(recorder, file="alphabeta_vectors.h", header="fusion_altitude_alphabeta.h",
                     generator="generate_alphabeta.py", reference="fusion_altitude.reference.alphabeta",
                     type_prefix="FusionAltitudeAlphaBeta", macro_prefix="FUSION_ALTITUDE_ALPHABETA",
                     description=description, state_fields=STATE_FIELDS, settings_words=len(SETTINGS_FIELDS),
                     checkpoint_every=128)


if __name__ == "__main__":
    sys.exit(vc.main(HEADER_PATH, render, sys.argv[1:], __doc__))
