"""Rockets: the rocket estimator (``csrc/fusion_altitude_rocket.h``) for logs and scripts.

- :func:`run_rocket` runs :class:`RocketEstimator` over a whole log and returns
  the per-sample estimates and the :class:`FlightEvents` with times in the
  log's own seconds; :func:`detect_events` returns the events only.
- :func:`rocket_altitude_settings` and :func:`rocket_kalman_settings`: settings
  of the plain observer and of the Kalman filter for rocket flights.
- :func:`long_axis_accel` turns a body-frame accelerometer into the input the
  rocket estimator expects (the long-axis specific force minus g).
- :func:`events_from_estimates` derives events from another flight computer's
  own height/velocity/acceleration (e.g. the CATS ``flightInfo`` log), to
  compare against; :func:`events_from_states` reads them off its logged
  flight states (AltOS ``state``); :func:`flight_computer_events` picks
  whichever a :class:`~fusion_altitude.logs.LogData` allows.

Units: time s, heights m above the pad, velocity m/s (+up), acceleration m/s².
See docs/rocket.md.
"""

from __future__ import annotations

from typing import List, Optional, Tuple

import numpy as np

from ._core._common import GRAVITY, as_float
from ._core._rocket import RocketEstimator
from ._core._rocket_glue import EVENT_NAMES, BaroFate, FlightEvent, FlightEvents, Phase, RocketBatch, RocketStatus
from .reference.rocket import RocketSettings

#: Observer gains of the rocket preset (Kh 1/s, Kv 1/s², Kb 1/s³): ω = 1 rad/s,
#: ζ = 0.7 and no in-flight bias learning (the bias comes from the pad).
ROCKET_OBSERVER_GAINS = (1.4, 1.0, 0.0)

__all__ = ["RocketEstimator", "RocketSettings", "RocketBatch", "FlightEvents", "FlightEvent", "Phase", "BaroFate",
           "RocketStatus", "ROCKET_OBSERVER_GAINS", "rocket_altitude_settings", "rocket_kalman_settings",
           "long_axis_accel", "run_rocket", "detect_events", "events_from_estimates", "events_from_states",
           "flight_computer_events", "STATE_EVENTS", "rocket_accel_input", "pad_levels", "saturated_samples"]


def rocket_altitude_settings():
    """The rocket preset of the plain observer: ``AltitudeSettings(1.4, 1.0, 0.0)``.

    ω = 1 rad/s, ζ = 0.7 through the bandwidth formulas with ω_b = 0: the
    bias is not learned in flight (static-port and transonic baro errors would
    leak into it); set it from a pad calibration with ``reset(..., accel_bias=...)``
    or use :class:`RocketEstimator`, which learns it on the pad.
    """
    from .reference.observer import AltitudeSettings
    return AltitudeSettings.preset("rocket")


def rocket_kalman_settings(**overrides: object):
    """Kalman filter settings for rockets (``KalmanSettings``), keywords override.

    Changed from the defaults, with reasons:

    - ``accel_noise`` 0.5 m/s²/√Hz: motor vibration and airframe flex (the
      default 0.035 is a quiet multirotor IMU);
    - ``baro_noise`` 2.0 m and ``baro_offset_random_walk`` 3.0 m/√s: the static
      port error changes with dynamic pressure by tens of metres within seconds;
    - ``gate`` 10 σ and ``rejection_timeout`` 0.3 s: a rocket's baro is
      rejected for good at the default 5 σ once the static-port error builds up;
      ejection spikes still fail a 10 σ gate;
    - ``accel_bias_random_walk`` 0.001 m/s³/√Hz: the bias is not observable
      through the baro errors of a boost.
    """
    from .reference.kalman import KalmanSettings
    values = {"accel_noise": 0.5, "baro_noise": 2.0, "baro_offset_random_walk": 3.0, "gate": 10.0,
              "rejection_timeout": 0.3, "accel_bias_random_walk": 0.001}
    values.update(overrides)
    return KalmanSettings(**values)


def long_axis_accel(accel_body: object, axis: int = 2, sign: float = 1.0) -> np.ndarray:
    """Long-axis specific force minus g, m/s²: the rocket estimator's ``accel`` input.

    Parameters
    ----------
    accel_body : array_like, shape (n, 3)
        Accelerometer, m/s², body frame (specific force: +g along the up axis at rest).
    axis : int, default 2
        Column along the rocket's long axis (0, 1 or 2).
    sign : float, default 1.0
        +1 if that axis points to the nose, −1 if to the tail (e.g. the Hedy
        CATS log: axis 1, sign −1, as its Y reads ≈ −9.9 on the rail).

    Returns
    -------
    numpy.ndarray
        ``sign · accel_body[:, axis] − g``, float64, ≈ 0 at rest on the pad.
    """
    array = np.asarray(accel_body, dtype=np.float64)
    if array.ndim != 2 or array.shape[1] != 3:
        raise ValueError(f"accel_body must have shape (n, 3), got {array.shape}")
    if axis not in (0, 1, 2):
        raise ValueError(f"axis must be 0, 1 or 2, got {axis!r}")
    sign = as_float(sign, "sign")
    if sign not in (1.0, -1.0):
        raise ValueError(f"sign must be +1 or -1, got {sign!r}")
    return sign * array[:, axis] - GRAVITY


def _time_steps(time: object) -> Tuple[np.ndarray, np.ndarray]:
    times = np.asarray(time, dtype=np.float64)
    if times.ndim != 1 or times.size < 2:
        raise ValueError(f"time must be 1-D with at least 2 samples, got shape {times.shape}")
    if not np.all(np.isfinite(times)):
        index = int(np.argmin(np.isfinite(times)))
        raise ValueError(f"time[{index}] must be finite, got {times[index]!r}")
    steps = np.diff(times)
    if np.any(steps <= 0):
        index = int(np.argmax(steps <= 0)) + 1
        raise ValueError(f"time[{index}] = {times[index]!r} s does not increase (previous {times[index - 1]!r} s)")
    dt = np.concatenate([[np.median(steps)], steps])
    return times, dt


def run_rocket(time: object, accel: object, baro_altitude: object, settings: Optional[RocketSettings] = None,
               accel_is_vertical: bool = False, estimator: Optional[object] = None) -> Tuple[RocketBatch, FlightEvents]:
    """Run the rocket estimator over a whole log.

    Parameters
    ----------
    time : array_like
        Sample times, s, strictly increasing (the log's own clock).
    accel : array_like
        m/s², gravity removed: the long-axis accelerometer minus g
        (:func:`long_axis_accel`), or an INS vertical acceleration with
        ``accel_is_vertical``.
    baro_altitude : array_like
        Pressure altitude, m (NaN where no baro sample); e.g.
        ``fusion_altitude.sensors.pressure_to_altitude(pressure_pa)``.
    settings : RocketSettings, optional
        Defaults if omitted.
    accel_is_vertical : bool, default False
        ``accel`` is a trusted earth-frame vertical acceleration (an INS): used
        after apogee too.
    estimator : RocketEstimator, optional
        Run this one (e.g. the pure-Python reference) instead of a new C-backed one.

    Returns
    -------
    (RocketBatch, FlightEvents)
        Height above the pad, velocity, bias, phase and baro fate per sample;
        the events with ``time`` in the log's seconds (of the declaring sample).
        The first sample is integrated over the median sample period.
    """
    times, dt = _time_steps(time)
    if estimator is None:
        estimator = RocketEstimator(settings)
    elif settings is not None:
        raise ValueError("give settings or estimator, not both")
    result = estimator.update_batch(accel, baro_altitude, dt, accel_is_vertical=accel_is_vertical)
    if result.height.shape[0] != times.shape[0]:
        raise ValueError(f"time has {times.shape[0]} samples but accel has {result.height.shape[0]}")
    return result, estimator.events.with_times(times)


def detect_events(time: object, accel: object, baro_altitude: object, settings: Optional[RocketSettings] = None,
                  accel_is_vertical: bool = False) -> FlightEvents:
    """The :class:`FlightEvents` of :func:`run_rocket` alone (times in the log's seconds)."""
    return run_rocket(time, accel, baro_altitude, settings, accel_is_vertical)[1]


def events_from_estimates(time: object, height: object, velocity: object, acceleration: object,
                          main_altitude: float = 250.0, launch_accel: float = 20.0,
                          landed_speed: float = 3.0, landed_time: float = 2.0) -> FlightEvents:
    """Events read off another flight computer's own estimates (to compare against).

    Rules, on its height h (m above the pad), velocity v (m/s) and acceleration a (m/s², gravity removed):
    launch: the first sample with a > ``launch_accel``; burnout: the first sample after launch with a < 0; max speed: the
    largest v; apogee: the first sample after burnout with v ≤ 0; main: the first sample after
    apogee with h ≤ ``main_altitude``; landed: |v| < ``landed_speed`` for ``landed_time`` s after main.
    ``sample`` indexes the given arrays.
    """
    t = np.asarray(time, dtype=np.float64)
    h = np.asarray(height, dtype=np.float64)
    v = np.asarray(velocity, dtype=np.float64)
    a = np.asarray(acceleration, dtype=np.float64)
    if not (t.shape == h.shape == v.shape == a.shape) or t.ndim != 1:
        raise ValueError("time, height, velocity and acceleration must be 1-D of one length")
    found = {}

    def first(mask: np.ndarray, start: int) -> Optional[int]:
        index = np.nonzero(mask[start:])[0]
        return int(index[0] + start) if index.size else None

    launch = first(a > launch_accel, 0)
    if launch is not None:
        found["launch"] = launch
        burnout = first(a < 0, found["launch"])
        if burnout is not None:
            found["burnout"] = burnout
            found["max_speed"] = int(np.argmax(v))
            apogee = first(v <= 0, burnout)
            if apogee is not None:
                found["apogee"] = apogee
                main = first(h <= main_altitude, apogee)
                if main is not None:
                    found["main"] = main
                    slow = np.abs(v) < landed_speed
                    for index in range(main, t.size):
                        if slow[index]:
                            end = first(~slow, index)
                            last = (end if end is not None else t.size) - 1
                            if t[last] - t[index] >= landed_time:
                                found["landed"] = index
                                break
    events = []
    for name in EVENT_NAMES:
        if name in found:
            k = found[name]
            events.append(FlightEvent(name, True, k, float(t[k]), float(h[k]), float(v[k])))
        else:
            events.append(FlightEvent(name, False, 0, 0.0, 0.0, 0.0))
    return FlightEvents(events)


#: Flight-computer states (AltOS ``state`` names, lower case) whose first sample dates each event: launch at the
#: first boost sample, burnout at the first fast/coast (AltOS "fast" is the coast above Mach 0.7), apogee at the
#: first drogue, then main and landed.
STATE_EVENTS = {"launch": ("boost",), "burnout": ("fast", "coast"), "apogee": ("drogue",), "main": ("main",),
                "landed": ("landed",)}


def events_from_states(time: object, states: object, height: object, velocity: Optional[object] = None
                       ) -> FlightEvents:
    """Events read off a flight computer's own logged states (AltOS ``state`` column).

    Parameters
    ----------
    time : array_like, shape (N,)
        s, the log's time.
    states : array_like of str, shape (N,)
        The state on each step (case is ignored), e.g. ``pad``, ``boost``,
        ``fast``, ``coast``, ``drogue``, ``main``, ``landed``.
    height : array_like, shape (N,)
        The flight computer's height, m above the pad (NaN where unknown).
    velocity : array_like, shape (N,), optional
        Its vertical velocity, m/s; dates ``max_speed`` (its largest value
        between launch and apogee) when given.

    Returns
    -------
    FlightEvents
        Each event at the first step of its state (:data:`STATE_EVENTS`),
        in flight order: an event is only looked for after the one before it.
    """
    t = np.asarray(time, dtype=np.float64)
    names = np.array([str(s).strip().lower() for s in np.asarray(states, dtype=object)])
    h = np.asarray(height, dtype=np.float64)
    v = None if velocity is None else np.asarray(velocity, dtype=np.float64)
    if not (t.shape == names.shape == h.shape) or t.ndim != 1 or (v is not None and v.shape != t.shape):
        raise ValueError("time, states, height (and velocity) must be 1-D of one length")
    found = {}
    start = 0
    for event, state_names in STATE_EVENTS.items():
        index = np.flatnonzero(np.isin(names[start:], state_names))
        if index.size == 0:
            break
        found[event] = start = int(index[0]) + start
    if v is not None and "launch" in found and np.isfinite(v).any():
        stop = found.get("apogee", t.size)
        part = v[found["launch"]:stop]
        if part.size and np.isfinite(part).any():
            found["max_speed"] = found["launch"] + int(np.nanargmax(part))
    events = []
    for name in EVENT_NAMES:
        if name in found:
            k = found[name]
            events.append(FlightEvent(name, True, k, float(t[k]), float(h[k]),
                                      float(v[k]) if v is not None else float("nan")))
        else:
            events.append(FlightEvent(name, False, 0, 0.0, 0.0, 0.0))
    return FlightEvents(events)


def flight_computer_events(data: object, pad_altitude: Optional[float] = None,
                           main_altitude: float = 250.0) -> Tuple[Optional[FlightEvents], str]:
    """The events of a log's own flight computer, to print next to ours, and how they were found.

    Parameters
    ----------
    data : fusion_altitude.logs.LogData
        A rocket log.
    pad_altitude : float, optional
        Datum of the log's reference altitude to subtract for heights above the
        pad, m; default the log's ``ground_altitude``, else the reference's
        first finite value.
    main_altitude : float, default 250
        m above the pad, for :func:`events_from_estimates`.

    Returns
    -------
    (FlightEvents or None, str)
        From the logged flight states (AltOS ``state``: :func:`events_from_states`)
        when they include ``boost``; else from the reference height and velocity
        (CATS ``flightInfo``: :func:`events_from_estimates`, its acceleration the
        time derivative of its velocity); (None, reason) when the log has neither.
    """
    time = np.asarray(data.time, dtype=np.float64)
    reference = getattr(data, "reference_altitude", None)
    velocity = getattr(data, "reference_velocity", None)
    height = None
    if reference is not None:
        reference = np.asarray(reference, dtype=np.float64)
        if pad_altitude is None:
            ground = getattr(data, "ground_altitude", None)
            finite = reference[np.isfinite(reference)]
            pad_altitude = float(ground) if ground is not None and np.isfinite(ground) else (
                float(finite[0]) if finite.size else 0.0)
        height = reference - pad_altitude
    states = getattr(data, "flight_state", None)
    if states is not None and any(str(s).strip().lower() == "boost" for s in np.unique(np.asarray(states, object))):
        h = height if height is not None else np.full(time.size, np.nan)
        return events_from_states(time, states, h, velocity), "its logged flight states"
    if height is not None and velocity is not None and np.isfinite(velocity).sum() >= 2:
        v = np.asarray(velocity, dtype=np.float64)
        finite = np.isfinite(v)
        filled = np.interp(time, time[finite], v[finite])
        acceleration = np.gradient(filled, time)
        events = events_from_estimates(time, height, filled, acceleration,
                                       main_altitude=main_altitude)
        return events, "read off its height and velocity (events_from_estimates)"
    return None, "the log has neither flight states nor the flight computer's height and velocity"


#: A pad window: the first this many s of a log are taken as at rest on the pad.
PAD_SECONDS = 1.0
#: s an along-axis accelerometer sample is held over steps without one; after its last sample and this long the
#: accelerometer has ended (NaN: the rocket estimator goes on baro-led).
ACCEL_HOLD = 1.0
#: An accelerometer column is taken as saturated where it stays within 0.1 % of its largest |value| on at least
#: this many samples, if that value is above 4 g.
SATURATION_SAMPLES = 3


def pad_levels(accel_body: object, time: Optional[object] = None, seconds: float = PAD_SECONDS
              ) -> Tuple[np.ndarray, np.ndarray]:
    """Median specific force per column over the pad window and which columns are alive.

    The median, not the mean: a log that starts less than ``seconds`` before
    the launch (the Hedy CATS log: 0.75 s) still gives the pad's reading.

    Parameters
    ----------
    accel_body : array_like, shape (N, 3) or (N,)
        Specific force, m/s².
    time : array_like, shape (N,), optional
        s; the window is the first ``seconds`` s (all samples if None).
    seconds : float
        s.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray of bool)
        The medians (m/s², NaN for a column without a finite sample in the
        window) and, per column, alive: at least two finite samples in the log
        and not constant (a dead axis logs one value, often 0).
    """
    array = np.asarray(accel_body, dtype=np.float64)
    array = array.reshape(array.shape[0], -1)
    window = np.ones(array.shape[0], dtype=bool)
    if time is not None:
        t = np.asarray(time, dtype=np.float64)
        window = t <= t[0] + seconds
    means = np.full(array.shape[1], np.nan)
    alive = np.zeros(array.shape[1], dtype=bool)
    for k in range(array.shape[1]):
        column = array[:, k]
        finite = column[np.isfinite(column)]
        alive[k] = finite.size >= 2 and float(np.ptp(finite)) > 0.0
        pad = column[window][np.isfinite(column[window])]
        if pad.size:
            means[k] = float(np.median(pad))
    return means, alive


def saturated_samples(specific_force: object, clipped: Optional[object] = None) -> np.ndarray:
    """Where an accelerometer column is at its range limit (bool per sample).

    ``clipped`` (a reader's flag, e.g. LogData.clipped) where given, or'ed with
    a plateau at the column's largest |value|: at least
    :data:`SATURATION_SAMPLES` samples within 0.1 % of it, that value above 4 g
    (a ±16 g IMU reads exactly ±156.9 m/s² through the thrust peak).
    """
    values = np.asarray(specific_force, dtype=np.float64)
    magnitude = np.abs(values)
    result = np.zeros(values.shape, dtype=bool) if clipped is None else np.asarray(clipped, dtype=bool).copy()
    if np.isfinite(magnitude).any():
        peak = float(np.nanmax(magnitude))
        plateau = np.isfinite(magnitude) & (magnitude >= 0.999 * peak)
        if peak > 4 * GRAVITY and plateau.sum() >= SATURATION_SAMPLES:
            result |= plateau
    return result


def _held(values: np.ndarray, time: np.ndarray, hold: float = ACCEL_HOLD) -> np.ndarray:
    """Each NaN step takes the latest finite sample if it is at most ``hold`` s old (NaN otherwise)."""
    finite = np.isfinite(values)
    index = np.where(finite, np.arange(values.size), -1)
    latest = np.maximum.accumulate(index)
    out = np.full(values.size, np.nan)
    ok = latest >= 0
    out[ok] = values[latest[ok]]
    out[ok & (time - time[np.maximum(latest, 0)] > hold)] = np.nan
    return out


def rocket_long_axis(accel_body, seconds_time=None, seconds: float = 1.0,
                     long_axis: Optional[Tuple[int, float]] = None) -> Tuple[int, float]:
    """The rocket's long axis in a body-frame accelerometer: (column, sign) of :func:`fusion_altitude.rocket.long_axis_accel`.

    On the pad the long axis is the one that carries gravity: among the live
    columns (not constant, not all NaN; any column if none is) the one with the largest median
    |specific force| over the first ``seconds`` s (all samples if
    ``seconds_time`` is None), signed so that it reads +g (nose up).

    Parameters
    ----------
    accel_body : array_like, shape (N, 3)
        Specific force, m/s², body frame.
    seconds_time : array_like, shape (N,), optional
        Sample times, s.
    seconds : float, default 1.0
        Length of the pad window, s.
    long_axis : (int, float), optional
        The user's (column, sign): checked against gravity instead of chosen.

    Raises
    ------
    LogError
        ``long_axis`` contradicts gravity on the pad: that axis does not read
        ≈ +9.81 m/s² (0.7–1.3 g) at rest, it is dead (constant), or another
        axis carries more than 0.5 g.
    """
    from .logs import LogError

    mean, alive = pad_levels(accel_body, seconds_time, seconds)
    if long_axis is not None:
        axis, sign = int(long_axis[0]), float(long_axis[1])
        name = f"{'+' if sign > 0 else '-'}{'XYZ'[axis]}"
        reading = sign * mean[axis]
        others = [(abs(mean[k]), k) for k in range(3) if k != axis and alive[k]]
        other, other_axis = max(others) if others else (0.0, axis)
        if not alive[axis]:
            raise LogError(f"long axis {name}: that accelerometer column is constant (dead); it cannot be the "
                           f"rocket's long axis")
        if not (0.7 * GRAVITY <= reading <= 1.3 * GRAVITY) or other > 0.5 * GRAVITY:
            carrier = (f"; {'XYZ'[other_axis]} reads {mean[other_axis]:+.2f} m/s² and carries gravity"
                       if other > 0.5 * GRAVITY else "")
            raise LogError(f"long axis {name} reads {reading:+.2f} m/s² at rest on the pad (first {seconds:g} s), "
                           f"not about +9.81: the nose-up axis reads +g at rest{carrier}")
        return axis, sign
    candidates = np.where(alive | ~alive.any(), np.abs(np.nan_to_num(mean)), -1.0)  # all columns dead: any
    axis = int(np.argmax(candidates))
    return axis, (1.0 if not mean[axis] < 0 else -1.0)


def rocket_accel_input(data: object, long_axis: Optional[Tuple[int, float]] = None) -> Tuple[np.ndarray, str]:
    """The rocket estimator's accel input for a log, and a one-line note of what it is.

    Parameters
    ----------
    data : fusion_altitude.logs.LogData
        A rocket log.
    long_axis : (int, float), optional
        The IMU column along the nose and its sign (``--long-axis``); checked
        against gravity on the pad (:func:`rocket_long_axis`).

    Returns
    -------
    (numpy.ndarray, str)
        m/s², the long-axis specific force minus g on every step; NaN where the
        rocket estimator must do without an accelerometer (from there on it is
        baro-led). In order of preference:

        1. ``baro_only`` logs: NaN throughout.
        2. ``axial_acceleration`` (the flight computer's along-axis, usually
           high-g, accelerometer) when alive and reading at least 0.5 g over
           the first second (≈ +g on the pad; more when the log starts in
           boost, as a Raven's export);
           held over steps without a sample for up to :data:`ACCEL_HOLD` s,
           NaN after its last sample (e.g. a Raven's that stops after 4.5 s).
        3. The raw IMU's long axis when alive (not constant) and reading
           ≈ +g (0.5–1.5 g) on the pad, NaN from its first saturated sample
           (:func:`saturated_samples`) on.
        4. The reader's vertical acceleration when it is not constant.
        5. NaN throughout (dead or missing accelerometer).

    Raises
    ------
    LogError
        ``long_axis`` contradicts gravity on the pad.
    """
    time = np.asarray(data.time, dtype=np.float64)
    none = np.full(time.size, np.nan)
    if getattr(data, "baro_only", False):
        return none, "rocket estimator: no accelerometer in the log: baro-only flight (events from the baro)"
    skipped: List[str] = []
    axial = getattr(data, "axial_acceleration", None)
    if axial is not None:
        found = _axial_accel(np.asarray(axial, dtype=np.float64), time, skipped)
        if found is not None:
            return found
    if data.accel is not None:
        found = _imu_accel(np.asarray(data.accel, dtype=np.float64), time, long_axis, getattr(data, "clipped", None),
                           skipped)
        if found is not None:
            return found
    elif not skipped:
        vertical = np.asarray(data.vertical_acceleration, dtype=np.float64)
        if pad_levels(vertical, time)[1][0]:
            return vertical, "rocket estimator: the reader's vertical acceleration, taken along the long axis"
        skipped.append("its vertical acceleration is constant")
    return none, f"rocket estimator: no usable accelerometer ({'; '.join(skipped)}): baro-led flight (events from the baro)"


def _axial_accel(axial: np.ndarray, time: np.ndarray, skipped: List[str]) -> Optional[Tuple[np.ndarray, str]]:
    """:func:`rocket_accel_input` from the flight computer's along-axis accelerometer (m/s²), or None with the
    reason appended to ``skipped``."""
    mean, alive = pad_levels(axial, time)
    if alive[0] and mean[0] >= 0.5 * GRAVITY:  # more than +g when the log starts in boost (a Raven's)
        return _held(axial, time) - GRAVITY, "rocket estimator: the flight computer's along-axis accelerometer"
    skipped.append("its along-axis accelerometer is dead" if not alive[0] else
                   f"its along-axis accelerometer reads {mean[0]:+.2f} m/s² on the pad, not +g")
    return None


def _imu_accel(accel: np.ndarray, time: np.ndarray, long_axis: Optional[Tuple[int, float]], clipped,
               skipped: List[str]) -> Optional[Tuple[np.ndarray, str]]:
    """:func:`rocket_accel_input` from the raw IMU's long axis (m/s², NaN from its first saturated sample), or
    None with the reason appended to ``skipped``."""
    axis, sign = rocket_long_axis(accel, time, long_axis=long_axis)
    mean, alive = pad_levels(accel, time)
    name = f"{'+' if sign > 0 else '-'}{'XYZ'[axis]}"
    if alive[axis] and 0.5 * GRAVITY <= sign * mean[axis] <= 1.5 * GRAVITY:
        values = long_axis_accel(accel, axis, sign)
        saturated = saturated_samples(accel[:, axis], clipped)
        if saturated.any():
            first = int(np.argmax(saturated))
            values[first:] = np.nan
            return values, (f"rocket estimator: IMU axis {name}, saturated from t = {time[first]:.2f} s on: "
                            f"baro-led from there")
        return values, f"rocket estimator: IMU axis {name}"
    skipped.append("the IMU is dead (constant)" if not alive.any() else
                   f"no IMU axis reads +g on the pad (means {', '.join(f'{m:+.2f}' for m in mean)} m/s²)")
    return None
