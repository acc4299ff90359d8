"""The two-stage complementary filter (seed write-up 001), in plain Python.

Written to be read next to ``csrc/fusion_altitude_complementary.h``: float32
arithmetic through numpy scalars in the same order as the C, so results agree
bit for bit.

State (float32): altitude h (m), vertical velocity v (m/s), low-passed accel
aLp (m/s²), low-passed baro zLp (m), the latest finite-difference baro
velocity (m/s), the time since the latest baro sample (s), the time since h
was last updated while a restart after a gap is pending (s), the gap and
baro-timeout counts, whether the reference is set and whether the baro timed out.
"""

from __future__ import annotations

import copy
from typing import Optional, Sequence

import numpy as np

from .._core import _common, _complementary_glue, _observer_glue
from .._core._complementary_glue import ComplementaryBatch, ComplementaryStatus

from ._checkpoint import Checkpointable
from ._diagnostics import BaroGapDiagnostics, settings_property, state_property
from ._settings import KeywordSettings

f32 = np.float32
_NAN = f32("nan")
_HALF = f32(0.5)
_ONE = f32(1)


def _is_time_constant(value: np.float32) -> bool:
    return bool(np.isfinite(value)) and value >= 0


def _is_coefficient(value: np.float32) -> bool:
    return bool(np.isfinite(value)) and 0 <= value <= 1


def _check(values: dict) -> ComplementaryStatus:
    """FusionAltitudeComplementarySettingsCheck."""
    if not all(_is_time_constant(f32(values[name])) for name in
               ("accel_time_constant", "baro_time_constant", "velocity_time_constant", "altitude_time_constant")):
        return ComplementaryStatus.INVALID_TIME_CONSTANT
    if not (_is_coefficient(f32(values["velocity_coefficient"])) and _is_coefficient(f32(values["altitude_coefficient"]))):
        return ComplementaryStatus.INVALID_COEFFICIENT
    if not f32(values["gap_period"]) > 0:
        return ComplementaryStatus.INVALID_GAP_PERIOD
    if not f32(values["baro_timeout"]) > 0:
        return ComplementaryStatus.INVALID_BARO_TIMEOUT
    return ComplementaryStatus.OK


def check_inputs(a: np.float32, z: np.float32, dt: np.float32) -> ComplementaryStatus:
    """FusionAltitudeComplementaryCheckInputs: a finite, z finite or NaN, dt finite and > 0."""
    if not np.isfinite(a):
        return ComplementaryStatus.INVALID_ACCEL
    if np.isinf(z):
        return ComplementaryStatus.INVALID_BARO_ALTITUDE
    if not np.isfinite(dt) or not dt > 0:
        return ComplementaryStatus.INVALID_DT
    return ComplementaryStatus.OK


class ComplementarySettings(KeywordSettings):
    """Settings of the two-stage complementary filter (float32, keyword arguments only).

    The defaults are ``FusionAltitudeComplementarySettingsDefault``'s.

    Parameters
    ----------
    accel_time_constant, baro_time_constant : 0.02 s, 0.05 s
        Low-pass time constants τA of the accelerometer and τB of the baro (>= 0; 0: none).
    per_sample_coefficients : False
        True: blend with the fixed coefficients below, per baro sample; False: from the time constants.
    velocity_coefficient, altitude_coefficient : 0.999, 0.998
        cV and cH in [0, 1], per baro sample (used with ``per_sample_coefficients``).
    velocity_time_constant, altitude_time_constant : 9.99 s, 4.99 s
        TV and TH (>= 0): cV = TV/(TV + D), cH = TH/(TH + D) for a baro period D (used otherwise).
    gap_period : 0.5 s
        An update whose dt exceeds this is a gap, not integrated.
    baro_timeout : 2.0 s
        After this long without a baro sample the filter stops dead-reckoning (+inf: never).
    """

    __slots__ = ()
    _DISTINCT = "per_sample_coefficients"

    def __init__(self, **kwargs) -> None:
        self._keep_checked(_complementary_glue.convert_complementary_settings(kwargs),
                           _complementary_glue.C_SETTINGS_FUNCTIONS.get("check", _check),  # C where built
                           _complementary_glue.raise_complementary_settings_error)

    @classmethod
    def from_coefficients(cls, velocity_coefficient=0.999, altitude_coefficient=0.998, **kwargs):
        """The write-up's fixed blend coefficients per baro sample."""
        return cls(per_sample_coefficients=True, velocity_coefficient=velocity_coefficient,
                   altitude_coefficient=altitude_coefficient, **kwargs)

    @classmethod
    def from_time_constants(cls, velocity_time_constant=9.99, altitude_time_constant=4.99, **kwargs):
        """Blend from time constants in s (the default form)."""
        return cls(velocity_time_constant=velocity_time_constant, altitude_time_constant=altitude_time_constant,
                   **kwargs)

    def replace(self, **changes) -> "ComplementarySettings":
        """A copy with some settings changed."""
        return ComplementarySettings(**{**self._values, **changes})


class ComplementaryFilter(BaroGapDiagnostics, Checkpointable):
    """The hobbyist two-stage complementary filter: baro altitude + vertical acceleration.

    Low-passes both signals, blends the integrated acceleration with a
    finite-difference baro velocity, then the predicted altitude with the baro
    altitude. It has no accelerometer-bias state: a constant bias b leaves an
    altitude error of b·T_v·T_h (5.9 m for 12 mg with the defaults).

    Parameters
    ----------
    settings : ComplementarySettings, optional
        Default: time constants T_v = 9.99 s, T_h = 4.99 s (the write-up's
        0.999 and 0.998 at 100 Hz).

    Notes
    -----
    Inputs as for :class:`fusion_altitude.AltitudeEstimator`: acceleration
    m/s² (+up, gravity removed), baro altitude m (NaN: no sample this step),
    dt s. The first baro sample sets the reference. Copies and pickles carry
    the full state.
    """

    __slots__ = ("_settings", "_h", "_v", "_a", "_zf", "_vb", "_since", "_gap_time", "_gap_count", "_baro_timeouts",
                 "_reference_set", "_baro_timed_out")

    def __init__(self, settings: Optional[ComplementarySettings] = None) -> None:
        # FusionAltitudeComplementaryInitialise
        self._settings = ComplementarySettings() if settings is None else ComplementarySettings.coerce(settings)
        self._h = self._v = self._a = self._zf = self._vb = self._since = self._gap_time = f32(0)
        self._gap_count = self._baro_timeouts = 0
        self._reference_set = self._baro_timed_out = False

    # FusionAltitudeComplementaryReset
    def _reset(self, z: np.float32) -> ComplementaryStatus:
        if not np.isfinite(z):
            return ComplementaryStatus.INVALID_BARO_ALTITUDE
        self._h = self._zf = z
        self._v = self._vb = self._since = self._gap_time = f32(0)
        self._reference_set, self._baro_timed_out = True, False
        return ComplementaryStatus.OK

    # FusionAltitudeComplementaryRestart: after a gap, v = vBaro = mean velocity over it
    def _restart(self, z: np.float32) -> None:
        velocity = (z - self._h) / self._gap_time
        velocity = velocity if np.isfinite(velocity) else f32(0)  # overflow: a gap of a few ulps
        self._h = self._zf = z
        self._v = self._vb = velocity
        self._since = self._gap_time = f32(0)
        self._reference_set, self._baro_timed_out = True, False

    # FusionAltitudeComplementaryUpdate
    def _update(self, a: np.float32, z: np.float32, dt: np.float32) -> ComplementaryStatus:
        status = check_inputs(a, z, dt)
        if status != ComplementaryStatus.OK:
            return status
        baro_sample = bool(np.isfinite(z))
        self._timing(dt, baro_sample)
        if not self._reference_set:
            if baro_sample and self._gap_time > 0:
                self._restart(z)
                return ComplementaryStatus.OK
            if baro_sample:
                return self._reset(z)
            if self._gap_time > 0:
                self._since += dt
            self._vb = _NAN
            return ComplementaryStatus.OK
        if self._baro_timed_out:
            self._timed_out_step(z, dt, baro_sample)
        else:
            self._blend(a, z, dt, baro_sample)
        return ComplementaryStatus.OK

    # FusionAltitudeComplementaryUpdate: a gap (dt > gap_period, s) ends the reference, a baro silence longer than
    # baro_timeout (s) is a timeout
    def _timing(self, dt: np.float32, baro_sample: bool) -> None:
        if self._reference_set and dt > f32(self._settings._values["gap_period"]):  # a gap
            self._gap_count = (self._gap_count + 1) & 0xFFFFFFFF
            self._reference_set = False
            self._gap_time = dt
        elif not self._reference_set and self._gap_time > 0:  # still waiting for the baro after a gap
            self._gap_time += dt
        if (not baro_sample and (self._reference_set or self._gap_time > 0) and not self._baro_timed_out
                and (self._since + dt) > f32(self._settings._values["baro_timeout"])):  # a baro timeout
            self._baro_timeouts = (self._baro_timeouts + 1) & 0xFFFFFFFF
            self._baro_timed_out = True

    # FusionAltitudeComplementaryUpdate, timed out: no dead reckoning, v decays to 0; the next baro sample restarts h
    def _timed_out_step(self, z: np.float32, dt: np.float32, baro_sample: bool) -> None:
        if baro_sample:
            self._h = self._zf = z
            self._vb = self._v
            self._since = f32(0)
            self._baro_timed_out = False
            return
        timeout = f32(self._settings._values["baro_timeout"])
        self._v *= timeout / (timeout + dt)
        self._h += self._v * dt
        self._vb = _NAN
        self._since += dt

    # FusionAltitudeComplementaryUpdate, referenced: low-passed accel and baro, then the two blends
    def _blend(self, a: np.float32, z: np.float32, dt: np.float32, baro_sample: bool) -> None:
        s = self._settings._values
        tau_a = f32(s["accel_time_constant"])
        # first-order low-pass of the acceleration: aLp += dt/(tauA + dt) * (a - aLp)
        self._a += (dt / (tau_a + dt)) * (a - self._a)
        a_lp = self._a
        velocity_predicted = self._v + a_lp * dt
        altitude_predicted = self._h + velocity_predicted * dt + _HALF * a_lp * dt * dt
        if not baro_sample:
            self._v = velocity_predicted
            self._h = altitude_predicted
            self._vb = _NAN
            self._since += dt
            return
        interval = self._since + dt  # D: time since the previous baro sample
        baro_previous = self._zf
        tau_b = f32(s["baro_time_constant"])
        self._zf = baro_previous + (interval / (tau_b + interval)) * (z - baro_previous)
        baro_velocity = (self._zf - baro_previous) / interval
        if s["per_sample_coefficients"]:
            c_v = f32(s["velocity_coefficient"])
            c_h = f32(s["altitude_coefficient"])
        else:
            t_v = f32(s["velocity_time_constant"])
            t_h = f32(s["altitude_time_constant"])
            c_v = t_v / (t_v + interval)
            c_h = t_h / (t_h + interval)
        self._v = c_v * velocity_predicted + (_ONE - c_v) * baro_velocity
        self._h = c_h * altitude_predicted + (_ONE - c_h) * self._zf
        self._vb = baro_velocity
        self._since = f32(0)

    def update(self, accel: float, baro_altitude: float, dt: float) -> None:
        """Process one sample: accel m/s², baro_altitude m (NaN: none), dt s."""
        with np.errstate(over="ignore"):
            a = f32(_common.as_float(accel, "accel"))
            z = f32(_common.as_float(baro_altitude, "baro_altitude"))
            t = f32(_common.as_float(dt, "dt"))
        with np.errstate(all="ignore"):
            status = self._update(a, z, t)
        if status != ComplementaryStatus.OK:
            _complementary_glue.raise_complementary_update_error(status, float(accel), float(baro_altitude), float(dt))  # type: ignore[arg-type]

    def reset(self, baro_altitude: float) -> None:
        """Set the reference: altitude = filtered baro = ``baro_altitude`` (m), velocities 0."""
        with np.errstate(over="ignore"):
            z = f32(_common.as_float(baro_altitude, "baro_altitude"))
        if self._reset(z) != ComplementaryStatus.OK:
            raise ValueError(f"baro_altitude must be finite (m), got {float(baro_altitude)!r}")  # type: ignore[arg-type]

    def update_batch(self, accel, baro_altitude, dt, out: Optional[Sequence[np.ndarray]] = None) -> ComplementaryBatch:
        """Process arrays of samples; equal, bit for bit, to calling :meth:`update` for each."""
        a, z, t, dt_is_array = _observer_glue.prepare_inputs(accel, baro_altitude, dt)
        result = _complementary_glue.complementary_outputs(a.shape[0], out)
        trial = copy.copy(self)
        with np.errstate(all="ignore"):
            for i in range(a.shape[0]):
                ti = t[i] if dt_is_array else t[0]
                status = trial._update(a[i], z[i], ti)
                if status != ComplementaryStatus.OK:
                    _complementary_glue.raise_complementary_update_error(status, float(a[i]), float(z[i]), float(ti), i,
                                                             dt_is_array)
                result.altitude[i] = trial._h
                result.vertical_velocity[i] = trial._v
                result.baro_filtered[i] = trial._zf
                result.baro_velocity[i] = trial._vb
        self._set_state(trial._get_state())
        return result if out is None else out  # out=: the caller's object itself

    altitude = state_property("_h", "Altitude estimate h, m.")
    vertical_velocity = state_property("_v", "Vertical velocity estimate v, m/s.")
    baro_filtered = state_property("_zf", "Low-passed baro altitude, m.")
    baro_velocity = state_property("_vb", "Finite-difference baro velocity of the latest step, m/s (NaN without baro).")
    reference_set = state_property(
        "_reference_set", "Whether the reference is set (False from a gap to the next baro sample).", bool)
    settings = settings_property(ComplementarySettings, "The settings; assign new ones to retune, keeping the state.")

    def _get_state(self) -> tuple:
        return (self._settings.as_dict(), float(self._h), float(self._v), float(self._a), float(self._zf),
                float(self._vb), float(self._since), float(self._gap_time), self._gap_count, self._baro_timeouts,
                self._reference_set, self._baro_timed_out)

    def _set_state(self, state: tuple) -> None:
        # the C struct's order; an 8-tuple is a checkpoint from before the gap fields, a 10-tuple one from before
        # the baro timeout
        baro_timeouts, baro_timed_out = 0, False
        if len(state) == 8:
            values, h, v, a, zf, vb, since, reference_set = state
            gap_time, gap_count = 0.0, 0
        elif len(state) == 10:
            values, h, v, a, zf, vb, since, gap_time, gap_count, reference_set = state
        else:
            values, h, v, a, zf, vb, since, gap_time, gap_count, baro_timeouts, reference_set, baro_timed_out = state
        self._baro_timeouts, self._baro_timed_out = int(baro_timeouts), bool(baro_timed_out)
        self._settings = ComplementarySettings(**{"baro_timeout": 2.0, **values})
        self._h, self._v, self._a, self._zf, self._vb, self._since = (f32(x) for x in (h, v, a, zf, vb, since))
        self._reference_set = bool(reference_set)
        self._gap_time, self._gap_count = f32(gap_time), int(gap_count)

    def __repr__(self) -> str:
        return f"ComplementaryFilter(altitude={self._h}, vertical_velocity={self._v}, settings={self._settings!r})"
