"""The rocket estimator (``csrc/fusion_altitude_rocket.h``) in plain Python.

Pad calibration, the baro gate (dynamic-pressure lockout, spike rejection,
offset re-admission) and the phase state machine pad → boost →
coast → drogue → main → landed around the reference altitude observer. Each
method mirrors the C function named in its comment, statement for statement,
in float32, so that the results agree bit for bit; see docs/rocket.md for the
design and the C header for the equations.
"""

from __future__ import annotations

import copy
from typing import List, Optional, Sequence

import numpy as np

from .._core import _common, _rocket_glue, _observer_glue
from .._core._rocket_glue import (BaroFate, FlightEvents, Phase, RocketBatch, RocketStatus, events_from_tuples,
                            prepare_batch, raise_update_error)
from ._checkpoint import Checkpointable
from ._diagnostics import state_property
from ._settings import KeywordSettings
from .observer import AltitudeEstimator, AltitudeSettings, Status, _check_gains, check_inputs

f32 = np.float32
_NAN = f32("nan")
_ZERO = f32(0)
MACH_LOCKOUT = f32(_rocket_glue.MACH_LOCKOUT)
MAX_GAP_STEPS = 4096
OFFSET_DECAY = f32(_rocket_glue._c_tables.FUSION_ALTITUDE_ROCKET_OFFSET_DECAY)
GAP_HOLD = f32(_rocket_glue._c_tables.FUSION_ALTITUDE_ROCKET_GAP_HOLD)
GRAVITY = f32(_rocket_glue._c_tables.FUSION_ALTITUDE_GRAVITY)
CONTRADICTION_TIME = f32(_rocket_glue._c_tables.FUSION_ALTITUDE_ROCKET_CONTRADICTION_TIME)
CONTRADICTION_LOCKOUT_TIME = f32(_rocket_glue._c_tables.FUSION_ALTITUDE_ROCKET_CONTRADICTION_LOCKOUT_TIME)
PEAK_AGE = f32(_rocket_glue._c_tables.FUSION_ALTITUDE_ROCKET_PEAK_AGE)
_HALF_G = f32(0.5) * GRAVITY
CALIBRATION_WINDOWS = 8

# event indices
LAUNCH, BURNOUT, MAX_SPEED, APOGEE, MAIN, LANDED = range(6)


def _event() -> list:
    """[occurred, sample, time, height, velocity]"""
    return [False, 0, _ZERO, _ZERO, _ZERO]


class RocketSettings(KeywordSettings):
    """Settings of the rocket estimator (``FusionAltitudeRocketSettings``), float32.

    Parameters
    ----------
    observer : AltitudeSettings, 3 gains or 4 values, optional
        Observer settings in flight: gains (Kh 1/s, Kv 1/s², Kb 1/s³) and the
        observer's gap period (s, 0.5 unless given); the rocket gains
        (1.4, 1.0, 0: ω 1 rad/s, ζ 0.7, no in-flight bias learning) if omitted.
        The bias gain is forced to 0 from apogee on. ``as_dict()["observer"]``
        holds the 4 values.
    stationary_accel : float, default 5.0
        m/s²: a pad sample within this of its window's first sample is stationary.
    calibration_window : float, default 0.5
        s: pad calibration window; only all-stationary windows are learned.
    launch_accel : float, default 20.0
        m/s²: accel − bias above this ...
    launch_time : float, default 0.05
        s: ... for this long declares launch.
    burnout_accel : float, default 0.0
        m/s²: accel − bias below this ...
    burnout_time : float, default 0.1
        s: ... for this long declares burnout.
    apogee_margin : float, default 1.0
        m/s: apogee when the velocity estimate falls below −apogee_margin.
    lockout_speed : float, default 100.0
        m/s: the baro is not fused while |v| exceeds this (and always above 236 m/s, Mach 0.8).
    spike_threshold : float, default 20.0
        m: a baro sample this far from the baro's own prediction is a spike.
    spike_time : float, default 0.2
        s: longest run of spike rejections; then the new level is accepted.
    offset_rate : float, default 0.9
        The output height absorbs the baro offset found at re-admission at up
        to ``offset_rate·|v|`` m/s (0 < offset_rate ≤ 1).
    main_altitude : float, default 250.0
        m above the pad: main deployment on the way down.
    landed_speed : float, default 3.0
        m/s: |v| below this ...
    landed_time : float, default 2.0
        s: ... for this long declares landing.
    gap_period : float, default 0.5
        s: an update with a longer dt is a gap (counted; extrapolated in flight).
    baro_launch_height : float, default 30.0
        m: launch from the baro when two rising pad baro samples are more than
        this above the pad (the accelerometer showed none); the flight is then
        baro-led.

    The defaults are the header's (``FusionAltitudeRocketSettingsDefault``).

    Raises
    ------
    ValueError
        A value breaks its rule (named in the message); TypeError for an
        unknown name or a non-real value.
    """

    __slots__ = ()
    _DISTINCT = "launch_accel"

    def __init__(self, observer: object = None, **kwargs: object) -> None:
        observer_values = _rocket_glue.observer_settings(observer)
        values = _rocket_glue.convert_settings(kwargs)
        kh, kv, kb, gap, baro_timeout = (f32(v) for v in observer_values)
        check_gains = _observer_glue.C_SETTINGS_FUNCTIONS.get("check_gains", _check_gains)  # C where built
        if check_gains(kh, kv, kb) != Status.OK or not gap > 0 or not baro_timeout > 0:  # FusionAltitudeSettingsCheck
            _rocket_glue.raise_settings_error(RocketStatus.INVALID_OBSERVER_SETTINGS, {"observer": observer_values})
        status = _rocket_glue.check_settings_values(values)
        if status != RocketStatus.OK:
            _rocket_glue.raise_settings_error(status, values)
        self._values = {"observer": observer_values, **values}

    @property
    def gains(self) -> tuple:
        """The observer gains (Kh 1/s, Kv 1/s², Kb 1/s³)."""
        return self._values["observer"][:3]


class RocketEstimator(Checkpointable):
    """Rocket flight computer: altitude observer + pad calibration + baro gate + flight phases.

    Parameters
    ----------
    settings : RocketSettings, optional
        Defaults if omitted.

    Notes
    -----
    Inputs per step: ``accel`` (m/s², gravity removed, +up: without an INS the
    long-axis accelerometer minus g, ≈ 0 at rest on the pad), ``baro_altitude``
    (m, pressure altitude; NaN for no sample) and ``dt`` (s). Heights are
    above the pad learned while stationary. See docs/rocket.md.
    """

    __slots__ = ("_settings", "_obs", "_phase", "_baro", "_events", "_candidate", "_sample", "_gap_count", "_windows",
                 "_window_samples", "_window_baro_samples", "_time", "_time_c", "_accel_bias", "_pad_altitude",
                 "_window_time", "_window_accel_first", "_window_accel_sum", "_window_baro_first", "_window_baro_sum",
                 "_run_time", "_spike_time", "_last_baro", "_last_baro_age", "_window_stationary", "_pad_altitude_set",
                 "_last_baro_set", "_baro_offset", "_offset_applied", "_baro_admitted", "_lockout", "_accel_trusted",
                 "_pad_baro_previous", "_pad_baro_age", "_baro_peak", "_contradiction_time", "_baro_peak_age", "_pad_baro_previous_set", "_baro_led", "_gap_restart", "_s")

    def __init__(self, settings: Optional[RocketSettings] = None) -> None:
        # FusionAltitudeRocketInitialise
        self._use_settings(RocketSettings() if settings is None else RocketSettings.coerce(settings))
        self._obs = AltitudeEstimator(AltitudeSettings(*self._settings.observer))
        self._obs._b = _ZERO
        self._obs._reset(_ZERO)
        self._phase = Phase.PAD
        self._baro = BaroFate.NONE
        self._events: List[list] = [_event() for _ in range(6)]
        self._candidate = _event()
        self._sample = self._gap_count = self._windows = 0
        self._time = self._time_c = self._accel_bias = self._pad_altitude = _ZERO  # s, s, m/s², m
        self._run_time = self._spike_time = self._last_baro = self._last_baro_age = _ZERO  # s, s, m, s
        self._baro_offset = self._offset_applied = _ZERO  # m
        self._pad_baro_previous = self._pad_baro_age = _ZERO  # m, s
        self._baro_peak = self._contradiction_time = self._baro_peak_age = _ZERO  # m, s, s
        self._pad_altitude_set = self._last_baro_set = self._baro_admitted = self._lockout = False
        self._accel_trusted = self._pad_baro_previous_set = self._baro_led = self._gap_restart = False
        self._clear_window()

    # FusionAltitudeRocketClearWindow
    def _clear_window(self) -> None:
        self._window_samples = self._window_baro_samples = 0
        self._window_time = _ZERO  # s
        self._window_accel_first = self._window_accel_sum = _ZERO  # m/s²
        self._window_baro_first = self._window_baro_sum = _ZERO  # m
        self._window_stationary = True

    def _reset_observer(self) -> None:
        # FusionAltitudeResetWithBias(&observer, 0, accelBias)
        self._obs._b = self._accel_bias
        self._obs._reset(_ZERO)

    # FusionAltitudeRocketRecord
    def _record(self, event: list) -> None:
        event[:] = [True, self._sample, self._time, self._obs._h + self._offset_applied, self._obs._v]

    # FusionAltitudeRocketBaroLaunchStep
    def _baro_launch_step(self, z: np.float32) -> bool:
        s = self._s
        height = z - self._pad_altitude
        previous, age = self._pad_baro_previous, self._pad_baro_age
        launched = bool(self._pad_baro_previous_set and previous > s["baro_launch_height"]
                        and height > s["baro_launch_height"] and height > previous)
        self._pad_baro_previous = height
        self._pad_baro_age = _ZERO
        self._pad_baro_previous_set = True
        if not launched:
            return False
        self._obs._b = self._accel_bias
        self._obs._reset(height)
        if age > s["gap_period"]:
            self._obs._v = (height - previous) / age
        self._record(self._events[LAUNCH])
        self._phase = Phase.COAST
        self._baro_led = True
        self._baro_admitted = True
        self._baro = BaroFate.FUSED
        self._last_baro = height
        self._last_baro_age = _ZERO
        self._last_baro_set = True
        self._baro_peak = height
        self._baro_peak_age = _ZERO
        self._run_time = _ZERO
        self._clear_window()
        return True

    # FusionAltitudeRocketPadStep
    def _pad_step(self, a: np.float32, z: np.float32, dt: np.float32, gap: bool) -> None:
        s = self._s
        has_baro = not np.isnan(z)
        self._baro = BaroFate.PAD if has_baro else BaroFate.NONE
        if has_baro and not self._pad_altitude_set:
            self._pad_altitude = z
            self._pad_altitude_set = True
        self._pad_baro_age += dt
        if has_baro and self._baro_launch_step(z):
            return

        net = a - self._accel_bias
        if not gap and not np.isnan(a) and net > s["launch_accel"]:
            if self._run_time == 0:
                self._reset_observer()
                self._obs._update(a, _NAN, dt)
                self._record(self._candidate)
            else:
                self._obs._update(a, _NAN, dt)
            self._run_time += dt
            if self._run_time >= s["launch_time"]:
                self._events[LAUNCH] = list(self._candidate)
                self._phase = Phase.BOOST
                self._baro_admitted = True
                self._run_time = _ZERO
                self._clear_window()
            self._window_stationary = False
            return
        self._run_time = _ZERO
        self._reset_observer()

        if gap:
            self._clear_window()
            return
        self._calibration_step(a, z, has_baro, dt)

    # FusionAltitudeRocketCalibrationStep
    def _calibration_step(self, a: np.float32, z: np.float32, has_baro: bool, dt: np.float32) -> None:
        s = self._s
        if not np.isnan(a):
            if self._window_samples == 0:
                self._window_accel_first = a
            deviation = a - self._window_accel_first
            if not deviation <= s["stationary_accel"] or not deviation >= -s["stationary_accel"]:
                self._window_stationary = False
            self._window_accel_sum += deviation
            self._window_samples += 1
        if has_baro:
            if self._window_baro_samples == 0:
                self._window_baro_first = z
            self._window_baro_sum += z - self._window_baro_first
            self._window_baro_samples += 1
        self._window_time += dt
        if self._window_time >= s["calibration_window"]:
            if self._window_stationary:
                if self._windows < CALIBRATION_WINDOWS:
                    self._windows += 1
                weight = f32(1) / f32(self._windows)
                if self._window_samples > 0:
                    mean_accel = self._window_accel_first + self._window_accel_sum / f32(self._window_samples)
                    self._accel_bias += (mean_accel - self._accel_bias) * weight
                if self._window_baro_samples > 0:
                    mean_baro = self._window_baro_first + self._window_baro_sum / f32(self._window_baro_samples)
                    self._pad_altitude += (mean_baro - self._pad_altitude) * weight
                self._reset_observer()
            self._clear_window()

    # FusionAltitudeRocketGate
    def _gate(self, z: np.float32, dt: np.float32) -> np.float32:
        s = self._s
        v = self._obs._v
        lockout_speed = s["lockout_speed"] if s["lockout_speed"] < MACH_LOCKOUT else MACH_LOCKOUT
        self._lockout = bool((self._phase == Phase.BOOST and not self._baro_led) or v > lockout_speed
                             or v < -lockout_speed)
        self._last_baro_age += dt
        self._baro_peak_age += dt
        if np.isnan(z):
            self._baro = BaroFate.NONE
            return _NAN
        height = z - self._pad_altitude
        previous_baro, previous_age, previous_set = self._last_baro, self._last_baro_age, self._last_baro_set
        if self._last_baro_set:
            miss = height - (self._last_baro + v * self._last_baro_age)
            threshold = s["spike_threshold"] + _HALF_G * (self._last_baro_age * self._last_baro_age)
            if miss > threshold or miss < -threshold:
                if self._spike_time < s["spike_time"]:
                    self._spike_time += dt
                    self._baro = BaroFate.SPIKE
                    return _NAN
                if not self._baro_led:
                    self._baro_admitted = False  # a lasting step: re-admitted through the offset
        self._spike_time = _ZERO
        self._last_baro = height
        self._last_baro_age = _ZERO
        self._last_baro_set = True
        if height > self._baro_peak:
            self._baro_peak = height
            self._baro_peak_age = _ZERO
        if self._lockout and not self._baro_led:
            self._baro = BaroFate.LOCKED_OUT
            self._baro_admitted = False
            return _NAN
        self._baro = BaroFate.FUSED
        if self._gap_restart:  # restart with the baro's mean velocity; height: re-based before apogee, restarted after
            if self._phase < Phase.DROGUE:
                self._baro_offset = height - self._obs._h
            else:
                self._obs._h = height - self._baro_offset
            if previous_set and previous_age > 0:
                self._obs._v = (height - previous_baro) / previous_age
            self._gap_restart = False
            self._baro_admitted = True
        elif not self._baro_admitted:
            self._baro_offset = height - self._obs._h
            self._baro_admitted = True
        return height - self._baro_offset

    # FusionAltitudeRocketBurnoutStep and FusionAltitudeRocketLandedStep: the run of a detector
    def _detector_run(self, holds: bool, dt: np.float32, duration: np.float32, event: int, phase: Phase) -> None:
        """While ``holds``, the run grows by dt (s), its first sample the candidate event; after ``duration`` s the
        candidate is ``event`` and the flight moves to ``phase``. Otherwise the run restarts."""
        if holds:
            if self._run_time == 0:
                self._record(self._candidate)
            self._run_time += dt
            if self._run_time >= duration:
                self._events[event] = list(self._candidate)
                self._phase = phase
                self._run_time = _ZERO
        else:
            self._run_time = _ZERO

    # FusionAltitudeRocketLandedStep: |v| < landed_speed (m/s) for landed_time s
    def _landed_step(self, v: np.float32, dt: np.float32) -> None:
        s = self._s
        still = not self._lockout and v < s["landed_speed"] and v > -s["landed_speed"]
        self._detector_run(still, dt, s["landed_time"], LANDED, Phase.LANDED)

    # FusionAltitudeRocketInput
    def _input(self, a: np.float32, accel_vertical: bool) -> np.float32:
        descending = self._phase >= Phase.DROGUE
        self._accel_trusted = (not self._baro_led) and ((not descending) or accel_vertical)
        if self._accel_trusted:
            return a
        if self._baro_led and self._phase == Phase.COAST:
            return self._obs._b - GRAVITY  # ballistic coast
        return self._obs._b

    # FusionAltitudeRocketApogee
    def _apogee(self, contradicted: bool) -> None:
        self._record(self._events[APOGEE])
        self._events[APOGEE][3] = self._baro_peak if contradicted else self._obs._h + self._baro_offset
        self._phase = Phase.DROGUE
        kh, kv, _ = self._obs._settings._gains
        descent = copy.copy(self._obs._settings)
        descent._gains = (kh, kv, _ZERO)  # bias frozen from apogee on
        self._obs._settings = descent
        if contradicted:  # FusionAltitudeResetWithBias(&observer, h, b)
            self._obs._reset(self._obs._h)
            self._baro_admitted = False

    # FusionAltitudeRocketFlightStep
    def _flight_step(self, a: np.float32, z: np.float32, dt: np.float32, gap: bool, accel_vertical: bool) -> None:
        if np.isnan(a) and not self._baro_led:  # the accelerometer is lost: baro-led from here
            self._lead_with_baro()
        if gap and not self._baro_led and self._phase < Phase.DROGUE and (self._lockout or self._phase == Phase.BOOST):
            self._lead_with_baro()  # a gap in boost or in the lockout: the integrated velocity is lost
        accel_input = self._input(a, accel_vertical)
        if gap:
            self._gap_step(accel_input, dt)
            return
        fused = self._gate(z, dt)
        height_before = self._obs._h
        self._obs._update(accel_input, fused, dt)
        v = self._obs._v
        self._apply_offset(v, height_before, dt)
        self._phase_step(a, v, dt)
        if self._phase in (Phase.BOOST, Phase.COAST) and (
                not self._events[MAX_SPEED][0] or v > self._events[MAX_SPEED][4]):
            self._record(self._events[MAX_SPEED])

    def _lead_with_baro(self) -> None:
        """The flight is baro-led from here; in boost it goes on in coast (no burnout event)."""
        self._baro_led = True
        if self._phase == Phase.BOOST:
            self._phase = Phase.COAST
            self._run_time = _ZERO

    # FusionAltitudeRocketGapStep
    def _gap_step(self, accel_input: np.float32, dt: np.float32) -> None:
        s = self._s
        steps = 1
        step = dt
        while step > s["gap_period"] and steps < MAX_GAP_STEPS:
            steps *= 2
            step = dt / f32(steps)
        hold = self._phase != Phase.BOOST and dt <= GAP_HOLD  # accel held over gaps up to 4 s
        gap_input = accel_input if hold else self._obs._b
        hold_top = self._baro_led and self._phase == Phase.COAST  # no extrapolated descent the baro has not shown
        for _ in range(steps):
            top = hold_top and not self._obs._v > 0
            self._obs._update(self._obs._b if top else gap_input, _NAN, step)
        if self._baro_led or not hold:
            self._gap_restart = True  # the extrapolation is a guess: the next sample restarts the observer
        else:
            self._baro_admitted = False  # held: the height error goes through the offset
        self._last_baro_age += dt
        self._baro_peak_age += dt
        if self._phase == Phase.BOOST:
            self._run_time = _ZERO  # the burnout run restarts; a landed run goes on
        self._baro = BaroFate.NONE

    # FusionAltitudeRocketApplyOffset
    def _apply_offset(self, v: np.float32, height_before: np.float32, dt: np.float32) -> None:
        """offset_applied -> baro_offset while climbing: up by at most offset_rate·|v|·dt (m), down by at most
        offset_rate times the observer's rise in this step (m; none if it did not rise): the output height never
        falls by absorbing the offset. In the descent at most offset_rate·(|v| + landed_speed)·dt either way."""
        s = self._s
        speed = -v if v < 0 else v
        offset_step = s["offset_rate"] * speed * dt
        rise = self._obs._h - height_before
        offset_step_down = s["offset_rate"] * rise if rise > 0 else _ZERO
        offset_left = self._baro_offset - self._offset_applied
        up, down = offset_step, offset_step_down  # the largest moves this step, m
        if self._phase >= Phase.DROGUE:
            left = -offset_left if offset_left < 0 else offset_left
            up = down = (s["offset_rate"] * (speed + s["landed_speed"]) + OFFSET_DECAY * left) * dt
        if offset_left > up:
            self._offset_applied += up
        elif offset_left < -down:
            self._offset_applied -= down
        else:
            self._offset_applied = self._baro_offset

    # FusionAltitudeRocketPhaseStep: burnout, apogee, main, landing
    def _phase_step(self, a: np.float32, v: np.float32, dt: np.float32) -> None:
        s = self._s
        h = self._obs._h + self._baro_offset  # the baro-corrected height decides main
        if self._phase == Phase.BOOST:  # FusionAltitudeRocketBurnoutStep
            self._detector_run(a - self._accel_bias < s["burnout_accel"], dt, s["burnout_time"], BURNOUT, Phase.COAST)
        elif self._phase == Phase.COAST:
            contradicted = self._last_baro_set and self._last_baro < self._baro_peak - s["spike_threshold"]
            self._contradiction_time = self._contradiction_time + dt if contradicted else _ZERO
            baro_agrees = not self._baro_led or (self._baro == BaroFate.FUSED and self._last_baro < self._baro_peak
                                                 and self._baro_peak_age >= PEAK_AGE)  # baro-led: the baro agrees
            if not self._lockout and v < -s["apogee_margin"] and baro_agrees:
                self._apogee(False)
            elif self._contradiction_time >= (CONTRADICTION_LOCKOUT_TIME if self._lockout else CONTRADICTION_TIME):
                self._apogee(True)
        elif self._phase == Phase.DROGUE:
            if not self._lockout and not h > s["main_altitude"]:
                self._record(self._events[MAIN])
                self._phase = Phase.MAIN
                self._run_time = _ZERO
            else:
                self._landed_step(v, dt)
        elif self._phase == Phase.MAIN:
            self._landed_step(v, dt)

    # FusionAltitudeRocketStep
    def _step(self, a: np.float32, z: np.float32, dt: np.float32, accel_vertical: bool) -> RocketStatus:
        status = check_inputs(_ZERO if np.isnan(a) else a, z, dt)  # accel NaN: no accelerometer sample
        if status != 0:
            return RocketStatus(int(status))  # the first three codes agree
        increment = dt - self._time_c
        total = self._time + increment
        self._time_c = (total - self._time) - increment
        self._time = total

        gap = bool(dt > self._s["gap_period"])
        if gap:
            self._gap_count += 1
        if self._phase == Phase.PAD:
            self._lockout = False
            self._accel_trusted = True
            self._pad_step(a, z, dt, gap)
        else:
            self._flight_step(a, z, dt, gap, accel_vertical)
        self._sample += 1
        return RocketStatus.OK

    # -- public API --------------------------------------------------------

    def update(self, accel: float, baro_altitude: float, dt: float, *, accel_is_vertical: bool = False) -> None:
        with np.errstate(over="ignore"):
            a = f32(_common.as_float(accel, "accel"))
            z = f32(_common.as_float(baro_altitude, "baro_altitude"))
            t = f32(_common.as_float(dt, "dt"))
        status = self._step(a, z, t, bool(accel_is_vertical))
        if status != RocketStatus.OK:
            raise_update_error(status, float(accel), float(baro_altitude), float(dt))

    def update_batch(self, accel, baro_altitude, dt, *, accel_is_vertical: bool = False,
                     out: Optional[Sequence[np.ndarray]] = None) -> RocketBatch:
        """Process arrays, continuing from the current state; equal bit for bit to :meth:`update` per sample.

        On a bad sample nothing is applied and ValueError names the argument and the first bad index.
        """
        a, z, t, dt_is_array, result = prepare_batch(accel, baro_altitude, dt, out)
        trial = copy.copy(self)
        for i in range(a.shape[0]):
            ti = t[i] if dt_is_array else t[0]
            status = trial._step(a[i], z[i], ti, bool(accel_is_vertical))
            if status != RocketStatus.OK:
                raise_update_error(status, float(a[i]), float(z[i]), float(ti), i, dt_is_array)
            result.height[i] = trial._obs._h + trial._offset_applied
            result.vertical_velocity[i] = trial._obs._v
            result.accel_bias[i] = trial._obs._b
            result.phase[i] = trial._phase
            result.baro[i] = trial._baro
        self._set_state(trial._get_state())
        return result if out is None else out  # out=: the caller's object itself

    @property
    def settings(self) -> RocketSettings:
        return self._settings

    @property
    def height(self) -> float:
        """Height above the pad, m (observer height + applied baro offset)."""
        return float(self._obs._h + self._offset_applied)

    vertical_velocity = state_property("_obs._v", "m/s, +up.")
    accel_bias = state_property("_obs._b", "Accelerometer bias in use, m/s² (pad-learned, frozen after apogee).")
    pad_altitude = state_property("_pad_altitude", "Pad pressure altitude learned on the pad, m.")
    phase = state_property("_phase", None, Phase)
    baro = state_property("_baro", "What happened to the latest step's baro sample.", BaroFate)
    locked_out = state_property("_lockout", None, bool)

    @property
    def calibrated(self) -> bool:
        return self._windows > 0

    gap_count = state_property("_gap_count", None, int)
    time = state_property("_time", "s since initialise (compensated sum of dt).")

    @property
    def events(self) -> FlightEvents:
        return events_from_tuples([(e[0], e[1], e[2], e[3], e[4]) for e in self._events])

    # -- checkpoint --------------------------------------------------------

    def _use_settings(self, settings: RocketSettings) -> None:
        self._settings = settings
        self._s = {name: f32(value) for name, value in settings.as_dict().items() if name != "observer"}

    def _get_state(self) -> tuple:
        """The fields of FusionAltitudeRocket in order (structs as tuples, the settings as ``as_dict()``)."""
        def event(e: list) -> tuple:
            return (bool(e[0]), int(e[1]), float(e[2]), float(e[3]), float(e[4]))

        return (self._settings.as_dict(), self._obs._get_state(), int(self._phase), int(self._baro),
                tuple(event(e) for e in self._events), event(self._candidate), self._sample, self._gap_count,
                self._windows, self._window_samples, self._window_baro_samples,
                *(float(x) for x in (self._time, self._time_c, self._accel_bias, self._pad_altitude, self._window_time,
                                     self._window_accel_first, self._window_accel_sum, self._window_baro_first,
                                     self._window_baro_sum, self._run_time, self._spike_time, self._last_baro,
                                     self._last_baro_age, self._baro_offset, self._offset_applied,
                                     self._pad_baro_previous, self._pad_baro_age, self._baro_peak, self._contradiction_time,
                                     self._baro_peak_age)),
                self._window_stationary, self._pad_altitude_set, self._last_baro_set, self._baro_admitted,
                self._lockout, self._accel_trusted, self._pad_baro_previous_set, self._baro_led, self._gap_restart)

    def _set_state(self, state: tuple) -> None:
        (settings, observer, phase, baro, events, candidate, self._sample, self._gap_count, self._windows,
         self._window_samples, self._window_baro_samples, *rest) = state
        floats, flags = rest[:20], rest[20:]
        self._use_settings(RocketSettings(**settings))
        self._obs = AltitudeEstimator(AltitudeSettings(*self._settings.observer))
        self._obs._set_state(tuple(observer))
        self._phase, self._baro = Phase(phase), BaroFate(baro)

        def event(e) -> list:
            return [bool(e[0]), int(e[1]), f32(e[2]), f32(e[3]), f32(e[4])]

        self._events = [event(e) for e in events]
        self._candidate = event(candidate)
        (self._time, self._time_c, self._accel_bias, self._pad_altitude, self._window_time, self._window_accel_first,
         self._window_accel_sum, self._window_baro_first, self._window_baro_sum, self._run_time, self._spike_time,
         self._last_baro, self._last_baro_age, self._baro_offset, self._offset_applied, self._pad_baro_previous,
         self._pad_baro_age, self._baro_peak, self._contradiction_time, self._baro_peak_age) = (f32(x) for x in floats)
        (self._window_stationary, self._pad_altitude_set, self._last_baro_set, self._baro_admitted, self._lockout,
         self._accel_trusted, self._pad_baro_previous_set, self._baro_led, self._gap_restart) = (bool(x) for x in flags)


_common.share_docstrings(RocketEstimator, _rocket_glue.RocketContract)
