"""The multi-sensor altitude Kalman filter, in plain Python.

Read it next to ``csrc/fusion_altitude_kalman.h``: every method below mirrors
the C function named in its docstring, statement for statement, in float32
scalar arithmetic (numpy scalars) in the same operation order, so its results
equal the C core's bit for bit.

State x (m, m/s, m, m, m/s²): height above ground h, vertical velocity v,
baro offset ob (the baro reads h + ob), GPS offset og (GPS reads h + og),
accelerometer bias b.

Prediction with u = a − b:  h += v·dt + u·dt²/2,  v += u·dt;
P = F·P·Fᵀ + Q with F = I + dt·E01 − (dt²/2)·E04 − dt·E14,
Q = N_a²/dt·B·Bᵀ (B = (dt²/2, dt, 0, 0, 0)ᵀ) + dt·diag(0, 0, N_ob², N_og², N_b²).

Measurements, as sequential scalar updates: baro h + ob, rangefinder h,
GPS h + og. Each: c = P·Hᵀ, S = H·c + R, K = c/S, y = z − H·x,
x += K·y, P = P − K·cᵀ − c·Kᵀ + S·K·Kᵀ (Joseph form, expanded).
"""

from __future__ import annotations

import copy
import math
from typing import List, Optional

import numpy as np

from .._core import _common, _kalman_glue
from .._core._c_tables import KalmanStateIndex
from .._core._kalman_glue import KalmanBatch, KalmanResult, KalmanSensors, KalmanStatus

from ._checkpoint import Checkpointable
from ._diagnostics import channels_property, state_property
from ._settings import KeywordSettings

f32 = np.float32
_NAN = f32("nan")
_ZERO = f32(0)
N_STATES = 5
#: Indices of x and P (the C's FusionAltitudeKalmanState), as plain ints: h m, v m/s, ob m, og m, b m/s².
HEIGHT, VELOCITY, BARO_OFFSET, GPS_OFFSET, ACCEL_BIAS = (int(index) for index in KalmanStateIndex)
#: FUSION_ALTITUDE_KALMAN_RESTART_VELOCITY_SIGMA, m/s.
RESTART_VELOCITY_SIGMA = f32(10)
MAX_SATELLITES = 64

#: FusionAltitudeKalmanInverseSqrt: 1/sqrt(n) rounded to float32, n = 0..64 (n = 0 → 1).
_INVERSE_SQRT = [f32(1)] + [f32(1 / math.sqrt(n)) for n in range(1, MAX_SATELLITES + 1)]


def _is_finite(x: np.float32) -> bool:
    return bool(np.isfinite(x))


def _is_nan(x: np.float32) -> bool:
    return bool(np.isnan(x))


# -- settings -----------------------------------------------------------------

class KalmanSettings(KeywordSettings):
    """Settings of the Kalman filter, in physical units (float32).

    Keyword arguments only; the defaults are for a multirotor.

    Parameters
    ----------
    accel_noise : 0.035 m/s²/√Hz
        Accelerometer white-noise density N_a, vibration included.
    accel_bias_random_walk : 0.003 m/s³/√Hz
        Accelerometer bias random walk N_b.
    accel_bias_initial_sigma : 0.2 m/s²
        Initial bias uncertainty.
    estimate_accel_bias : True
        False holds the bias state at 0.
    baro_noise : 0.5 m
        Baro 1σ per sample (> 0).
    baro_offset_random_walk : 0.05 m/√s
        Baro offset drift N_ob (weather, temperature).
    range_noise : 0.05 m
        Rangefinder 1σ per sample (> 0).
    range_min, range_max : 0.1 m, 8.0 m
        Readings outside are "no echo" (not fused).
    gps_noise_base, gps_noise_satellite : 1.0 m, 1.0 m
        GPS σ = base + satellite/√n for n satellites.
    gps_min_satellites : 4
        Fewer satellites: GPS not fused.
    gps_offset_random_walk : 0.1 m/√s
        GPS altitude wander N_og.
    gate : 5.0 σ
        A sample is rejected if y²/S > gate².
    rejection_timeout : 1.0 s
        A sensor rejected for longer is reset (offset; rangefinder: ground).
    ground_effect_noise_scale : 3.0
        Baro σ multiplier with the ground-effect flag (>= 1).
    ground_effect_dead_zone : 0.5 m
        Negative baro innovations up to this are ignored in ground effect.
    initial_height_sigma, initial_velocity_sigma : 0.1 m, 1.0 m/s
        Initial uncertainty of "on the ground, at rest".
    gap_period : 0.5 s
        An update whose dt exceeds this is a gap, not integrated.
    baro_timeout, range_timeout, gps_timeout : 1.5 s, 0.5 s, 2.0 s
        A sensor with no usable sample for longer is timed out (``baro_timed_out`` …, counted in
        ``timeout_counts``); the filter carries on with the others (> 0).
    """

    __slots__ = ()
    _DISTINCT = "gps_min_satellites"

    def __init__(self, **kwargs) -> None:
        self._keep_checked(_kalman_glue.convert_kalman_settings(kwargs), _settings_check,
                           _kalman_glue.raise_kalman_settings_error)

    def replace(self, **changes) -> "KalmanSettings":
        """A copy with some settings changed."""
        return type(self)(**{**self._values, **changes})


#: FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING: squared it stays far inside float32.
MAXIMUM_SETTING = f32(_kalman_glue.KALMAN_MAXIMUM_SETTING)


def _settings_check(values: dict) -> KalmanStatus:
    """FusionAltitudeKalmanSettingsCheck itself where the binding registered it (``_kalman_glue``), else its twin
    :func:`_check`."""
    c_function = _kalman_glue.C_SETTINGS_FUNCTIONS.get("check")
    return _check(values) if c_function is None else KalmanStatus(c_function(values))


def _check(values: dict) -> KalmanStatus:
    """FusionAltitudeKalmanSettingsCheck."""
    v = {name: (f32(value) if kind == "f" else value) for (name, _, kind, _, _), value in
         zip(_kalman_glue.KALMAN_SETTINGS, values.values())}

    def non_negative(x):  # in [0, MAXIMUM_SETTING]
        return _is_finite(x) and x >= 0 and x <= MAXIMUM_SETTING

    def positive(x):  # in (0, MAXIMUM_SETTING]
        return _is_finite(x) and x > 0 and x <= MAXIMUM_SETTING

    if not (non_negative(v["accel_noise"]) and non_negative(v["accel_bias_random_walk"])
            and non_negative(v["accel_bias_initial_sigma"]) and positive(v["baro_noise"])
            and non_negative(v["baro_offset_random_walk"]) and positive(v["range_noise"])
            and non_negative(v["gps_offset_random_walk"]) and non_negative(v["initial_height_sigma"])
            and non_negative(v["initial_velocity_sigma"])):
        return KalmanStatus.INVALID_NOISE
    if not (non_negative(v["range_min"]) and positive(v["range_max"]) and v["range_max"] > v["range_min"]):
        return KalmanStatus.INVALID_RANGE
    if not (non_negative(v["gps_noise_base"]) and non_negative(v["gps_noise_satellite"])
            and v["gps_noise_base"] + v["gps_noise_satellite"] > 0) or v["gps_min_satellites"] < 0:
        return KalmanStatus.INVALID_GPS
    if not (positive(v["gate"]) and non_negative(v["rejection_timeout"])):
        return KalmanStatus.INVALID_GATE
    if not (positive(v["ground_effect_noise_scale"]) and v["ground_effect_noise_scale"] >= 1
            and non_negative(v["ground_effect_dead_zone"])
            and v["baro_noise"] * v["ground_effect_noise_scale"] <= MAXIMUM_SETTING):
        return KalmanStatus.INVALID_GROUND_EFFECT
    if not v["gap_period"] > 0:
        return KalmanStatus.INVALID_GAP_PERIOD
    if not (positive(v["baro_timeout"]) and positive(v["range_timeout"]) and positive(v["gps_timeout"])):
        return KalmanStatus.INVALID_TIMEOUT
    return KalmanStatus.OK


class _Settings32:
    """The settings as float32 scalars, for the arithmetic."""

    __slots__ = tuple(_kalman_glue.KALMAN_SETTINGS_NAMES)

    def __init__(self, settings: KalmanSettings) -> None:
        for name, _, kind, _, _ in _kalman_glue.KALMAN_SETTINGS:
            value = settings._values[name]
            setattr(self, name, f32(value) if kind == "f" else value)


# -- estimator ------------------------------------------------------------------

class _Sensor:
    """FusionAltitudeKalmanSensor."""

    __slots__ = ("innovation", "innovation_variance", "nis", "rejecting_for", "since_sample", "rejections", "resets",
                 "timeouts", "result", "rejecting", "sampled", "timed_out")

    def __init__(self) -> None:
        self.innovation = self.innovation_variance = self.nis = _NAN
        self.rejecting_for = self.since_sample = _ZERO
        self.rejections = self.resets = self.timeouts = 0
        self.result = KalmanResult.NO_SAMPLE
        self.rejecting = self.sampled = self.timed_out = False

    def no_sample(self, result: KalmanResult) -> None:
        """FusionAltitudeKalmanNoSample."""
        self.innovation = _NAN
        self.innovation_variance = _NAN
        self.nis = _NAN
        self.result = result

    def silent(self, result: KalmanResult, timeout: np.float32) -> None:
        """FusionAltitudeKalmanSilent: no usable sample; timed out (counted once) after ``timeout`` s of silence."""
        self.no_sample(result)
        if self.sampled and self.since_sample > timeout and not self.timed_out:
            self.timed_out = True
            self.timeouts = (self.timeouts + 1) & 0xFFFFFFFF  # uint32_t

    def as_tuple(self) -> tuple:
        # the C struct's fields: nis is not stored there (FusionAltitudeKalmanGetNis computes y²/S)
        return (float(self.innovation), float(self.innovation_variance), float(self.rejecting_for),
                float(self.since_sample), self.rejections, self.resets, self.timeouts, int(self.result),
                self.rejecting, self.sampled, self.timed_out)

    @classmethod
    def from_tuple(cls, values: tuple) -> "_Sensor":
        sensor = cls()
        if len(values) == 8:  # a checkpoint from before the sensor timeouts (with nis, without the timeout fields)
            values = (*values[:2], values[3], 0.0, values[4], values[5], 0, values[6], values[7], False, False)
        (i, s, rf, since, sensor.rejections, sensor.resets, sensor.timeouts, result, rejecting, sampled,
         timed_out) = values
        sensor.innovation, sensor.innovation_variance, sensor.rejecting_for = f32(i), f32(s), f32(rf)
        # FusionAltitudeKalmanGetNis
        sensor.nis = _NAN if _is_nan(sensor.innovation_variance) else (sensor.innovation * sensor.innovation) / sensor.innovation_variance
        sensor.since_sample = f32(since)
        sensor.result = KalmanResult(result)
        sensor.rejecting, sensor.sampled, sensor.timed_out = bool(rejecting), bool(sampled), bool(timed_out)
        return sensor


class KalmanEstimator(Checkpointable):
    """Multi-sensor altitude Kalman filter: baro, rangefinder and GPS altitude with vertical acceleration.

    Estimates height above ground (m), baro-referenced altitude (m), vertical
    velocity (m/s, +up), the accelerometer's vertical bias (m/s², +up) and the
    baro and GPS offsets to the ground (m).

    Parameters
    ----------
    settings : KalmanSettings, optional
        The defaults if omitted.

    Notes
    -----
    Starts on the ground at rest with unknown baro and GPS offsets; each
    sensor's first sample sets its offset (no start-up phase). ``altitude``
    is h + baro_offset: what a noise-free baro would read, comparable to
    :class:`AltitudeEstimator`'s altitude. Copies and pickles carry the full
    state.
    """

    __slots__ = ("_settings", "_s", "_x", "_P", "_sensors", "_since_fused", "_gap_count", "_baro_initialised",
                 "_gps_initialised")

    def __init__(self, settings: Optional[KalmanSettings] = None) -> None:
        # FusionAltitudeKalmanInitialiseWith
        self._settings = KalmanSettings() if settings is None else KalmanSettings.coerce(settings)
        s = self._s = _Settings32(self._settings)
        self._x: List[np.float32] = [_ZERO] * N_STATES
        P = self._P = [[_ZERO] * N_STATES for _ in range(N_STATES)]
        P[HEIGHT][HEIGHT] = s.initial_height_sigma * s.initial_height_sigma
        P[VELOCITY][VELOCITY] = s.initial_velocity_sigma * s.initial_velocity_sigma
        P[ACCEL_BIAS][ACCEL_BIAS] = (s.accel_bias_initial_sigma * s.accel_bias_initial_sigma if s.estimate_accel_bias
                                     else _ZERO)
        self._sensors = [_Sensor() for _ in range(3)]
        self._since_fused = _ZERO
        self._gap_count = 0
        self._baro_initialised = False
        self._gps_initialised = False

    # -- the algorithm ------------------------------------------------------------

    def _predict(self, accel: np.float32, dt: np.float32) -> None:
        """FusionAltitudeKalmanPredict."""
        P, x, s = self._P, self._x, self._s
        half_dt2 = f32(0.5) * dt * dt
        u = accel - x[ACCEL_BIAS]
        x[HEIGHT] = x[HEIGHT] + x[VELOCITY] * dt + u * half_dt2
        x[VELOCITY] = x[VELOCITY] + u * dt
        A = [P[HEIGHT][j] + dt * P[VELOCITY][j] - half_dt2 * P[ACCEL_BIAS][j] for j in range(N_STATES)]
        Bv = [P[VELOCITY][j] - dt * P[ACCEL_BIAS][j] for j in range(N_STATES)]
        q = s.accel_noise * s.accel_noise
        qvv = q * dt
        qhv = qvv * (f32(0.5) * dt)
        qhh = qhv * (f32(0.5) * dt)
        phh = A[HEIGHT] + dt * A[VELOCITY] - half_dt2 * A[ACCEL_BIAS] + qhh
        phv = A[VELOCITY] - dt * A[ACCEL_BIAS] + qhv
        pvv = Bv[VELOCITY] - dt * Bv[ACCEL_BIAS] + qvv
        P[HEIGHT][HEIGHT] = phh
        P[HEIGHT][VELOCITY] = P[VELOCITY][HEIGHT] = phv
        P[VELOCITY][VELOCITY] = pvv
        for j in range(2, N_STATES):
            P[HEIGHT][j] = P[j][HEIGHT] = A[j]
            P[VELOCITY][j] = P[j][VELOCITY] = Bv[j]
        self._random_walks(dt)
        for sensor in self._sensors:
            if sensor.rejecting:
                sensor.rejecting_for += dt
            sensor.since_sample += dt
        self._since_fused += dt

    def _random_walks(self, dt: np.float32) -> None:
        """FusionAltitudeKalmanRandomWalks: offsets once they exist, the bias if estimated."""
        P, s = self._P, self._s
        if self._baro_initialised:
            P[BARO_OFFSET][BARO_OFFSET] += (s.baro_offset_random_walk * s.baro_offset_random_walk) * dt
        if self._gps_initialised:
            P[GPS_OFFSET][GPS_OFFSET] += (s.gps_offset_random_walk * s.gps_offset_random_walk) * dt
        if s.estimate_accel_bias:
            P[ACCEL_BIAS][ACCEL_BIAS] += (s.accel_bias_random_walk * s.accel_bias_random_walk) * dt

    def _inflate(self, T: np.float32) -> None:
        """FusionAltitudeKalmanInflate: P_hh += (V·T)², P_vv += V² for V = RESTART_VELOCITY_SIGMA."""
        height_sigma = RESTART_VELOCITY_SIGMA * T
        self._P[HEIGHT][HEIGHT] += height_sigma * height_sigma
        self._P[VELOCITY][VELOCITY] += RESTART_VELOCITY_SIGMA * RESTART_VELOCITY_SIGMA

    def _gap(self, dt: np.float32) -> None:
        """FusionAltitudeKalmanGap: x kept, P inflated, random walks over dt, streaks ended, gap counted."""
        self._inflate(dt)
        self._random_walks(dt)
        for sensor in self._sensors:
            sensor.rejecting = False
            sensor.rejecting_for = _ZERO
        self._since_fused += dt
        self._gap_count = (self._gap_count + 1) & 0xFFFFFFFF

    def _fuse(self, c: List[np.float32], S: np.float32, y: np.float32) -> None:
        """FusionAltitudeKalmanFuse: x += K·y, P = P − K·cᵀ − c·Kᵀ + S·K·Kᵀ."""
        P, x = self._P, self._x
        inverse_s = f32(1) / S
        K = [ci * inverse_s for ci in c]
        sK = [S * ki for ki in K]
        for i in range(N_STATES):
            x[i] += K[i] * y
        for i in range(N_STATES):
            for j in range(i, N_STATES):
                P[i][j] = P[j][i] = P[i][j] - K[i] * c[j] - c[i] * K[j] + sK[i] * K[j]

    def _set_offset(self, o: int, z: np.float32, R: np.float32) -> None:
        """FusionAltitudeKalmanSetOffset: o = z − h, P_oo = P_hh + R, P_oj = −P_hj."""
        P, x = self._P, self._x
        x[o] = z - x[HEIGHT]
        for j in range(N_STATES):
            if j != o:
                P[o][j] = P[j][o] = -P[HEIGHT][j]
        P[o][o] = P[HEIGHT][HEIGHT] + R

    def _reset_ground(self, z: np.float32, R: np.float32) -> None:
        """FusionAltitudeKalmanResetGround: h = z, offsets absorb the difference."""
        P, x = self._P, self._x
        m = [False, False, self._baro_initialised, self._gps_initialised, False]
        d = z - x[HEIGHT]
        x[HEIGHT] = z
        for i in (BARO_OFFSET, GPS_OFFSET):
            if m[i]:
                x[i] = x[i] - d
        ph = list(P[HEIGHT])
        for i in range(HEIGHT + 1, N_STATES):
            for j in range(i, N_STATES):
                value = P[i][j]
                if m[i]:
                    value = value + ph[j]
                if m[j]:
                    value = value + ph[i]
                if m[i] and m[j]:
                    value = value + ph[HEIGHT] + R
                P[i][j] = P[j][i] = value
        P[HEIGHT][HEIGHT] = R
        for j in range(HEIGHT + 1, N_STATES):
            P[HEIGHT][j] = P[j][HEIGHT] = -R if m[j] else _ZERO

    def _process(self, sensor: _Sensor, o: int, z: np.float32, y: np.float32, R: np.float32) -> None:
        """FusionAltitudeKalmanProcess: gate, then fuse, reject or reset."""
        P = self._P
        c = [P[i][HEIGHT] if o < 0 else P[i][HEIGHT] + P[i][o] for i in range(N_STATES)]
        S = (c[HEIGHT] if o < 0 else c[HEIGHT] + c[o]) + R
        nis = (y * y) / S
        sensor.innovation, sensor.innovation_variance, sensor.nis = y, S, nis
        gate = self._s.gate
        if not nis > gate * gate:
            self._fuse(c, S, y)
            self._since_fused = _ZERO
            sensor.rejecting = False
            sensor.rejecting_for = _ZERO
            sensor.result = KalmanResult.FUSED
            return
        sensor.rejections = (sensor.rejections + 1) & 0xFFFFFFFF  # uint32_t
        if not sensor.rejecting:
            sensor.rejecting = True
            sensor.rejecting_for = _ZERO
        if sensor.rejecting_for > self._s.rejection_timeout:
            if self._since_fused >= sensor.rejecting_for:  # nothing fused during the streak: the state is suspect
                self._inflate(sensor.rejecting_for)
                if self._s.estimate_accel_bias:
                    sigma = self._s.accel_bias_initial_sigma
                    self._P[ACCEL_BIAS][ACCEL_BIAS] += sigma * sigma
                if o >= 0:  # fused with the inflated P, not re-based (see FusionAltitudeKalmanProcess)
                    c = [P[i][HEIGHT] + P[i][o] for i in range(N_STATES)]
                    inflated_s = (c[HEIGHT] + c[o]) + R
                    sensor.innovation_variance, sensor.nis = inflated_s, (y * y) / inflated_s
                    self._fuse(c, inflated_s, y)
                    self._since_fused = _ZERO
                    sensor.resets = (sensor.resets + 1) & 0xFFFFFFFF
                    sensor.rejecting = False
                    sensor.rejecting_for = _ZERO
                    sensor.result = KalmanResult.RESET
                    return
            if o < 0:
                self._reset_ground(z, R)
            else:
                self._set_offset(o, z, R)
            sensor.resets = (sensor.resets + 1) & 0xFFFFFFFF
            sensor.rejecting = False
            sensor.rejecting_for = _ZERO
            sensor.result = KalmanResult.RESET
            return
        sensor.result = KalmanResult.REJECTED

    def _resume(self, sensor: _Sensor, timeout: np.float32) -> None:
        """FusionAltitudeKalmanResume: a usable sample ends the sensor's silence; after a timeout with nothing fused
        within the last ``timeout`` s, h and v are inflated over the silence (b by its initial variance) first."""
        if sensor.timed_out and self._since_fused > timeout:  # nothing corrected h for the whole silence
            self._inflate(sensor.since_sample)
            if self._s.estimate_accel_bias:
                sigma = self._s.accel_bias_initial_sigma
                self._P[ACCEL_BIAS][ACCEL_BIAS] += sigma * sigma
        sensor.sampled, sensor.timed_out, sensor.since_sample = True, False, _ZERO

    def _gps_sigma(self, accuracy: np.float32, satellites: int) -> np.float32:
        """FusionAltitudeKalmanGpsSigma."""
        s = self._s
        if not _is_nan(accuracy):
            return accuracy
        n = s.gps_min_satellites if satellites < 0 else satellites
        inverse_sqrt = f32(1) if n < 1 else _INVERSE_SQRT[min(n, MAX_SATELLITES)]
        return s.gps_noise_base + s.gps_noise_satellite * inverse_sqrt

    def _update(self, a, dt, baro, rng, gps, accuracy, satellites: int, ground_effect: bool) -> KalmanStatus:
        """FusionAltitudeKalmanUpdate (all float arguments np.float32)."""
        if not _is_finite(a):
            return KalmanStatus.INVALID_ACCEL
        if not _is_finite(dt) or not dt > 0:
            return KalmanStatus.INVALID_DT
        baro_present = not _is_nan(baro)
        if baro_present and not _is_finite(baro):
            return KalmanStatus.INVALID_BARO_ALTITUDE
        gps_present = not _is_nan(gps)
        if gps_present and not _is_finite(gps):
            return KalmanStatus.INVALID_GPS_ALTITUDE
        if gps_present and not _is_nan(accuracy) and not (_is_finite(accuracy) and accuracy > 0):
            return KalmanStatus.INVALID_GPS_ACCURACY
        if dt > self._s.gap_period:
            self._gap(dt)
        else:
            self._predict(a, dt)
        self._process_baro(baro, baro_present, ground_effect)
        self._process_range(rng)
        self._process_gps(gps, gps_present, accuracy, satellites)
        return KalmanStatus.OK

    def _process_baro(self, baro: np.float32, baro_present: bool, ground_effect: bool) -> None:
        """FusionAltitudeKalmanProcessBaro: z = h + ob (m), R = baro_noise² (m², times ground_effect_noise_scale²
        in ground effect, where a negative innovation y is min(y + ground_effect_dead_zone, 0)); the first sample
        sets ob."""
        s, x, sensor = self._s, self._x, self._sensors[0]
        if not baro_present:
            sensor.silent(KalmanResult.NO_SAMPLE, s.baro_timeout)
            return
        sigma = s.baro_noise * s.ground_effect_noise_scale if ground_effect else s.baro_noise
        R = sigma * sigma
        self._resume(sensor, s.baro_timeout)
        if not self._baro_initialised:
            self._first_offset_sample(sensor, BARO_OFFSET, baro, R)
            self._baro_initialised = True
            return
        y = baro - (x[HEIGHT] + x[BARO_OFFSET])
        if ground_effect and y < 0:
            shifted = y + s.ground_effect_dead_zone
            y = shifted if shifted < 0 else _ZERO
        self._process(sensor, BARO_OFFSET, baro, y, R)

    def _process_range(self, rng: np.float32) -> None:
        """FusionAltitudeKalmanProcessRange: z = h (m); NaN or outside [range_min, range_max] (m) not fused;
        R = range_noise² (m²)."""
        s, sensor = self._s, self._sensors[1]
        if _is_nan(rng):
            sensor.silent(KalmanResult.NO_SAMPLE, s.range_timeout)
        elif not rng >= s.range_min or not rng <= s.range_max:
            sensor.silent(KalmanResult.UNUSABLE, s.range_timeout)
        else:
            R = s.range_noise * s.range_noise
            self._resume(sensor, s.range_timeout)
            self._process(sensor, -1, rng, rng - self._x[HEIGHT], R)

    def _process_gps(self, gps: np.float32, gps_present: bool, accuracy: np.float32, satellites: int) -> None:
        """FusionAltitudeKalmanProcessGps: z = h + og (m); fewer than gps_min_satellites (when known) not fused;
        R = sigma² (m², :meth:`_gps_sigma`); the first sample sets og."""
        s, x, sensor = self._s, self._x, self._sensors[2]
        if not gps_present:
            sensor.silent(KalmanResult.NO_SAMPLE, s.gps_timeout)
        elif 0 <= satellites < s.gps_min_satellites:
            sensor.silent(KalmanResult.UNUSABLE, s.gps_timeout)
        else:
            sigma = self._gps_sigma(accuracy, satellites)
            R = sigma * sigma
            self._resume(sensor, s.gps_timeout)
            if not self._gps_initialised:
                self._first_offset_sample(sensor, GPS_OFFSET, gps, R)
                self._gps_initialised = True
            else:
                self._process(sensor, GPS_OFFSET, gps, gps - (x[HEIGHT] + x[GPS_OFFSET]), R)

    def _first_offset_sample(self, sensor: _Sensor, o: int, z: np.float32, R: np.float32) -> None:
        """The first sample z (m, variance R m²) of a sensor that reads h + x[o] sets its offset
        (FusionAltitudeKalmanSetOffset); nothing is fused (result INITIALISED)."""
        self._set_offset(o, z, R)
        sensor.no_sample(KalmanResult.INITIALISED)

    # -- public API -----------------------------------------------------------------

    @_common.argument_order(_kalman_glue.KALMAN_LEGACY_ORDER)
    def update(self, accel: float, baro_altitude: float, dt: float, *, range_distance: float = math.nan,
               gps_altitude: float = math.nan, gps_satellites: Optional[int] = None,
               gps_vertical_accuracy: Optional[float] = None, ground_effect: bool = False) -> None:
        values = {"accel": accel, "dt": dt, "baro_altitude": baro_altitude, "gps_altitude": gps_altitude,
                  "gps_vertical_accuracy": gps_vertical_accuracy}
        with np.errstate(over="ignore"):
            a = f32(_common.as_float(accel, "accel"))
            t = f32(_common.as_float(dt, "dt"))
            z_baro = f32(_common.as_float(baro_altitude, "baro_altitude"))
            z_range = f32(_common.as_float(range_distance, "range_distance"))
            z_gps = f32(_common.as_float(gps_altitude, "gps_altitude"))
            accuracy = _NAN if gps_vertical_accuracy is None else f32(
                _common.as_float(gps_vertical_accuracy, "gps_vertical_accuracy"))
        satellites = _kalman_glue.kalman_satellites(gps_satellites)
        status = self._update(a, t, z_baro, z_range, z_gps, accuracy, satellites, bool(ground_effect))
        if status != KalmanStatus.OK:
            _kalman_glue.raise_kalman_update_error(status, values)

    @_common.argument_order(_kalman_glue.KALMAN_LEGACY_ORDER + ("out",))
    def update_batch(self, accel, baro_altitude, dt, *, range_distance=None, gps_altitude=None,
                     gps_satellites=None, gps_vertical_accuracy=None, ground_effect=None, out=None) -> KalmanBatch:
        """Process arrays of steps, continuing from the current state.

        Each argument is an array with one entry per step, a scalar for all
        steps, or None (no samples of that sensor; satellites unknown; no
        ground effect). NaN means "no sample this step". Equal, bit for bit,
        to calling :meth:`update` per step; on a bad step nothing is applied
        and ValueError names the argument and its first bad index.
        """
        n, inputs, steps, result = _kalman_glue.prepare_kalman_batch(
            accel, dt, baro_altitude, range_distance, gps_altitude, gps_satellites, gps_vertical_accuracy,
            ground_effect, out)
        trial = copy.copy(self)
        names = ("accel", "dt", "baro_altitude", "range_distance", "gps_altitude", "gps_vertical_accuracy",
                 "gps_satellites", "ground_effect")
        for i in range(n):
            a, t, zb, zr, zg, acc, sats, ge = (inputs[name][i * steps[name]] for name in names)
            status = trial._update(a, t, zb, zr, zg, acc, int(sats), bool(ge))
            if status != KalmanStatus.OK:
                values = {"accel": float(a), "dt": float(t), "baro_altitude": float(zb), "gps_altitude": float(zg),
                          "gps_vertical_accuracy": float(acc)}
                _kalman_glue.raise_kalman_update_error(status, values, i, {k: bool(v) for k, v in steps.items()})
            trial._record(result, i)
        self._set_state(trial._get_state())
        return result if out is None else out  # out=: the caller's object itself

    def _record(self, result: KalmanBatch, i: int) -> None:
        x, P = self._x, self._P
        result.height_above_ground[i] = x[HEIGHT]
        result.altitude[i] = x[HEIGHT] + x[BARO_OFFSET]
        result.vertical_velocity[i] = x[VELOCITY]
        result.accel_bias[i] = x[ACCEL_BIAS]
        result.baro_offset[i] = x[BARO_OFFSET]
        result.gps_offset[i] = x[GPS_OFFSET]
        for j in range(N_STATES):
            result.covariance_diagonal[i, j] = P[j][j]
        for k, sensor in enumerate(self._sensors):
            result.innovation[i, k] = sensor.innovation
            result.nis[i, k] = sensor.nis
            result.result[i, k] = sensor.result

    height_above_ground = state_property("_x", "Height above ground h, m.", index=HEIGHT)

    @property
    def altitude(self) -> float:
        """Baro-referenced altitude h + baro_offset, m (equals h before the first baro sample)."""
        return float(self._x[HEIGHT] + self._x[BARO_OFFSET])

    @property
    def altitude_variance(self) -> float:
        """Variance of the altitude, m²: P_hh + 2·P_h,ob + P_ob,ob."""
        P = self._P
        return float(P[HEIGHT][HEIGHT] + f32(2) * P[HEIGHT][BARO_OFFSET] + P[BARO_OFFSET][BARO_OFFSET])

    vertical_velocity = state_property("_x", "Vertical velocity v, m/s, +up.", index=VELOCITY)
    accel_bias = state_property("_x", "Accelerometer bias b, m/s², +up (subtracted from the input).", index=ACCEL_BIAS)
    baro_offset = state_property("_x", "Baro offset (baro reads h + offset), m; 0 before the first baro sample.",
                                 index=BARO_OFFSET)
    gps_offset = state_property("_x", "GPS offset (GPS reads h + offset), m; 0 before the first usable GPS sample.",
                                index=GPS_OFFSET)

    @property
    def state(self) -> np.ndarray:
        """State vector (h, v, baro_offset, gps_offset, accel_bias), float32 copy."""
        return np.array(self._x, dtype=np.float32)

    @property
    def covariance(self) -> np.ndarray:
        """Covariance P (5×5, order of :attr:`state`), float32 copy."""
        return np.array(self._P, dtype=np.float32)

    innovations = channels_property("_sensors", "innovation", KalmanSensors,
                                    "Latest innovation y = z − H·x per sensor, m (NaN: no tested sample).")
    innovation_variances = channels_property("_sensors", "innovation_variance", KalmanSensors,
                                             "Latest innovation variance S per sensor, m² (NaN: no tested sample).")
    nis = channels_property("_sensors", "nis", KalmanSensors,
                            "Latest normalized innovation squared y²/S per sensor (NaN: no tested sample).")
    rejections = channels_property("_sensors", "rejections", KalmanSensors,
                                   "Samples rejected by the gate so far, per sensor.", int)
    resets = channels_property("_sensors", "resets", KalmanSensors,
                               "Resets after rejection streaks longer than the timeout, per sensor.", int)
    results = channels_property("_sensors", "result", KalmanSensors,
                                "What the latest update did with each sensor (:class:`KalmanResult`).", KalmanResult)
    timeout_counts = channels_property(
        "_sensors", "timeouts", KalmanSensors,
        "Silences longer than the sensor's timeout so far, per sensor (each counted once).", int)

    @property
    def baro_timed_out(self) -> bool:
        """Whether the baro is timed out: no sample for longer than ``baro_timeout`` s (FusionAltitudeKalmanIsBaroTimedOut)."""
        return self._sensors[0].timed_out

    @property
    def range_timed_out(self) -> bool:
        """Whether the rangefinder is timed out: no usable reading for longer than ``range_timeout`` s."""
        return self._sensors[1].timed_out

    @property
    def gps_timed_out(self) -> bool:
        """Whether the GPS is timed out: no usable fix for longer than ``gps_timeout`` s."""
        return self._sensors[2].timed_out

    baro_initialised = state_property(
        "_baro_initialised", "Whether the baro offset is set (first baro sample seen).", bool)
    gps_initialised = state_property(
        "_gps_initialised", "Whether the GPS offset is set (first usable GPS sample seen).", bool)

    @property
    def settings(self) -> KalmanSettings:
        """The settings; assign new :class:`KalmanSettings` to retune, keeping the state."""
        return self._settings

    @settings.setter
    def settings(self, settings: KalmanSettings) -> None:
        # FusionAltitudeKalmanSetSettings
        new = KalmanSettings.coerce(settings)
        s = _Settings32(new)
        if s.estimate_accel_bias != self._s.estimate_accel_bias:
            self._x[ACCEL_BIAS] = _ZERO
            for i in range(N_STATES):
                self._P[i][ACCEL_BIAS] = self._P[ACCEL_BIAS][i] = _ZERO
            if s.estimate_accel_bias:
                self._P[ACCEL_BIAS][ACCEL_BIAS] = s.accel_bias_initial_sigma * s.accel_bias_initial_sigma
        self._settings, self._s = new, s

    gap_count = state_property(
        "_gap_count", "Number of gaps so far: updates whose dt exceeded ``settings.gap_period``.", int)

    def _get_state(self) -> tuple:
        return (self._settings.as_dict(), [float(v) for v in self._x], [float(v) for row in self._P for v in row],
                [s.as_tuple() for s in self._sensors], float(self._since_fused), self._gap_count,
                self._baro_initialised, self._gps_initialised)

    def _set_state(self, state: tuple) -> None:
        # the C struct's order; a 6-tuple is a checkpoint from before the gap fields
        if len(state) == 6:
            settings, x, P, sensors, baro_initialised, gps_initialised = state
            since_fused, gap_count = _ZERO, 0
        else:
            settings, x, P, sensors, since_fused, gap_count, baro_initialised, gps_initialised = state
        self._gap_count = int(gap_count)
        self._since_fused = f32(since_fused)
        self._settings = KalmanSettings(**settings)
        self._s = _Settings32(self._settings)
        self._x = [f32(v) for v in x]
        self._P = [[f32(P[i * N_STATES + j]) for j in range(N_STATES)] for i in range(N_STATES)]
        self._sensors = [_Sensor.from_tuple(tuple(s)) for s in sensors]
        self._baro_initialised = bool(baro_initialised)
        self._gps_initialised = bool(gps_initialised)

    def __repr__(self) -> str:
        return (f"KalmanEstimator(height_above_ground={self.height_above_ground!r}, altitude={self.altitude!r}, "
                f"vertical_velocity={self.vertical_velocity!r}, accel_bias={self.accel_bias!r})")


_common.share_docstrings(KalmanEstimator, _kalman_glue.KalmanContract)
