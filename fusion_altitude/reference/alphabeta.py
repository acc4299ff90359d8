"""Quality-weighted alpha-beta multi-sensor fusion (seed write-up 003), in plain Python.

Written to be read next to ``csrc/fusion_altitude_alphabeta.h`` (whose file
comment has the equations and why alpha = 2(2Q−1)/(Q(Q+1)) rather than the
write-up's printed formula): float32 arithmetic through numpy scalars in the
same order as the C, so results agree bit for bit.

Each sensor channel (IMU, baro, lidar, sonar, GPS) has an alpha-beta filter
(altitude x m, velocity v m/s, time since its latest sample T s, quality Q);
the fused output is their mean weighted by Q · confidence.
"""

from __future__ import annotations

import copy
import math
from typing import Optional

import numpy as np

from .._core import _c_tables, _common, _alphabeta_glue
from .._core._alphabeta_glue import (ALPHABETA_MAX_QUALITY, ALPHABETA_SENSORS, AlphaBetaBatch, AlphaBetaSensors,
                               AlphaBetaSensorSettings, AlphaBetaStatus)

from ._checkpoint import Checkpointable
from ._diagnostics import channels_property, state_property
from ._settings import KeywordSettings

f32 = np.float32
_NAN = f32("nan")
_HALF = f32(0.5)
_ONE = f32(1)
_TWO = f32(2)
_SIX = f32(6)
_IMU = 0
_MAX_CONFIDENCE = _c_tables.FUSION_ALTITUDE_ALPHABETA_MAX_CONFIDENCE  # every weight Q · confidence finite
_ZERO = f32(0)
_MAX_INTERVAL_RATIO = f32(4)  # FUSION_ALTITUDE_ALPHABETA_MAX_INTERVAL_RATIO


def gains(quality: int):
    """FusionAltitudeAlphaBetaGains: alpha = 2(2Q−1)/(Q(Q+1)), beta = 6/(Q(Q+1)), float32."""
    q = f32(quality)
    denominator = q * (q + _ONE)
    return (_TWO * (_TWO * q - _ONE)) / denominator, _SIX / denominator


def _sensor_status(s: AlphaBetaSensorSettings) -> AlphaBetaStatus:
    """FusionAltitudeAlphaBetaSensorSettingsCheck."""
    if not (math.isfinite(s.threshold) and s.threshold > 0):
        return AlphaBetaStatus.INVALID_THRESHOLD
    if s.quality_min < 2 or s.quality_max < s.quality_min or s.quality_max > ALPHABETA_MAX_QUALITY:
        return AlphaBetaStatus.INVALID_QUALITY
    if not (math.isfinite(s.confidence) and 0 <= s.confidence <= _MAX_CONFIDENCE):
        return AlphaBetaStatus.INVALID_CONFIDENCE
    if not s.altitude_min < s.altitude_max:
        return AlphaBetaStatus.INVALID_ALTITUDE_BAND
    if not s.gap_max > 0:
        return AlphaBetaStatus.INVALID_GAP_MAX
    if not (math.isfinite(s.timeout) and s.timeout > 0):
        return AlphaBetaStatus.INVALID_TIMEOUT
    return AlphaBetaStatus.OK


def _gap_period_status(gap_period: float) -> AlphaBetaStatus:
    """The gap-period part of FusionAltitudeAlphaBetaSettingsCheck: > 0 (NaN fails, inf passes)."""
    return AlphaBetaStatus.OK if f32(gap_period) > 0 else AlphaBetaStatus.INVALID_GAP_PERIOD


class AlphaBetaSettings(KeywordSettings):
    """One :class:`AlphaBetaSensorSettings` per sensor; see :class:`fusion_altitude.AlphaBetaSettings`."""

    __slots__ = ()
    _DISTINCT = "sonar"

    def __init__(self, **sensors) -> None:
        values = _alphabeta_glue.convert_alphabeta_settings(sensors)
        for sensor in ALPHABETA_SENSORS:  # FusionAltitudeAlphaBetaSettingsCheck: first failure in sensor order
            status = _alphabeta_glue.C_SETTINGS_FUNCTIONS.get("check_sensor", _sensor_status)(values[sensor])
            if status != AlphaBetaStatus.OK:
                _alphabeta_glue.raise_alphabeta_settings_error(status, values)
        status = _alphabeta_glue.C_SETTINGS_FUNCTIONS.get("check_gap_period", _gap_period_status)(values["gap_period"])
        if status != AlphaBetaStatus.OK:
            _alphabeta_glue.raise_alphabeta_settings_error(status, values)
        self._values = values

    def replace(self, **sensors) -> "AlphaBetaSettings":
        """A copy with some sensors' fields changed."""
        unknown = set(sensors) - set(ALPHABETA_SENSORS) - {"gap_period"}
        if unknown:
            raise TypeError(f"unknown alpha-beta sensor(s): {', '.join(sorted(unknown))}")
        merged = {}
        for name, value in self._values.items():
            change = sensors.get(name)
            if change is None:
                merged[name] = value
            elif name == "gap_period":
                merged[name] = change
            elif isinstance(change, AlphaBetaSensorSettings):
                merged[name] = change
            else:
                merged[name] = value._replace(**change)
        return AlphaBetaSettings(**merged)


def check_inputs(accel: np.float32, dt: np.float32, z: tuple) -> AlphaBetaStatus:
    """FusionAltitudeAlphaBetaCheckInputs: no infinities; dt finite and > 0. z = (baro, lidar, sonar, gps)."""
    if np.isinf(accel):
        return AlphaBetaStatus.INVALID_ACCEL
    if not np.isfinite(dt) or not dt > 0:
        return AlphaBetaStatus.INVALID_DT
    for status, value in zip((AlphaBetaStatus.INVALID_BARO_ALTITUDE, AlphaBetaStatus.INVALID_LIDAR_ALTITUDE,
                              AlphaBetaStatus.INVALID_SONAR_ALTITUDE, AlphaBetaStatus.INVALID_GPS_ALTITUDE), z):
        if np.isinf(value):
            return status
    return AlphaBetaStatus.OK


class _Filter:
    """FusionAltitudeAlphaBetaFilter: one sensor's alpha-beta filter."""

    __slots__ = ("x", "v", "since", "interval", "gap", "weight", "quality", "timeouts", "started", "timed_out")

    def __init__(self, quality: int) -> None:
        self.x = self.v = self.since = self.interval = self.gap = self.weight = f32(0)
        self.quality = quality
        self.timeouts = 0
        self.started = self.timed_out = False

    def state(self) -> tuple:
        return (float(self.x), float(self.v), float(self.since), float(self.interval), float(self.gap),
                float(self.weight), self.quality, self.timeouts, self.started, self.timed_out)


class AlphaBetaFusion(Checkpointable):
    """Quality-weighted alpha-beta fusion of IMU-integrated altitude, baro, lidar, sonar and GPS.

    Each sensor runs an alpha-beta filter of depth Q (its quality), which
    rises by one while the sensor agrees with the fused prediction within its
    threshold and falls by one otherwise; alpha = 2(2Q−1)/(Q(Q+1)), beta =
    6/(Q(Q+1)). The output is the mean of the filters weighted by
    Q · confidence, a sensor's weight zeroed outside its altitude band, while
    its latest sample is further than its gap maximum from the prediction, or
    after its timeout.

    Parameters
    ----------
    settings : AlphaBetaSettings, optional
        Default: the write-up's tables.

    Notes
    -----
    NaN means "no sample this step" for every input, accel (the IMU channel)
    included. No offsets are estimated: every sensor is taken to measure the
    same altitude. Copies and pickles carry the full state.
    """

    __slots__ = ("_settings", "_filters", "_h", "_v", "_total", "_coasting", "_gap_time", "_gap_count", "_started")

    def __init__(self, settings: Optional[AlphaBetaSettings] = None) -> None:
        # FusionAltitudeAlphaBetaInitialise / InitialiseWith
        self._settings = AlphaBetaSettings() if settings is None else AlphaBetaSettings.coerce(settings)
        self._clear()

    def _clear(self) -> None:
        self._filters = [_Filter(self._settings._values[name].quality_min) for name in ALPHABETA_SENSORS]
        self._h = self._v = self._total = self._coasting = self._gap_time = f32(0)
        self._gap_count = 0
        self._started = False

    def _sensor(self, i: int) -> AlphaBetaSensorSettings:
        return self._settings._values[ALPHABETA_SENSORS[i]]

    def _start(self, accel: np.float32, z: list) -> None:
        """FusionAltitudeAlphaBetaStart: h = the Qmin·confidence-weighted mean of the samples; v = 0, or after a
        gap the mean velocity over it. Nothing changes when no non-IMU sample has weight."""
        sum_weight = f32(0)
        sum_altitude = f32(0)
        for i in range(1, 5):
            if np.isfinite(z[i]):
                s = self._sensor(i)
                w = f32(s.quality_min) * f32(s.confidence)
                sum_weight += w
                sum_altitude += w * z[i]
        if not sum_weight > 0:
            return  # nothing to start from yet
        altitude = sum_altitude / sum_weight
        velocity = (altitude - self._h) / self._gap_time if self._gap_time > 0 else f32(0)
        self._h = altitude
        self._v = velocity
        self._total = sum_weight
        imu_sample = bool(np.isfinite(accel))
        for i, f in enumerate(self._filters):
            s = self._sensor(i)
            sampled = imu_sample if i == _IMU else bool(np.isfinite(z[i]))
            f.x = self._h if i == _IMU else z[i]
            f.v = velocity
            f.since = f32(0)
            f.interval = f32(0)
            f.gap = f.x - self._h if sampled else f32(0)
            f.quality = s.quality_min
            f.started = sampled
            f.timed_out = f.timed_out and not sampled  # a silent sensor stays timed out through the restart
            f.weight = f32(s.quality_min) * f32(s.confidence) if (sampled and i != _IMU) else f32(0)
            if not sampled:
                f.x = f32(0)
        self._coasting = f32(0)
        self._gap_time = f32(0)
        self._started = True

    def _filter_step(self, f: _Filter, s: AlphaBetaSensorSettings, z: np.float32, dt: np.float32,
                     altitude_predicted: np.float32) -> np.float32:
        """FusionAltitudeAlphaBetaFilterStep: one sensor's alpha-beta filter, quality and weight."""
        timeout = f32(s.timeout)
        if f.started:
            f.x += f.v * dt
            f.since += dt
        if np.isfinite(z):
            gap_max = f32(s.gap_max)
            was_beyond_gap = not (-gap_max <= f.gap <= gap_max)
            fresh = not f.started or f.since > timeout
            # an interval more than MAX_INTERVAL_RATIO times the previous one or less than its inverse times it: not
            # integrated (stable steps)
            irregular = f.interval > 0 and (f.since > _MAX_INTERVAL_RATIO * f.interval
                                            or _MAX_INTERVAL_RATIO * f.since < f.interval)
            f.gap = z - altitude_predicted  # the sensor's gap, held until its next sample
            f.interval = f32(0) if fresh else f.since
            if fresh or was_beyond_gap or irregular:  # first, back after silence, gap or irregular interval: restart
                f.x = z
                f.v = _ZERO if irregular else self._v  # learnt over mismatched intervals: not kept
                f.quality = s.quality_min
                f.started = True
            else:
                threshold = f32(s.threshold)
                if -threshold <= f.gap <= threshold:
                    f.quality = min(f.quality + 1, s.quality_max)
                else:
                    f.quality = max(f.quality - 1, s.quality_min)
                alpha, beta = gains(f.quality)
                residual = z - f.x
                f.x += alpha * residual
                f.v += (beta * residual) / f.since
            f.since = f32(0)
        # FusionAltitudeAlphaBetaFilterStep: timed out once a started sensor is silent for longer than its timeout,
        # counted once per silence, held until its next sample
        if np.isfinite(z):
            f.timed_out = False
        elif f.started and f.since > timeout and not f.timed_out:
            f.timed_out = True
            f.timeouts = (f.timeouts + 1) & 0xFFFFFFFF
        weight = f32(0)
        if f.started and not f.since > timeout:
            in_band = f32(s.altitude_min) <= altitude_predicted <= f32(s.altitude_max)
            gap_max = f32(s.gap_max)
            if in_band and -gap_max <= f.gap <= gap_max:
                weight = f32(f.quality) * f32(s.confidence)
        f.weight = weight
        return weight

    def _step(self, accel: np.float32, dt: np.float32, z: list) -> None:
        """FusionAltitudeAlphaBetaStep: IMU prediction, every filter, weighted mean or bounded dead reckoning."""
        imu_sample = bool(np.isfinite(accel))
        # 1. IMU prediction of the fused altitude; also the IMU channel's sample.
        altitude_predicted = self._h + self._v * dt
        velocity_predicted = self._v
        if imu_sample:
            altitude_predicted += _HALF * accel * dt * dt
            velocity_predicted += accel * dt
        z[_IMU] = altitude_predicted if imu_sample else _NAN
        # 2. Each sensor's alpha-beta filter, quality and weight.
        sum_weight = f32(0)
        sum_altitude = f32(0)
        sum_velocity = f32(0)
        referenced = False  # a baro, lidar, sonar or GPS channel has weight
        for i, f in enumerate(self._filters):
            weight = self._filter_step(f, self._sensor(i), z[i], dt, altitude_predicted)
            if weight > 0:
                sum_weight += weight
                sum_altitude += weight * f.x
                sum_velocity += weight * f.v
                referenced = referenced or i != _IMU
        # 3. Weighted mean, or dead reckoning when every weight is zero.
        if sum_weight > 0:
            self._h = sum_altitude / sum_weight
            self._v = sum_velocity / sum_weight
        else:
            self._h = altitude_predicted
            self._v = velocity_predicted
        self._total = sum_weight
        # Bounded coasting: after gap_period s without a non-IMU weight, re-acquire from the next samples.
        self._coasting = f32(0) if referenced else self._coasting + dt
        gap_period = f32(self._settings._values["gap_period"])
        stop = self._coasting > gap_period
        # ... and by the disagreement: a non-IMU channel with a current sample beyond its gap maximum ends it once
        # coasting * |g| > gap_period * gap_max (FusionAltitudeAlphaBetaStep)
        if not stop and self._coasting > 0:
            for i in range(1, len(self._filters)):
                f, s = self._filters[i], self._sensor(i)
                disagreement = -f.gap if f.gap < 0 else f.gap
                current = f.started and not f.since > f32(s.timeout)
                if current and self._coasting * disagreement > gap_period * f32(s.gap_max):
                    stop = True
                    break
        if stop:
            self._started = False

    # FusionAltitudeAlphaBetaUpdate
    def _update(self, accel: np.float32, dt: np.float32, measurements: tuple) -> AlphaBetaStatus:
        status = check_inputs(accel, dt, measurements)
        if status != AlphaBetaStatus.OK:
            return status
        z = [_NAN, *measurements]
        if self._started and dt > f32(self._settings._values["gap_period"]):  # a gap: restart from the next samples
            self._gap_count = (self._gap_count + 1) & 0xFFFFFFFF
            self._started = False
            self._gap_time = dt
        elif not self._started and self._gap_time > 0:  # still waiting for samples after a gap
            self._gap_time += dt
        if not self._started:
            self._start(accel, z)
        else:
            self._step(accel, dt, z)
        return AlphaBetaStatus.OK

    @_common.argument_order(_alphabeta_glue.ALPHABETA_INPUTS[1:])
    def update(self, accel: float, baro_altitude: float, dt: float, *, lidar_altitude: float = math.nan,
               sonar_altitude: float = math.nan, gps_altitude: float = math.nan) -> None:
        """Process one step (accel m/s² or NaN, dt s, each sensor's altitude m or NaN)."""
        names = ("baro_altitude", "lidar_altitude", "sonar_altitude", "gps_altitude")
        raw = (baro_altitude, lidar_altitude, sonar_altitude, gps_altitude)
        with np.errstate(over="ignore"):
            a = f32(_common.as_float(accel, "accel"))
            t = f32(_common.as_float(dt, "dt"))
            z = tuple(f32(_common.as_float(value, name)) for value, name in zip(raw, names))
        with np.errstate(all="ignore"):
            status = self._update(a, t, z)
        if status != AlphaBetaStatus.OK:
            _alphabeta_glue.raise_alphabeta_update_error(status, {"accel": float(a), "dt": float(t),
                                                          **{n: float(v) for n, v in zip(names, raw)}})  # type: ignore[arg-type]

    @_common.argument_order(_alphabeta_glue.ALPHABETA_INPUTS[1:] + ("out",))
    def update_batch(self, accel, baro_altitude, dt, *, lidar_altitude=None, sonar_altitude=None,
                     gps_altitude=None, out=None) -> AlphaBetaBatch:
        """Process arrays of steps; equal, bit for bit, to calling :meth:`update` for each."""
        n, inputs, steps, result = _alphabeta_glue.prepare_alphabeta_batch(accel, dt, baro_altitude, lidar_altitude,
                                                                    sonar_altitude, gps_altitude, out)
        trial = copy.copy(self)
        names = _alphabeta_glue.ALPHABETA_INPUTS
        with np.errstate(all="ignore"):
            for i in range(n):
                values = [inputs[name][i * steps[name]] for name in names]
                status = trial._update(values[0], values[1], tuple(values[2:]))
                if status != AlphaBetaStatus.OK:
                    _alphabeta_glue.raise_alphabeta_update_error(status, {name: float(v) for name, v in zip(names, values)},
                                                         i, {k: bool(s) for k, s in steps.items()})
                result.altitude[i] = trial._h
                result.vertical_velocity[i] = trial._v
                for j, f in enumerate(trial._filters):
                    result.weight[i, j] = f.weight
                    result.quality[i, j] = f.quality
        self._set_state(trial._get_state())
        return result if out is None else out  # out=: the caller's object itself

    altitude = state_property("_h", "Fused altitude h, m (0 until started).")
    vertical_velocity = state_property("_v", "Fused vertical velocity v, m/s.")
    started = state_property("_started", "Whether the fusion has started.", bool)
    total_weight = state_property("_total", "Sum of the weights of the latest step (0: dead reckoning).")
    weights = channels_property("_filters", "weight", AlphaBetaSensors, "Each sensor's weight in the latest step.")
    qualities = channels_property("_filters", "quality", AlphaBetaSensors, "Each sensor's quality Q.", int)
    filter_altitudes = channels_property("_filters", "x", AlphaBetaSensors, "Each sensor's filtered altitude x, m.")
    gaps = channels_property("_filters", "gap", AlphaBetaSensors,
                             "Each sensor's gap z − predicted fused altitude at its latest sample, m.")

    @property
    def settings(self) -> AlphaBetaSettings:
        """The settings; assign new ones to retune (qualities clamped to the new ranges)."""
        return self._settings

    @settings.setter
    def settings(self, settings: AlphaBetaSettings) -> None:
        # FusionAltitudeAlphaBetaSetSettings
        self._settings = AlphaBetaSettings.coerce(settings)
        for i, f in enumerate(self._filters):
            s = self._sensor(i)
            f.quality = min(max(f.quality, s.quality_min), s.quality_max)

    timed_out = channels_property(
        "_filters", "timed_out", AlphaBetaSensors,
        "Each sensor's timeout flag: it had samples, then none for longer than its ``timeout`` (s), until its next\n"
        "        sample (FusionAltitudeAlphaBetaIsTimedOut).", bool)
    timeout_counts = channels_property(
        "_filters", "timeouts", AlphaBetaSensors,
        "Each sensor's number of timeouts so far, each silence longer than its ``timeout`` counted once.", int)
    gap_count = state_property(
        "_gap_count", "Number of time gaps so far: updates whose dt exceeded ``settings.gap_period`` once started.",
        int)

    def _get_state(self) -> tuple:
        return (self._settings.as_dict(), tuple(f.state() for f in self._filters), float(self._h), float(self._v),
                float(self._total), float(self._coasting), float(self._gap_time), self._gap_count, self._started)

    def _set_state(self, state: tuple) -> None:
        # the C struct's order; a 6-tuple is a checkpoint from before the gap fields
        if len(state) == 6:
            values, filters, h, v, total, started = state
            coasting, gap_time, gap_count = 0.0, 0.0, 0
        else:
            values, filters, h, v, total, coasting, gap_time, gap_count, started = state
        self._settings = AlphaBetaSettings(**values)
        self._filters = []
        for row in filters:
            if len(row) == 7:  # a checkpoint from before the interval and timeout fields
                row = (*row[:3], 0.0, *row[3:6], 0, row[6], False)
            x, vi, since, interval, gap, weight, quality, timeouts, filter_started, timed_out = row
            f = _Filter(int(quality))
            f.x, f.v, f.since, f.gap, f.weight = f32(x), f32(vi), f32(since), f32(gap), f32(weight)
            f.interval = f32(interval)
            f.timeouts, f.started, f.timed_out = int(timeouts), bool(filter_started), bool(timed_out)
            self._filters.append(f)
        self._h, self._v, self._total = f32(h), f32(v), f32(total)
        self._started = bool(started)
        self._coasting, self._gap_time, self._gap_count = f32(coasting), f32(gap_time), int(gap_count)

    def __repr__(self) -> str:
        return f"AlphaBetaFusion(altitude={self._h}, vertical_velocity={self._v}, weights={tuple(self.weights)!r})"
