"""Running any estimator on a recorded log (:class:`fusion_altitude.logs.LogData`) and writing the results.

Estimator registry
------------------
:data:`ESTIMATORS` maps a name (the CLI's ``--estimator`` choice) to an
:class:`EstimatorEntry`: a one-line description and a function
``run(data, dt, options) -> batch`` that feeds the estimator what the log
has and returns its batch outputs (a NamedTuple of per-sample arrays with at
least ``altitude`` (m) and ``vertical_velocity`` (m/s)). Adding an estimator
to ``run``, ``compare LOG`` and the output CSV is one call::

    from fusion_altitude import runner

    def _run_ins(data, dt, options):
        return InsEstimator().update_batch(...)      # any NamedTuple with altitude, vertical_velocity

    runner.register_estimator(runner.EstimatorEntry("ins", "inertial filter (raw gyro + accel + baro)", _run_ins))

Every 1-D numeric field of the batch (float, integer or boolean, e.g. a
flight-phase code) becomes a column of :func:`write_csv`.

Baro-rate compensation
----------------------
The observer's gains are scaled by :func:`fusion_altitude.tuning.settings_for_baro_rate`
when the baro is slower than the accelerometer grid; ``run``, ``fit`` and
``compare`` all go through :func:`fusion_altitude.tuning.steps_per_baro`, so
the three agree on what a setting scores.

Gap period
----------
Every estimator with a gap period (observer, Kalman, complementary,
alpha-beta) runs with ``max(its default, 10 × the log's nominal period)``
(:func:`fusion_altitude.tuning.gap_period_for`), so a slow log (a 1 Hz CSV)
is integrated rather than treated as one gap per step, and a real logging
gap stays a gap at any rate. ``LogRun.gap_period`` and ``LogRun.gap_count``
say what was used and how many gaps the estimator met.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Dict, List, NamedTuple, Optional, Tuple

import numpy as np

from ._core._observer import AltitudeEstimator, AltitudeSettings
from ._core._observer_glue import AltitudeBatch
from .logs import LogData
from .metrics import ErrorStatistics, error_statistics
from .rocket import rocket_long_axis
from .outputs import atomic_output, csv_columns, is_special_output, write_csv
from .tuning import (_bandwidth_of, _other_fields, baro_interval, baro_timeout_for, gap_period_for, settings_for_baro_rate,
                     steps_per_baro)

__all__ = ["LogRun", "EstimatorEntry", "ESTIMATORS", "register_estimator", "estimator_names", "applicable_estimators",
           "missing_inputs", "default_preset", "InsLogBatch", "RocketLogBatch", "rocket_long_axis", "run_observer",
           "sample_periods", "nominal_period", "run_log", "above_start", "write_csv", "atomic_output",
           "is_special_output",
           "csv_columns"]


@dataclass
class LogRun(LogData):
    """A :class:`LogData` with one estimator's outputs.

    Attributes
    ----------
    estimate : NamedTuple
        The estimator's batch outputs, per grid step (``altitude`` m,
        ``vertical_velocity`` m/s, and the estimator's own fields).
    estimator : str
        The registry name of the estimator that produced ``estimate``.
    datum : float
        Altitude subtracted from every altitude column (m): 0, or the start
        (pad) altitude with ``agl=True`` (see :func:`above_start`).
    events : fusion_altitude.rocket.FlightEvents or None
        The flight events of the ``rocket`` estimator (times in the log's
        seconds, heights m above the pad); None for the other estimators.
    gap_period : float or None
        s: the gap period the estimator ran with (see the module's "Gap
        period"); None for an estimator that does not report it.
    gap_count : int or None
        Updates the estimator treated as gaps (dt > its gap period); None
        for an estimator without a gap counter.
    baro_rejections, baro_resets : int or None
        The INS's baro innovation gate: readings rejected, and height resets
        after a rejection streak longer than its timeout; None for the other
        estimators.
    """

    estimate: Optional[object] = None
    estimator: str = "observer"
    datum: float = 0.0
    events: Optional[object] = None
    gap_period: Optional[float] = None
    gap_count: Optional[int] = None
    baro_rejections: Optional[int] = None
    baro_resets: Optional[int] = None

    def comparison(self, transient: float = 0.0) -> Optional[ErrorStatistics]:
        """Statistics of estimate − reference altitude (m) after ``transient`` s; None without a reference."""
        if self.reference_altitude is None:
            return None
        return error_statistics(self.time, np.asarray(self.estimate.altitude, float) - self.reference_altitude,
                                transient)

    def baro_comparison(self, transient: float = 0.0) -> Optional[ErrorStatistics]:
        """Statistics of baro − reference altitude (m) after ``transient`` s; None without a reference."""
        if self.reference_altitude is None:
            return None
        return error_statistics(self.time, self.baro_altitude - self.reference_altitude, transient)


# ----------------------------------------------------------------------------
# the registry


@dataclass(frozen=True)
class EstimatorEntry:
    """One estimator that can run on a :class:`LogData`.

    Attributes
    ----------
    name : str
        Registry key and ``--estimator`` choice.
    description : str
        One line: what it is and which sensors of the log it uses.
    run : callable(data, dt, options) -> NamedTuple
        ``data`` a :class:`LogData`, ``dt`` the per-sample periods (s, from
        :func:`sample_periods`), ``options`` a dict (``settings``,
        ``progress``); returns per-sample outputs with ``altitude`` (m) and
        ``vertical_velocity`` (m/s) fields. It may put ``options["events"]``
        (a :class:`~fusion_altitude.rocket.FlightEvents`), which lands in
        ``LogRun.events``.
    needs : tuple of str, default ()
        :class:`LogData` fields the estimator cannot run without (e.g.
        ``("gyro", "accel")`` for the INS); ``compare LOG`` leaves it out on
        logs that lack one (:func:`applicable_estimators`), ``run`` refuses
        it by name.
    vehicle : str, default ""
        Non-empty: ``compare LOG`` runs it only on logs of that
        ``LogData.vehicle`` (the rocket layer waits on the pad forever on a
        multirotor log); ``run`` still runs it on any log when asked.
    """

    name: str
    description: str
    run: Callable[[LogData, np.ndarray, dict], object]
    needs: Tuple[str, ...] = ()
    vehicle: str = ""


#: Registered estimators by name, in table order.
ESTIMATORS: Dict[str, EstimatorEntry] = {}


def register_estimator(entry: EstimatorEntry) -> None:
    """Add (or replace) an estimator of :data:`ESTIMATORS`; it appears in ``run --estimator`` and ``compare LOG``."""
    if not isinstance(entry, EstimatorEntry):
        raise TypeError(f"entry must be an EstimatorEntry, got {type(entry).__name__}")
    ESTIMATORS[entry.name] = entry


def estimator_names() -> List[str]:
    """The registered estimator names, in table order."""
    return list(ESTIMATORS)


def missing_inputs(data: LogData, estimator: str) -> List[str]:
    """The :class:`LogData` fields that ``estimator`` needs (``EstimatorEntry.needs``) and ``data`` lacks."""
    return [name for name in ESTIMATORS[estimator].needs if getattr(data, name, None) is None]


def applicable_estimators(data: LogData) -> List[str]:
    """The registered estimators ``compare LOG`` runs on ``data``, in table order: every input they need is in the
    log and, for an entry made for one kind of vehicle (``EstimatorEntry.vehicle``), the log is of that kind."""
    return [name for name, entry in ESTIMATORS.items()
            if not missing_inputs(data, name) and entry.vehicle in ("", getattr(data, "vehicle", ""))]


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
    for name in ("vtol", "fixed_wing", "balloon"):
        gains = tuple(np.float32(g) for g in AltitudeSettings.preset(name).as_tuple())
        if step_stable(*gains, period32, period32):
            return name
    return "balloon"


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


def _run_observer_entry(data: LogData, dt: np.ndarray, options: dict):
    settings = options.get("settings")
    if settings is None:
        settings = AltitudeSettings.preset(default_preset(data))
    info = options if options is not None else {}
    result = run_observer(data.time, data.vertical_acceleration, data.baro_altitude, settings,
                          clipped=data.clipped, progress=options.get("progress"), dt=dt, info=info)
    mask = _baro_timeout_warning("observer", data.time, dt, data.baro_altitude, info["baro_timeout"],
                                 info["baro_timeouts"])
    aided = np.ones(data.time.size, np.int64) if mask is None else (~mask).astype(np.int64)
    return ObserverLogBatch(*result, aided)


def _run_kalman(data: LogData, dt: np.ndarray, options: dict):
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


def _run_complementary(data: LogData, dt: np.ndarray, options: dict):
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


def _run_alphabeta(data: LogData, dt: np.ndarray, options: dict):
    import math

    from ._core._alphabeta import AlphaBetaFusion, AlphaBetaSettings

    # a log's altitudes are above sea level (or any datum) and may dip below the start: the altitude windows of
    # the defaults (made for heights above a take-off point) are opened for the imu, baro and GPS
    settings = AlphaBetaSettings(**{s: {"altitude_min": -math.inf, "altitude_max": math.inf}
                                    for s in ("imu", "baro", "gps")})
    settings = settings.replace(**_alphabeta_log_sensors(data, settings))
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


def _alphabeta_log_sensors(data: LogData, settings) -> dict:
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
        m, the INS's own height above its reference d (``InsBatch.altitude``).
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


def _run_ins(data: LogData, dt: np.ndarray, options: dict) -> InsLogBatch:
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
    return InsLogBatch(batch.altitude + batch.baro_bias, batch.vertical_velocity, batch.altitude,
                       euler[:, 0], euler[:, 1], euler[:, 2], *(batch.quaternion[:, i] for i in range(4)),
                       *(batch.gyro_bias[:, i] for i in range(3)), batch.accel_z_bias, batch.baro_bias,
                       batch.is_stationary, batch.baro_timed_out)


class RocketLogBatch(NamedTuple):
    """The rocket flight layer on a log, per grid step, as ``run -o`` writes it.

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


def _run_rocket(data: LogData, dt: np.ndarray, options: dict) -> RocketLogBatch:
    """The rocket flight layer on a log; its accelerometer input is chosen by :func:`fusion_altitude.rocket.rocket_accel_input`
    (NaN where the flight layer must do without one: baro-led), and what was chosen goes to ``data.notes``."""
    from ._core._flight import RocketEstimator
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


for _entry in (
        EstimatorEntry("observer", "3rd-order complementary observer (baro + accel)", _run_observer_entry),
        EstimatorEntry("kalman", "Kalman filter (baro + accel, GPS altitude with its fix quality, rangefinder)",
                       _run_kalman),
        EstimatorEntry("complementary", "two-stage complementary filter (baro + accel)", _run_complementary),
        EstimatorEntry("alphabeta", "quality-weighted alpha-beta fusion (baro, rangefinder, GPS shifted onto the baro "
                                    "datum + accel)",
                       _run_alphabeta),
        EstimatorEntry("ins", "inertial navigation filter (raw gyro + accelerometer + baro; attitude, gyro bias, "
                              "baro bias)", _run_ins, needs=("gyro", "accel")),
        EstimatorEntry("rocket", "rocket flight layer (long-axis accel + baro: pad calibration, baro lockout, "
                                 "flight events)", _run_rocket, vehicle="rocket")):
    register_estimator(_entry)


# ----------------------------------------------------------------------------
# running


def run_observer(time, vertical_acceleration, baro_altitude, settings: Optional[AltitudeSettings] = None,
                 clipped=None, clipped_settings: Optional[AltitudeSettings] = None,
                 progress: Optional[Callable[[int, int], None]] = None, chunk: int = 50_000,
                 compensate_baro_rate: bool = True, dt=None, info: Optional[dict] = None) -> AltitudeBatch:
    """Run the observer over a log with irregular timestamps and missing baro samples.

    Parameters
    ----------
    time : array_like
        Sample times, s, strictly increasing; dt[i] = time[i] − time[i−1]
        (the first step uses the second step's dt; it only sets the reference).
    vertical_acceleration : array_like
        m/s², +up, gravity removed.
    baro_altitude : array_like
        m; NaN where there is no baro sample.
    settings : AltitudeSettings, optional
        Gains; default the VTOL preset.
    clipped : array_like of bool, optional
        Samples whose accelerometer reading hit its range. See Notes.
    clipped_settings : AltitudeSettings, optional
        Gains on clipped samples; default ``settings`` with the position loop
        4× faster (ω·4, ζ 0.7) and **bias estimation off** (Kb = 0).
    progress : callable(done, total), optional
        Called after each chunk of samples.
    compensate_baro_rate : bool, default True
        Scale the gains by (samples / baro samples) when the baro is slower
        than the grid (:func:`fusion_altitude.tuning.settings_for_baro_rate`),
        so ``settings`` keeps its designed bandwidth.
    dt : array_like, optional
        Per-sample periods, s; default :func:`sample_periods` of ``time``.
        The gap period used is ``max(settings.gap_period, 10 × nominal dt)``
        (:func:`fusion_altitude.tuning.gap_period_for`), the baro timeout
        ``max(settings.baro_timeout, 5 × the baro period)``
        (:func:`fusion_altitude.tuning.baro_timeout_for`).
    info : dict, optional
        Receives ``gap_period`` (s, as float32 holds it), ``gap_count``,
        ``baro_timeout`` (s) and ``baro_timeouts``.

    Returns
    -------
    AltitudeBatch

    Notes
    -----
    **Clipping.** A clipped accelerometer under-reports the acceleration, and
    the observer would integrate that error and push it into its bias
    estimate. On clipped samples the observer therefore (1) still uses the
    clipped reading (a lower bound of the true magnitude), (2) switches to
    baro-trusting gains so the baro pulls the estimate back quickly, and
    (3) freezes the bias estimate (Kb = 0) so the bias learned before the
    clipping survives it. The normal gains return on the first unclipped
    sample, with the state carried over.
    """
    time = np.asarray(time, dtype=float)
    accel = np.asarray(vertical_acceleration, dtype=float)
    baro = np.asarray(baro_altitude, dtype=float)
    n = time.size
    dt = sample_periods(time) if dt is None else np.asarray(dt, dtype=float)
    settings = settings or AltitudeSettings()
    settings = settings.replace(gap_period=gap_period_for(dt, settings.gap_period),
                                baro_timeout=baro_timeout_for(time, baro, settings.baro_timeout))
    if compensate_baro_rate:
        settings = settings_for_baro_rate(settings, steps_per_baro(baro))
    estimator = AltitudeEstimator(settings)
    normal = estimator.settings
    if clipped is None:
        clipped = np.zeros(n, dtype=bool)
    clipped = np.asarray(clipped, dtype=bool)
    if clipped.any() and clipped_settings is None:
        omega = _bandwidth_of(normal)
        clipped_settings = AltitudeSettings.from_bandwidth(4 * omega, 0.7, 0.0, **_other_fields(normal))
    out = AltitudeBatch(*(np.empty(n, dtype=np.float32) for _ in range(4)))
    # Segments of constant clipping state, further cut into chunks for progress.
    edges = np.flatnonzero(np.diff(clipped.astype(np.int8))) + 1
    bounds = np.unique(np.concatenate([[0], edges, np.arange(0, n, chunk), [n]]))
    for start, stop in zip(bounds[:-1], bounds[1:]):
        estimator.settings = clipped_settings if clipped[start] else normal
        views = AltitudeBatch(*(array[start:stop] for array in out))
        estimator.update_batch(accel[start:stop], baro[start:stop], dt[start:stop], out=views)
        if progress is not None:
            progress(int(stop), n)
    if info is not None:
        _gaps(info, estimator, normal.gap_period)
        info["baro_timeout"] = float(np.float32(normal.baro_timeout))
        info["baro_timeouts"] = int(estimator.baro_timeouts)
    return out


def sample_periods(time) -> np.ndarray:
    """Per-sample dt, s, from timestamps: dt[i] = time[i] − time[i−1], and dt[0] = dt[1]
    (the first sample only sets the reference)."""
    time = np.asarray(time, dtype=float)
    dt = np.empty(time.size)
    dt[1:] = np.diff(time)
    dt[:1] = dt[1] if time.size > 1 else 0.01
    return dt


def nominal_period(time) -> float:
    """The log's nominal sample period, s: the median of its positive steps (gaps do not move it)."""
    steps = np.diff(np.asarray(time, dtype=float))
    steps = steps[steps > 0]
    return float(np.median(steps)) if steps.size else 0.01


def above_start(data: LogData, seconds: float = 1.0) -> float:
    """The datum (m) that turns the log's altitudes into heights above the start (or the pad).

    The log's own ``ground_altitude`` (pad altitude) when the reader found
    one, else the median baro altitude over the first ``seconds`` s with baro
    samples. The baro and the reference share one datum (see
    :class:`~fusion_altitude.logs.LogData`), so subtracting this one value
    from both aligns them the same way.

    Raises
    ------
    ValueError
        No baro sample and no ground altitude.
    """
    ground = getattr(data, "ground_altitude", None)
    if ground is not None and np.isfinite(ground):
        return float(ground)
    baro = np.asarray(data.baro_altitude, float)
    finite = np.flatnonzero(np.isfinite(baro))
    if finite.size == 0:
        raise ValueError(f"{data.source}: no baro sample to take the start altitude from")
    early = finite[data.time[finite] <= data.time[finite[0]] + seconds]
    return float(np.median(baro[early]))


def run_log(data: LogData, settings: Optional[AltitudeSettings] = None,
            progress: Optional[Callable[[int, int], None]] = None, estimator: str = "observer",
            agl: bool = False, **options) -> LogRun:
    """Run a registered estimator on a :class:`LogData`.

    Parameters
    ----------
    data : LogData
        The log.
    settings : AltitudeSettings, optional
        Observer gains (ignored by the other estimators); default
        :func:`default_preset` (VTOL unless the log is too slow for it),
        compensated for the baro rate. Clipped samples are handled as in
        :func:`run_observer`.
    progress : callable(done, total), optional
        Called as samples are processed.
    estimator : str, default "observer"
        A name of :data:`ESTIMATORS`.
    agl : bool, default False
        Heights above the start (or the pad): the baro, the GPS altitude,
        the estimate and the reference all shifted by the one datum of
        :func:`above_start` (``LogRun.datum``).
    **options
        Passed to the estimator's entry (e.g. ``kalman_settings``).

    Returns
    -------
    LogRun

    Raises
    ------
    ValueError
        Unknown ``estimator`` (the message lists the known ones).
    """
    if estimator not in ESTIMATORS:
        raise ValueError(f"estimator must be one of {', '.join(ESTIMATORS)}, got {estimator!r}")
    missing = missing_inputs(data, estimator)
    if missing:
        raise ValueError(f"estimator {estimator} needs the log's raw {' and '.join(missing)}; {data.source} has "
                         f"no {' or '.join(missing)}")
    fields = {name: getattr(data, name) for name in LogData.__dataclass_fields__}
    datum = 0.0
    if agl:
        datum = above_start(data)
        fields["baro_altitude"] = np.asarray(data.baro_altitude, float) - datum
        for name in ("reference_altitude", "gps_altitude"):
            if fields.get(name) is not None:
                fields[name] = np.asarray(fields[name], float) - datum
        if "ground_altitude" in fields:
            fields["ground_altitude"] = 0.0
        data = type(data)(**fields)
    options = dict(options, settings=settings, progress=progress)
    estimate = ESTIMATORS[estimator].run(data, sample_periods(data.time), options)
    return LogRun(**fields, estimate=estimate, estimator=estimator, datum=datum, events=options.get("events"),
                  gap_period=options.get("gap_period"), gap_count=options.get("gap_count"),
                  baro_rejections=options.get("baro_rejections"), baro_resets=options.get("baro_resets"))
