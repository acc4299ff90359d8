"""Per-estimator adapters, each with its registry row: an adapter feeds one estimator what a recorded log
(:class:`fusion_altitude.logs.LogData`) has, on the log's own time grid, and returns its per-sample outputs (a
NamedTuple with at least ``altitude``, m, and ``vertical_velocity``, m/s).

Each adapter carries the estimator's row of the registry (:mod:`fusion_altitude.estimators`) in its
:func:`registry_row` decorator: its CLI name, description, label, class, needs, vehicle, and whether it fuses GPS,
takes the observer's presets or has a gap period. The decorated adapters are :data:`ADAPTERS`, in table order; the
registry makes one :class:`~fusion_altitude.estimators.EstimatorEntry` of each, and
:func:`fusion_altitude.runner.run_log` calls the adapter. Adding an estimator to ``run``, ``compare LOG``, the fleet
and the output CSV is one decorated adapter here.
"""

from __future__ import annotations

from typing import Callable, List, NamedTuple, Optional

import numpy as np

from ._core._observer import AltitudeEstimator, AltitudeSettings
from ._core._observer_glue import AltitudeBatch
from .logs import LogData
from .tuning import (baro_interval, baro_timeout_for, bandwidth_of, gap_period_for, other_fields, sample_periods,
                     settings_for_baro_rate, steps_per_baro)

__all__ = ["ObserverLogBatch", "InsLogBatch", "RocketLogBatch", "ALPHABETA_BARO_WINDOW",
           "ALPHABETA_GPS_FALLBACK_CONFIDENCE", "ADAPTERS", "registry_row", "DEFAULT_PRESET_ORDER", "default_preset",
           "run_observer_log", "run_kalman_log", "run_complementary_log", "run_alphabeta_log", "run_ins_log",
           "run_rocket_log", "run_observer", "alphabeta_log_sensors"]

#: The built-in adapters in table order, each with its ``registry_row`` (the registry's rows).
ADAPTERS: List[Callable[[LogData, np.ndarray, dict], object]] = []


def registry_row(name: str, description: str, **columns) -> Callable:
    """Decorate an adapter ``run(data, dt, options)`` with its estimator's registry row and add it to
    :data:`ADAPTERS`: ``name`` (``--estimator``), ``description`` (one line: what it is, which sensors it uses) and
    the other columns of :class:`~fusion_altitude.estimators.EstimatorEntry` by keyword (``label``,
    ``estimator_class``, ``needs``, ``vehicle``, ``uses_gps``, ``takes_preset``, ``has_gap_period``)."""
    def mark(adapter: Callable) -> Callable:
        adapter.registry_row = dict(name=name, description=description, **columns)
        ADAPTERS.append(adapter)
        return adapter
    return mark


# ----------------------------------------------------------------------------
# the observer's default preset

#: The presets the default rule tries, fastest first (:func:`default_preset`).
DEFAULT_PRESET_ORDER = ("vtol", "fixed_wing", "balloon")


def default_preset(data: LogData) -> str:
    """The observer preset used when none is given: the fastest of ``vtol``, ``fixed_wing``, ``balloon`` whose
    gains the core's stability rule accepts at the log's baro period (:func:`fusion_altitude.tuning.baro_interval`:
    the median time between baro samples where the baro is present), i.e. Jury's test with the 1.5 margin of
    ``FusionAltitudeIsStepStable`` for the observer sampled at the baro rate (the gains are scaled to it,
    :func:`fusion_altitude.tuning.settings_for_baro_rate`). ``balloon`` when none is (a baro slower than one
    sample in 3.1 s), ``vtol`` without two baro samples.

    With a 2 Hz baro (0.5 s) the VTOL gains are past that limit (0.41 s): they passed plain Jury (0.62 s) and ran
    at Kh·T = 1.2, a correction that overshoots every baro sample, so the observer was worse than the raw baro
    (0.729 m against 0.455 m on ``px4_octorotor_2hz_baro.ulg``); fixed_wing is chosen there now."""
    from .reference.observer import step_stable

    period = baro_interval(data.time, data.baro_altitude)
    if not np.isfinite(period) or not period > 0:
        return "vtol"
    period32 = np.float32(period)
    for name in DEFAULT_PRESET_ORDER:
        gains = tuple(np.float32(g) for g in AltitudeSettings.preset(name).as_tuple())
        if step_stable(*gains, period32, period32):
            return name
    return "balloon"


def _optional(data: LogData, name: str) -> Optional[np.ndarray]:
    """A per-sample field of the log if the reader filled it (fields land in LogData over time)."""
    value = getattr(data, name, None)
    if value is None:
        return None
    value = np.asarray(value)
    return value if value.ndim == 1 and value.size == data.time.size else None


def _gaps(options: dict, estimator, gap_period: float) -> None:
    """Put the gap period used (s) and the estimator's gap counter into ``options`` (they land in the LogRun)."""
    options["gap_period"] = float(np.float32(gap_period))
    options["gap_count"] = int(estimator.gap_count)


class ObserverLogBatch(NamedTuple):
    """The observer's outputs on a log (:class:`fusion_altitude.AltitudeBatch`) and ``baro_aided``: 1 where a
    baro sample came within the baro timeout, 0 where the estimate is not baro-aided (the velocity decays, the
    acceleration is not integrated: see ``FusionAltitudeUpdate``)."""

    altitude: np.ndarray
    vertical_velocity: np.ndarray
    accel_bias: np.ndarray
    baro_residual: np.ndarray
    baro_aided: np.ndarray


def _baro_timeout_warning(name: str, time: np.ndarray, dt, baro, timeout: float, timeouts: int) -> Optional[np.ndarray]:
    """Warn (one line, :class:`fusion_altitude.logs.LogWarning`) when the estimator timed out; the per-sample
    not-baro-aided mask (None without a timeout)."""
    import warnings

    from .logs import LogWarning
    from .tuning import not_baro_aided

    if not timeouts:
        return None
    mask = not_baro_aided(dt, baro, timeout)
    if mask.any():
        first = int(np.argmax(mask))
        warnings.warn(f"{name}: no baro sample for more than {timeout:.3g} s {timeouts} time(s), first from "
                      f"t = {float(time[first]) - timeout:.1f} s: {int(np.count_nonzero(mask))} samples are not "
                      "baro-aided (velocity decayed to 0, column baro_aided = 0)", LogWarning, stacklevel=3)
    return mask


@registry_row("observer", "3rd-order complementary observer (baro + accel)", estimator_class="AltitudeEstimator",
              takes_preset=True, has_gap_period=True)
def run_observer_log(data: LogData, dt: np.ndarray, options: dict):
    settings = options.get("settings")
    if settings is None:
        settings = AltitudeSettings.preset(default_preset(data))
    info = options if options is not None else {}
    result = run_observer(data.time, data.vertical_acceleration, data.baro_altitude, settings,
                          clipped=data.clipped, progress=options.get("progress"), dt=dt, info=info,
                          steps=options.get("steps_per_baro"))
    mask = _baro_timeout_warning("observer", data.time, dt, data.baro_altitude, info["baro_timeout"],
                                 info["baro_timeouts"])
    aided = np.ones(data.time.size, np.int64) if mask is None else (~mask).astype(np.int64)
    return ObserverLogBatch(*result, aided)


@registry_row("kalman", "Kalman filter (baro + accel, GPS altitude with its fix quality, rangefinder)", label="Kalman",
              estimator_class="KalmanEstimator", uses_gps=True, has_gap_period=True)
def run_kalman_log(data: LogData, dt: np.ndarray, options: dict):
    from ._core._kalman import KalmanEstimator

    gps = _optional(data, "gps_altitude")
    satellites = _optional(data, "gps_satellites")
    accuracy = _optional(data, "gps_accuracy")
    if satellites is not None:  # float, NaN where unknown (what the binding takes: NaN → unknown)
        satellites = satellites.astype(float)
    # every argument after accel by keyword: valid in the old (accel, dt, ...) and the new (accel, baro_altitude,
    # dt, ...) argument order alike
    settings = options.get("kalman_settings")
    if settings is None and getattr(data, "vehicle", None) == "rocket":
        # The rocket settings follow a rocket flight a little better than the general defaults (on the Hedy
        # flight 14.36 m against 15.88 m RMS; docs/kalman.md, "Real rocket log").
        from .rocket import rocket_kalman_settings
        settings = rocket_kalman_settings()
    if settings is None:
        from ._core._kalman import KalmanSettings
        settings = KalmanSettings()
    settings = settings.replace(gap_period=gap_period_for(dt, settings.gap_period))
    estimator = KalmanEstimator(settings)
    result = estimator.update_batch(
        data.vertical_acceleration, dt=dt, baro_altitude=data.baro_altitude,
        range_distance=_optional(data, "rangefinder"), gps_altitude=gps,
        gps_satellites=satellites if gps is not None else None,
        gps_vertical_accuracy=accuracy if gps is not None else None)
    _gaps(options, estimator, settings.gap_period)
    counts = estimator.timeout_counts
    if counts.baro:
        rangefinder = _optional(data, "rangefinder")
        live = [name for name, samples, count in (("rangefinder", rangefinder, counts.range), ("GPS", gps, counts.gps))
                if samples is not None and np.isfinite(samples).any() and count == 0]
        carried = f"carried by the {' and '.join(live)}" if live else "dead-reckoned from the accelerometer"
        _timeout_warning(data, f"kalman: the baro timed out {counts.baro} time(s) (no sample for > "
                               f"{settings.baro_timeout:g} s): the altitude there is {carried}")
    _done(options, data.time.size)
    return result


@registry_row("complementary", "two-stage complementary filter (baro + accel)", estimator_class="ComplementaryFilter",
              has_gap_period=True)
def run_complementary_log(data: LogData, dt: np.ndarray, options: dict):
    from ._core._complementary import ComplementaryFilter, ComplementarySettings

    settings = ComplementarySettings()
    settings = settings.replace(gap_period=gap_period_for(dt, settings.gap_period),
                                baro_timeout=baro_timeout_for(data.time, data.baro_altitude, settings.baro_timeout))
    estimator = ComplementaryFilter(settings)
    result = estimator.update_batch(data.vertical_acceleration, data.baro_altitude, dt)
    _gaps(options, estimator, settings.gap_period)
    mask = _baro_timeout_warning("complementary", data.time, dt, data.baro_altitude, settings.baro_timeout,
                                 estimator.baro_timeouts)
    _done(options, data.time.size)
    if mask is None:
        return result
    fields = dict(result._asdict(), baro_aided=(~mask).astype(np.int64))
    return NamedTuple("ComplementaryLogBatch", [(name, np.ndarray) for name in fields])(**fields)


@registry_row("alphabeta", "quality-weighted alpha-beta fusion (baro, rangefinder, GPS shifted onto the baro datum + "
                           "accel)", label="alpha-beta", estimator_class="AlphaBetaFusion", uses_gps=True,
              has_gap_period=True)
def run_alphabeta_log(data: LogData, dt: np.ndarray, options: dict):
    import math

    from ._core._alphabeta import AlphaBetaFusion, AlphaBetaSettings

    # a log's altitudes are above sea level (or any datum) and may dip below the start: the altitude windows of
    # the defaults (made for heights above a take-off point) are opened for the imu, baro and GPS
    settings = AlphaBetaSettings(**{s: {"altitude_min": -math.inf, "altitude_max": math.inf}
                                    for s in ("imu", "baro", "gps")})
    settings = settings.replace(**alphabeta_log_sensors(data, settings))
    gap_period = gap_period_for(dt, settings.gap_period)
    if gap_period > settings.gap_period:  # a slow log: each sensor's timeout at least the gap period too
        settings = settings.replace(gap_period=gap_period, **{
            name: {"timeout": max(getattr(settings, name).timeout, gap_period)}
            for name in ("imu", "baro", "lidar", "sonar", "gps")})
    fusion = AlphaBetaFusion(settings)
    result = fusion.update_batch(data.vertical_acceleration, dt=dt, baro_altitude=data.baro_altitude,
                                                    lidar_altitude=_optional(data, "rangefinder"),
                                                    gps_altitude=_gps_on_baro_datum(data))
    _gaps(options, fusion, settings.gap_period)
    counts = fusion.timeout_counts
    if counts.baro:
        others = [name for name, column in (("rangefinder", 2), ("GPS", 4)) if np.any(result.weight[:, column] > 0)]
        carried = f"carried by the {' and '.join(others)}" if others else "dead-reckoned, then held (no other height source)"
        _timeout_warning(data, f"alphabeta: the baro timed out {counts.baro} time(s) (no sample for > "
                               f"{settings.baro.timeout:g} s): the altitude there is {carried}")
    _done(options, data.time.size)
    return result


def _timeout_warning(data: LogData, message: str) -> None:
    """A one-line warning about a sensor timeout, printed by ``run`` with the log's warnings (once per message)."""
    warnings = getattr(data, "warnings", None)
    if isinstance(warnings, list) and message not in warnings:
        warnings.append(message)


#: s of baro samples the α-β fusion's baro filter spans at most on a log: the write-up's Qmax of 60 samples at the
#: 20 Hz of an autopilot baro (a line fitted over 3 s of flight)
ALPHABETA_BARO_WINDOW = 3.0

#: The α-β fusion's GPS confidence on a log that has a baro (the write-up's is 1): the GPS is the fallback height
#: source, as in PX4's EKF2 and ArduPilot's EKF3 (the baro is the height reference, GPS height takes over when it
#: stops): at most 120 × 0.01 = 1.2 against the baro's 20–120 while the baro is live, all the weight but the IMU
#: channel's once the baro times out.
ALPHABETA_GPS_FALLBACK_CONFIDENCE = 0.01


def alphabeta_log_sensors(data: LogData, settings) -> dict:
    """The α-β fusion's per-sensor changes for a log (docs/hobby_estimators.md, "On real logs").

    - A baro slower than 20 Hz keeps the write-up's 3 s filter span rather than its 60 samples:
      ``quality_max = max(quality_min, round(ALPHABETA_BARO_WINDOW × baro rate))`` (10 at 2 Hz, a 5 s span with
      Qmin 10); 60 samples of a 2 Hz baro fit a line to 30 s of flight and lag every climb.
    - With a baro, the GPS has confidence :data:`ALPHABETA_GPS_FALLBACK_CONFIDENCE`: the write-up lets a 10 m GPS
      reach the weight of a coherent baro (Qmax 120 × confidence 1 = 60 × 2), and on
      ``px4_octorotor_2hz_baro.ulg`` (GPS 4.1 m RMS from the autopilot's estimate, 8.8 m reported accuracy) it
      pulled the fusion to 4.62 m RMS against the raw baro's 0.455 m.
    """
    changes: dict = {}
    baro = np.asarray(data.baro_altitude, float)
    has_baro = np.flatnonzero(np.isfinite(baro))
    if has_baro.size >= 2:
        period = float(np.median(np.diff(data.time[has_baro])))
        if period > 0:
            quality_max = max(settings.baro.quality_min,
                              min(settings.baro.quality_max, int(round(ALPHABETA_BARO_WINDOW / period))))
            changes["baro"] = {"quality_max": quality_max}
    if has_baro.size:
        changes["gps"] = {"confidence": ALPHABETA_GPS_FALLBACK_CONFIDENCE}
    return changes


def _gps_on_baro_datum(data: LogData, seconds: float = 5.0) -> Optional[np.ndarray]:
    """The log's GPS altitude shifted onto the baro's datum (the α-β fusion has no GPS-offset state, unlike the
    Kalman filter): minus the median of GPS − baro over the first ``seconds`` s in which both have samples
    (the baro held to each GPS step). None without GPS or without an overlap."""
    gps = _optional(data, "gps_altitude")
    if gps is None:
        return None
    baro = np.asarray(data.baro_altitude, float)
    has_baro = np.flatnonzero(np.isfinite(baro))
    has_gps = np.flatnonzero(np.isfinite(gps))
    if has_baro.size == 0 or has_gps.size == 0:
        return None
    held = baro[has_baro[np.clip(np.searchsorted(has_baro, has_gps, side="right") - 1, 0, has_baro.size - 1)]]
    both = has_gps[has_gps >= has_baro[0]]
    if both.size == 0:
        return None
    early = data.time[has_gps] <= data.time[both[0]] + seconds
    early &= has_gps >= has_baro[0]
    return gps - float(np.median(gps[has_gps][early] - held[early]))


class InsLogBatch(NamedTuple):
    """The INS on a log, per grid step, as ``run -o`` writes it (float32).

    Attributes
    ----------
    altitude : numpy.ndarray
        m, +up, on the baro's datum: the INS height plus its baro bias (what
        the baro would read without noise), comparable with the log's own
        estimate and the other estimators.
    vertical_velocity : numpy.ndarray
        m/s, +up.
    height : numpy.ndarray
        m, the INS's own height above its reference d (``InsBatch.height_above_start``).
    roll, pitch, yaw : numpy.ndarray
        Local attitude, degrees (ZYX Euler, body → local NWU earth; yaw starts
        at 0 and is integrated).
    quaternion_w, quaternion_x, quaternion_y, quaternion_z : numpy.ndarray
        Local attitude quaternion, body → local NWU earth.
    gyro_bias_x, gyro_bias_y, gyro_bias_z : numpy.ndarray
        Gyroscope bias, rad/s, body frame: the log's own axes (``LogData.imu_frame``),
        except FRD logs (PX4, ArduPilot), which are turned into FLU (x forward,
        y left, z up: y and z negated) before the INS sees them.
    accel_z_bias : numpy.ndarray
        Accelerometer bias along body z, m/s² (learned while stationary).
    baro_bias : numpy.ndarray
        m: the baro altitude at height 0 (learned while stationary).
    is_stationary : numpy.ndarray of bool
        The INS's stationary detection.
    baro_timed_out : numpy.ndarray of bool
        Not baro-aided: no baro reading for longer than the INS's ``baro_timeout`` (s); beyond its
        ``dead_reckoning_horizon`` the height is held, not dead-reckoned (docs/ins.md).
    """

    altitude: np.ndarray
    vertical_velocity: np.ndarray
    height: np.ndarray
    roll: np.ndarray
    pitch: np.ndarray
    yaw: np.ndarray
    quaternion_w: np.ndarray
    quaternion_x: np.ndarray
    quaternion_y: np.ndarray
    quaternion_z: np.ndarray
    gyro_bias_x: np.ndarray
    gyro_bias_y: np.ndarray
    gyro_bias_z: np.ndarray
    accel_z_bias: np.ndarray
    baro_bias: np.ndarray
    is_stationary: np.ndarray
    baro_timed_out: np.ndarray


@registry_row("ins", "inertial navigation filter (raw gyro + accelerometer + baro; attitude, gyro bias, baro bias)",
              needs=("gyro", "accel"), label="INS", estimator_class="InsEstimator")
def run_ins_log(data: LogData, dt: np.ndarray, options: dict) -> InsLogBatch:
    from ._core._ins import InsEstimator, InsSettings

    gyro, accel = np.asarray(data.gyro, float), np.asarray(data.accel, float)
    if data.imu_frame == "FRD":  # to FLU (x forward, y left, z up): a level vehicle then reads roll 0, not ±180°
        flip = np.array([1.0, -1.0, -1.0])
        gyro, accel = gyro * flip, accel * flip
    settings = options.get("ins_settings") or InsSettings()
    # the rule of every estimator (tuning.gap_period_for): on a slow log (an IMU at 10 Hz or less) each step would
    # exceed the 0.1 s default and the INS would never integrate
    ins = InsEstimator(settings.replace(gap_period=gap_period_for(dt, settings.gap_period)))
    batch = ins.update_batch(gyro, accel, dt, data.baro_altitude)
    _gaps(options, ins, ins.settings.gap_period)
    options["baro_rejections"], options["baro_resets"] = int(ins.baro_rejections), int(ins.baro_resets)
    if ins.baro_timeouts:
        silent = int(np.count_nonzero(batch.baro_timed_out))
        _timeout_warning(data, f"INS: the baro timed out {ins.baro_timeouts} time(s) (no reading for > "
                               f"{ins.settings.baro_timeout:g} s): {silent} samples not baro-aided (column "
                               f"baro_timed_out); beyond {ins.settings.dead_reckoning_horizon:g} s the height is held, "
                               "not dead-reckoned")
    _done(options, data.time.size)
    euler = batch.euler.astype(np.float32)
    return InsLogBatch(batch.altitude, batch.vertical_velocity, batch.height_above_start,
                       euler[:, 0], euler[:, 1], euler[:, 2], *(batch.quaternion[:, i] for i in range(4)),
                       *(batch.gyro_bias[:, i] for i in range(3)), batch.accel_z_bias, batch.baro_bias,
                       batch.is_stationary, batch.baro_timed_out)


class RocketLogBatch(NamedTuple):
    """The rocket estimator on a log, per grid step, as ``run -o`` writes it.

    Attributes
    ----------
    altitude : numpy.ndarray
        float32, m, on the baro's datum: the pad altitude learned on the pad
        plus ``height`` (comparable with the log's own estimate).
    vertical_velocity : numpy.ndarray
        float32, m/s, +up.
    height : numpy.ndarray
        float32, m above the pad.
    accel_bias : numpy.ndarray
        float32, the accelerometer bias in use, m/s² (pad-learned).
    phase : numpy.ndarray
        uint8, :class:`fusion_altitude.rocket.Phase` after each step.
    baro_fate : numpy.ndarray
        uint8, :class:`fusion_altitude.rocket.BaroFate` of each step's baro sample.
    """

    altitude: np.ndarray
    vertical_velocity: np.ndarray
    height: np.ndarray
    accel_bias: np.ndarray
    phase: np.ndarray
    baro_fate: np.ndarray


@registry_row("rocket", "rocket estimator (long-axis accel + baro: pad calibration, baro lockout, "
                        "flight events)", vehicle="rocket", estimator_class="RocketEstimator")
def run_rocket_log(data: LogData, dt: np.ndarray, options: dict) -> RocketLogBatch:
    """The rocket estimator on a log; its accelerometer input is chosen by :func:`fusion_altitude.rocket.rocket_accel_input`
    (NaN where the rocket estimator must do without one: baro-led), and what was chosen goes to ``data.notes``."""
    from ._core._rocket import RocketEstimator
    from .rocket import rocket_accel_input

    accel, note = rocket_accel_input(data, options.get("long_axis"))
    if note not in data.notes:
        data.notes.append(note)
    options["rocket_input"] = note
    estimator = RocketEstimator(options.get("rocket_settings"))
    result = estimator.update_batch(accel, data.baro_altitude, dt)
    options["gap_count"] = int(estimator.gap_count)
    _done(options, data.time.size)
    options["events"] = estimator.events.with_times(data.time)
    pad = float(estimator.pad_altitude)
    return RocketLogBatch(np.float32(pad) + result.height, result.vertical_velocity, result.height,
                          result.accel_bias, result.phase, result.baro)


def _done(options: dict, n: int) -> None:
    if options.get("progress") is not None:
        options["progress"](n, n)


def run_observer(time, vertical_acceleration, baro_altitude, settings: Optional[AltitudeSettings] = None,
                 clipped=None, clipped_settings: Optional[AltitudeSettings] = None,
                 progress: Optional[Callable[[int, int], None]] = None, chunk: int = 50_000,
                 compensate_baro_rate: bool = True, dt=None, info: Optional[dict] = None,
                 steps: Optional[float] = None) -> AltitudeBatch:
    """Run the observer over a log with irregular timestamps and missing baro samples.

    Parameters
    ----------
    time : array_like
        Sample times, s, strictly increasing; dt[i] = time[i] − time[i−1] (the first step uses the second
        step's dt; it only sets the reference).
    vertical_acceleration : array_like
        m/s², +up, gravity removed.
    baro_altitude : array_like
        m; NaN where there is no baro sample.
    settings : AltitudeSettings, optional
        Gains; default the VTOL preset.
    clipped : array_like of bool, optional
        Samples whose accelerometer reading hit its range. See Notes.
    clipped_settings : AltitudeSettings, optional
        Gains on clipped samples; default :func:`clipping_settings` of ``settings`` (the position loop 4×
        faster, ω·4 and ζ 0.7, and **bias estimation off**, Kb = 0).
    progress : callable(done, total), optional
        Called after each chunk of samples.
    compensate_baro_rate : bool, default True
        Scale the gains by (samples / baro samples) when the baro is slower than the grid
        (:func:`fusion_altitude.tuning.settings_for_baro_rate`), so ``settings`` keeps its designed bandwidth.
    dt : array_like, optional
        Per-sample periods, s; default :func:`sample_periods` of ``time``. The gap period used is
        ``max(settings.gap_period, 10 × nominal dt)`` (:func:`fusion_altitude.tuning.gap_period_for`), the
        baro timeout ``max(settings.baro_timeout, 5 × the baro period)`` (:func:`~fusion_altitude.tuning.baro_timeout_for`).
    steps : float, optional
        Grid steps per baro sample when the caller has it (:attr:`fusion_altitude.estimators.ObserverRate.steps_per_baro`);
        computed from ``baro_altitude`` if None.
    info : dict, optional
        Receives ``gap_period`` (s, as float32 holds it), ``gap_count``, ``baro_timeout`` (s) and ``baro_timeouts``.

    Returns
    -------
    AltitudeBatch

    Notes
    -----
    **Clipping.** A clipped accelerometer under-reports, and the observer would integrate that error into its bias
    estimate. On clipped samples it therefore keeps the clipped reading (a lower bound), switches to baro-trusting
    gains and freezes the bias (Kb = 0) so the bias learned before the clipping survives it; the normal gains
    return on the first unclipped sample, with the state carried over.
    """
    time = np.asarray(time, dtype=float)
    baro = np.asarray(baro_altitude, dtype=float)
    dt = sample_periods(time) if dt is None else np.asarray(dt, dtype=float)
    estimator = AltitudeEstimator(_log_settings(settings or AltitudeSettings(), time, baro, dt,
                                                compensate_baro_rate, steps))
    clipped = np.zeros(time.size, dtype=bool) if clipped is None else np.asarray(clipped, dtype=bool)
    out = _run_clipping_segments(estimator, clipped_settings, clipped, np.asarray(vertical_acceleration, dtype=float),
                                 baro, dt, chunk, progress)
    if info is not None:
        _observer_info(info, estimator)
    return out


def _observer_info(info: dict, estimator: AltitudeEstimator) -> None:
    """Put the gap period (s, float32) and count, the baro timeout (s) and the baro timeouts into ``info``."""
    _gaps(info, estimator, estimator.settings.gap_period)
    info["baro_timeout"] = float(np.float32(estimator.settings.baro_timeout))
    info["baro_timeouts"] = int(estimator.baro_timeouts)


def _log_settings(settings: AltitudeSettings, time: np.ndarray, baro: np.ndarray, dt: np.ndarray,
                  compensate_baro_rate: bool, steps: Optional[float]) -> AltitudeSettings:
    """``settings`` for this log: its gap period and baro timeout widened to the log's rates, and the gains
    scaled to its baro rate when asked (see :func:`run_observer`)."""
    settings = settings.replace(gap_period=gap_period_for(dt, settings.gap_period),
                                baro_timeout=baro_timeout_for(time, baro, settings.baro_timeout))
    if compensate_baro_rate:
        settings = settings_for_baro_rate(settings, steps_per_baro(baro) if steps is None else steps)
    return settings


def clipping_settings(settings: AltitudeSettings) -> AltitudeSettings:
    """The gains :func:`run_observer` uses on clipped samples by default: ``settings``' other fields with the
    position loop 4× faster (ω·4 rad/s, ζ 0.7) and bias estimation off (ω_b = 0)."""
    return AltitudeSettings.from_bandwidth(4 * bandwidth_of(settings), 0.7, 0.0, **other_fields(settings))


def _run_clipping_segments(estimator: AltitudeEstimator, clipped_settings: Optional[AltitudeSettings],
                           clipped: np.ndarray, accel: np.ndarray, baro: np.ndarray, dt: np.ndarray, chunk: int,
                           progress: Optional[Callable[[int, int], None]]) -> AltitudeBatch:
    """Run ``estimator`` over segments of constant clipping state (``clipped_settings``, default
    :func:`clipping_settings`, on clipped ones, its own settings elsewhere), cut into chunks of ``chunk``
    samples for ``progress(done, total)``; the estimator ends with its own settings."""
    n = accel.size
    normal = estimator.settings
    if clipped.any() and clipped_settings is None:
        clipped_settings = clipping_settings(normal)
    out = AltitudeBatch(*(np.empty(n, dtype=np.float32) for _ in range(4)))
    edges = np.flatnonzero(np.diff(clipped.astype(np.int8))) + 1
    bounds = np.unique(np.concatenate([[0], edges, np.arange(0, n, chunk), [n]]))
    for start, stop in zip(bounds[:-1], bounds[1:]):
        estimator.settings = clipped_settings if clipped[start] else normal
        views = AltitudeBatch(*(array[start:stop] for array in out))
        estimator.update_batch(accel[start:stop], baro[start:stop], dt[start:stop], out=views)
        if progress is not None:
            progress(int(stop), n)
    estimator.settings = normal
    return out
