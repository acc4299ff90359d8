"""Every estimator on the same data, one comparison table: the simulator's scenarios or one recorded log.

Estimators, each fed what it can use from one :func:`~fusion_altitude.scenarios.run_scenario` run:

- ``observer``: the 3rd-order observer with the scenario's preset gains (as ``demo`` runs it; VTOL defaults
  unless the scenario is a balloon, fixed wing or rocket), baro + accel;
- ``observer (fit)``: the observer with gains from :func:`fusion_altitude.fit` on the same scenario with
  another seed (``fit_seed``, default 1), evaluated on the compare seed, so the fit is held out;
- ``Kalman``: :class:`fusion_altitude.KalmanEstimator`, default settings, baro + rangefinder + GPS + accel,
  its baro-referenced ``altitude``;
- ``complementary``: the two-stage complementary filter (seed 001), defaults, baro + accel;
- ``alpha-beta``: the quality-weighted α-β fusion (seed 003), the write-up's tables; baro, rangefinder (as
  the lidar), GPS and accel; on the two sinusoid scenarios, which fly 5 m below their start, the altitude
  minimum of the tables is lifted (the tables assume height above the take-off point);
- ``INS``: the inertial navigation filter (seed 004, :class:`fusion_altitude.InsEstimator`, defaults), fed the
  scenario's **raw** IMU (the same simulated gyro °/s, accelerometer g and magnetometer from which the other
  rows' vertical acceleration is made) and baro; its altitude in the baro's frame (INS height + baro bias). The
  scenarios start moving at once, so the INS never sees the rest it learns its accel z bias in
  (docs/ins.md: with a stationary start it beats the two-step pipeline, without one it does not);
- ``rocket``, the rocket estimator (the ``rocket`` scenario only; labelled ``rocket layer`` in 0.1.0, a
  label still accepted): :func:`fusion_altitude.rocket.run_rocket` (defaults: pad calibration, baro lockout,
  spike gate, baro-led descent) on the long-axis accelerometer and the baro, its height above the pad plus the
  pad altitude it learned;
- ``raw baro``: the baro samples themselves.

Metrics after the scenario's transient: altitude RMS and max |error| (m), velocity RMS (m/s), time to
recover from the scenario's sensor fault (s after it ends until |altitude error| stays within
``recovery_tolerance``, 0.5 m, for the rest of a 15 s window; ">15" if never) and the C batch speed
(ns/sample, best of ``repeat``; none with ``repeat=0``).

:func:`compare_log` does the same on one recorded log (:class:`fusion_altitude.logs.LogData`): every
estimator of :data:`fusion_altitude.runner.ESTIMATORS` against the log's own estimate (its reference
altitude), same :class:`Row`, same table.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from ._core._alphabeta import AlphaBetaFusion, AlphaBetaSettings
from ._core._complementary import ComplementaryFilter
from ._core._kalman import KalmanEstimator
from ._core._observer import AltitudeEstimator, AltitudeSettings
from .estimators import ESTIMATORS as REGISTRY
from .health import check_estimate
from .metrics import error_statistics, settling_time
from .sim.scenarios import ScenarioResult, run_scenario

__all__ = ["ESTIMATORS", "SCENARIOS", "estimators_for", "Row", "compare", "compare_scenario", "compare_log", "format_markdown",
           "plot_comparison", "plot_log_comparison", "table_cells", "header", "HEADER"]

#: Estimator names, in table order: the registry's labels (:mod:`fusion_altitude.estimators`), the observer with
#: fitted gains after the observer, and the raw baro last.
ESTIMATORS = ("observer", "observer (fit)", *(entry.table_label for entry in REGISTRY.values() if entry.name != "observer"),
              "raw baro")
#: Estimators that only run on some scenarios: those made for one vehicle, on the scenario of that name.
_ONLY_ON = {entry.table_label: (entry.vehicle,) for entry in REGISTRY.values() if entry.vehicle}
#: The scenarios of the table.
SCENARIOS = ("realistic", "clean", "balloon", "fixed-wing", "ground-effect", "baro-glitches", "terrain-step",
             "gps-outage")
#: Scenarios whose truth goes below the start altitude (the α-β tables' altitude minimum is lifted there).
_BELOW_START = ("realistic", "clean")
RECOVERY_WINDOW = 15.0


@dataclass
class Row:
    """One estimator on one scenario (m, m/s, s, ns)."""

    scenario: str
    estimator: str
    altitude_rms: float
    altitude_max: float
    velocity_rms: float
    recovery: Optional[float]
    ns_per_sample: Optional[float]
    altitude: np.ndarray
    #: Why the estimate was refused (:func:`fusion_altitude.health.check_estimate`: non-finite or a runaway); its
    #: error cells are then NaN. None for an estimate that can be printed.
    problem: Optional[str] = None


def _best_ns(run, n: int, repeat: int) -> Optional[float]:
    """Best wall time of ``run`` over ``repeat`` calls, ns per sample; None when ``repeat`` < 1 (no timing)."""
    if repeat < 1:
        return None
    best = math.inf
    for _ in range(repeat):
        start = time.perf_counter_ns()
        run()
        best = min(best, time.perf_counter_ns() - start)
    return best / max(n, 1)


def _inputs(result: ScenarioResult):
    from .sim import align_to

    t = result.time
    rangefinder = align_to(t, result.rangefinder) if result.rangefinder is not None else np.full(t.size, np.nan)
    gps = align_to(t, result.gps) if result.gps is not None else np.full(t.size, np.nan)
    return (np.asarray(result.vertical_acceleration, np.float32), np.asarray(result.baro_altitude, np.float32),
            rangefinder.astype(np.float32), gps.astype(np.float32), np.float32(result.trajectory.dt))


def _fit_settings(name: str, fit_seed: int, attitude: str):
    from .tuning import fit, steps_per_baro

    training = run_scenario(name, seed=fit_seed, attitude=attitude)
    mask = training.time >= training.time[0] + training.transient
    return fit(training.vertical_acceleration, training.baro_altitude, training.trajectory.dt,
               training.trajectory.altitude, mask=mask, steps_per_baro=steps_per_baro(training.baro_altitude)).settings


#: Old estimator labels → their names now; accepted with a DeprecationWarning.
OLD_LABELS = {"rocket layer": "rocket"}


def _current_labels(estimators: Sequence[str]) -> List[str]:
    """``estimators`` with every old label of :data:`OLD_LABELS` replaced by its name (a DeprecationWarning each)."""
    for old in sorted(set(estimators) & OLD_LABELS.keys()):
        warnings.warn(f"the estimator label {old!r} is now {OLD_LABELS[old]!r}", DeprecationWarning, stacklevel=3)
    return [OLD_LABELS.get(e, e) for e in estimators]


def estimators_for(name: str, estimators: Sequence[str] = ESTIMATORS) -> List[str]:
    """The ``estimators`` that run on scenario ``name`` (the rocket estimator, ``rocket``, only on ``rocket``), in
    order; an old label of :data:`OLD_LABELS` is accepted with a DeprecationWarning."""
    return [e for e in _current_labels(estimators) if name in _ONLY_ON.get(e, (name,))]


def compare_scenario(name: str, seed: int = 0, fit_seed: int = 1, attitude: str = "truth", repeat: int = 3,
                     estimators: Sequence[str] = ESTIMATORS, recovery_tolerance: float = 0.5) -> List[Row]:
    """Run every estimator of ``estimators`` that applies to the scenario (:func:`estimators_for`) on one
    scenario; one :class:`Row` each, in that order."""
    estimators = estimators_for(name, estimators)
    result = run_scenario(name, seed=seed, attitude=attitude)
    inputs = _inputs(result)
    runners = _scenario_runners(name, estimators, result, inputs, fit_seed, attitude)
    return [_scenario_row(name, estimator, result, inputs[1], None if estimator == "raw baro" else runners[estimator],
                          repeat, recovery_tolerance) for estimator in estimators]


def _scenario_runners(name: str, estimators: Sequence[str], result, inputs, fit_seed: int,
                      attitude: str) -> Dict[str, Any]:
    """Per estimator row of :func:`compare_scenario`, a function that runs it over the scenario's ``inputs``
    (:func:`_inputs`): the built-in estimators' own runners (:data:`_SCENARIO_RUNNERS`), and for any other
    registered estimator its registry adapter on the scenario as a log (:func:`_registry_runner`)."""
    from .tuning import settings_for_baro_rate, steps_per_baro

    accel, baro, _, _, dt = inputs
    runners: Dict[str, Any] = {}
    observer_settings = settings_for_baro_rate(AltitudeSettings.preset(_preset(name)), steps_per_baro(baro))
    runners["observer"] = lambda: AltitudeEstimator(observer_settings).update_batch(accel, baro, dt)
    if "observer (fit)" in estimators:
        # fitted and run with the same baro-rate compensation as the preset row (and as `run` and `fit`)
        fitted = settings_for_baro_rate(_fit_settings(name, fit_seed, attitude), steps_per_baro(baro))
        runners["observer (fit)"] = lambda: AltitudeEstimator(fitted).update_batch(accel, baro, dt)
    entries = {entry.table_label: entry for entry in REGISTRY.values()}
    for label in estimators:
        if label in runners or label == "raw baro":
            continue
        if label not in entries:
            raise ValueError(f"estimators: unknown estimator {label!r} (known: {', '.join(ESTIMATORS)})")
        runner = _SCENARIO_RUNNERS.get(label)
        runners[label] = runner(name, result, inputs) if runner else _registry_runner(entries[label], result, inputs)
    return runners


def _kalman_runner(name: str, result: ScenarioResult, inputs):
    accel, baro, rangefinder, gps, dt = inputs
    # keywords after accel: the same call in the old and the new (accel, baro_altitude, dt, ...) argument order
    return lambda: KalmanEstimator().update_batch(accel, dt=dt, baro_altitude=baro, range_distance=rangefinder,
                                                  gps_altitude=gps)


def _complementary_runner(name: str, result: ScenarioResult, inputs):
    accel, baro, _, _, dt = inputs
    return lambda: ComplementaryFilter().update_batch(accel, baro, dt)


def _alphabeta_runner(name: str, result: ScenarioResult, inputs):
    accel, baro, rangefinder, gps, dt = inputs
    settings = AlphaBetaSettings(**{s: {"altitude_min": -math.inf} for s in ("imu", "baro", "gps")}) \
        if name in _BELOW_START else AlphaBetaSettings()
    return lambda: AlphaBetaFusion(settings).update_batch(accel, dt=dt, baro_altitude=baro, lidar_altitude=rangefinder,
                                                          gps_altitude=gps)


def _registry_runner(entry, result: ScenarioResult, inputs):
    """A call running a registered estimator's adapter (``entry.function()``) on the scenario as a
    :class:`fusion_altitude.logs.LogData`: its time, vertical acceleration (m/s²), baro, GPS and rangefinder
    heights (m); no raw IMU, so an estimator that needs one (``entry.needs``) is refused."""
    from .logs import LogData
    from .runner import sample_periods

    accel, baro, rangefinder, gps, _ = inputs
    data = LogData("simulated", result.time, accel, baro, gps_altitude=gps, rangefinder=rangefinder)
    missing = [field for field in entry.needs if getattr(data, field, None) is None]
    if missing:
        raise ValueError(f"estimators: {entry.table_label!r} needs {', '.join(missing)}, which a scenario does not give")
    dt = sample_periods(result.time)
    return lambda: entry.function()(data, dt, {})


def _scenario_row(name: str, estimator: str, result, baro: np.ndarray, run, repeat: int,
                  recovery_tolerance: float) -> Row:
    """One row of :func:`compare_scenario`: ``estimator`` (``run`` runs it; None for the raw baro) against the
    scenario's truth after its transient: altitude RMS and max (m), velocity RMS (m/s), recovery time (s)."""
    truth_h = result.trajectory.altitude
    if run is None:  # the raw baro
        altitude, velocity, ns = baro.astype(float), None, None
    else:
        out = run()
        altitude = np.asarray(out.altitude, float)
        velocity = np.asarray(out.vertical_velocity, float)
        ns = _best_ns(run, baro.size, repeat)
    error = altitude - truth_h
    statistics = error_statistics(result.time, error, result.transient)
    velocity_rms = error_statistics(result.time, velocity - result.trajectory.vertical_velocity,
                                    result.transient).rms if velocity is not None else math.nan
    recovery = None
    if result.fault_end is not None and run is not None:  # the raw baro has no memory to recover
        window = (result.time >= result.fault_end) & (result.time <= result.fault_end + RECOVERY_WINDOW)
        settle = settling_time(result.time[window], error[window], recovery_tolerance)
        recovery = settle if math.isfinite(settle) else math.inf
    problem = None if run is None else check_estimate(_Heights(result.time, baro, truth_h), altitude, velocity)
    if problem is not None:  # never a figure from an estimate that cannot be trusted
        return Row(name, estimator, math.nan, math.nan, math.nan, None, ns, altitude, str(problem))
    return Row(name, estimator, statistics.rms, statistics.max, velocity_rms, recovery, ns, altitude)


@dataclass(frozen=True)
class _Heights:
    """The height sources of a simulated scenario for :func:`fusion_altitude.health.check_estimate`: the baro and,
    as the log's own estimate, the truth (m)."""

    time: np.ndarray
    baro_altitude: np.ndarray
    reference_altitude: np.ndarray


class _InsAltitude:
    """The INS outputs a comparison row reads: altitude in the baro's frame (m) and vertical velocity (m/s)."""

    def __init__(self, batch):
        self.altitude = batch.altitude
        self.vertical_velocity = batch.vertical_velocity


def _ins_runner(result: ScenarioResult, baro: np.ndarray, dt: np.float32):
    """A call running the INS on the scenario's raw IMU (gyro °/s, accel g, magnetometer) and baro."""
    from ._core._ins import InsEstimator

    gyro, accel, mag = result.imu.gyro, result.imu.accel, result.imu.mag   # float64: converted by the binding
    return lambda: _InsAltitude(InsEstimator(gyro_units="deg/s", accel_units="g").update_batch(gyro, accel, dt, baro,
                                                                                             mag))


class _RocketAltitude:
    """The rocket estimator's outputs a comparison row reads: altitude on the baro's datum (m), velocity (m/s)."""

    def __init__(self, batch, pad_altitude: float):
        self.altitude = batch.height.astype(np.float64) + pad_altitude
        self.vertical_velocity = batch.vertical_velocity


def _rocket_runner(result: ScenarioResult):
    """A call running the rocket estimator on the scenario's long-axis accelerometer and baro."""
    from ._core._rocket import RocketEstimator
    from .runner import sample_periods

    dt = sample_periods(result.time)
    accel, baro = result.vertical_acceleration, result.baro_altitude

    def run():
        estimator = RocketEstimator()
        batch = estimator.update_batch(accel, baro, dt)
        return _RocketAltitude(batch, float(estimator.pad_altitude))
    return run


#: The built-in estimators' scenario runners by table label: ``runner(scenario name, result, inputs)`` returns a call
#: that runs the estimator (settings chosen for the scenario, raw IMU for the INS); a registered estimator without
#: one runs through its registry adapter (:func:`_registry_runner`).
_SCENARIO_RUNNERS = {"Kalman": _kalman_runner, "complementary": _complementary_runner, "alpha-beta": _alphabeta_runner,
                     "INS": lambda name, result, inputs: _ins_runner(result, inputs[1], inputs[4]),
                     "rocket": lambda name, result, inputs: _rocket_runner(result)}


def _preset(name: str) -> str:
    from .sim.scenarios import spec

    return spec(name).preset


def compare(scenarios: Sequence[str] = SCENARIOS, seed: int = 0, fit_seed: int = 1, attitude: str = "truth",
            repeat: int = 3, estimators: Sequence[str] = ESTIMATORS, progress=None) -> List[Row]:
    """:func:`compare_scenario` for each scenario, concatenated; ``progress(done, total)`` after each."""
    rows: List[Row] = []
    for k, name in enumerate(scenarios):
        rows.extend(compare_scenario(name, seed, fit_seed, attitude, repeat, estimators))
        if progress is not None:
            progress(k + 1, len(scenarios))
    return rows


def _cell(value: Optional[float], digits: int = 3) -> str:
    if value is None:
        return "—"
    if isinstance(value, float) and math.isinf(value):
        return f">{RECOVERY_WINDOW:g}"
    if isinstance(value, float) and math.isnan(value):
        return "—"
    return f"{value:.{digits}f}"


HEADER = ("scenario", "estimator", "alt RMS (m)", "alt max (m)", "vel RMS (m/s)", "recovery (s)", "ns/sample")


def table_cells(rows: Sequence[Row]) -> List[List[str]]:
    """The table's cells, one list per row, in :data:`HEADER` order."""
    return [[r.scenario, r.estimator, _cell(r.altitude_rms), _cell(r.altitude_max), _cell(r.velocity_rms),
             _cell(r.recovery, 1), _cell(r.ns_per_sample, 0)] for r in rows]


def header(rows: Sequence[Row]) -> Tuple[str, ...]:
    """:data:`HEADER`, with "log" as the first column's name when the rows come from :func:`compare_log`."""
    from .sim.scenarios import scenario_names

    if rows and not any(r.scenario in scenario_names() for r in rows):
        return ("log",) + HEADER[1:]
    return HEADER


def format_markdown(rows: Sequence[Row]) -> str:
    """A Markdown table of the rows."""
    lines = ["| " + " | ".join(header(rows)) + " |", "|" + "|".join(["---"] * 2 + ["---:"] * 5) + "|"]
    lines += ["| " + " | ".join(cells) + " |" for cells in table_cells(rows)]
    return "\n".join(lines)


def compare_log(data, estimators: Optional[Sequence[str]] = None, repeat: int = 3, skip: float = 0.0,
                agl: bool = False, progress=None) -> List[Row]:
    """Every registered estimator on one recorded log against the log's own estimate.

    Parameters
    ----------
    data : fusion_altitude.logs.LogData
        The log; it needs a reference altitude (the autopilot's or flight
        computer's estimate, or a CSV ``reference_column``).
    estimators : sequence of str, optional
        Names of :data:`fusion_altitude.runner.ESTIMATORS` (default those
        that can run on the log, :func:`fusion_altitude.runner.applicable_estimators`:
        the INS needs raw gyro and accelerometer, the rocket estimator a rocket
        log), in table order; "raw baro" is appended.
    repeat : int, default 3
        Timing repeats, best taken; 0 skips the timing (ns/sample "—").
    skip : float, default 0
        Seconds after the first sample left out of the metrics.
    agl : bool, default False
        Heights above the start (:func:`fusion_altitude.runner.above_start`).
    progress : callable(done, total), optional
        Called after each estimator.

    Returns
    -------
    list of Row
        One per estimator and one for the raw baro; ``scenario`` is the
        log's file name, ``recovery`` None (a log has no known fault).

    Raises
    ------
    ValueError
        The log has no reference altitude, or an unknown estimator name.
    """
    import os

    from . import runner

    if data.reference_altitude is None:
        raise ValueError(f"{data.source} has no reference altitude to compare against: give --reference COLUMN "
                         "(CSV), or a .ulg/.bin with the autopilot's own height estimate")
    names = runner.applicable_estimators(data) if estimators is None else list(estimators)
    if int(repeat) < 0:
        raise ValueError(f"repeat must be >= 0, got {repeat}")
    label = os.path.basename(str(data.source).split(" ")[0]) or str(data.source)
    rows: List[Row] = []
    run = None
    for k, name in enumerate(names):
        run = runner.run_log(data, estimator=name, agl=agl)
        ns = _best_ns(lambda: runner.run_log(data, estimator=name, agl=agl), data.time.size, int(repeat))
        rows.append(_log_row(run, label, name, skip, ns))
        if progress is not None:
            progress(k + 1, len(names))
    baro_run = run if run is not None else runner.run_log(data, agl=agl)
    baro = np.asarray(baro_run.baro_altitude, float)
    statistics = error_statistics(baro_run.time, baro - baro_run.reference_altitude, skip)
    rows.append(Row(label, "raw baro", statistics.rms, statistics.max, math.nan, None, None, baro))
    return rows


def _log_row(run, label: str, name: str, skip: float, ns: Optional[float]) -> Row:
    """The row of one estimator's run on a log: altitude RMS and max error (m) and velocity RMS error (m/s)
    against the log's own estimate after ``skip`` s; NaN figures and the problem when the estimate cannot be
    trusted."""
    altitude = np.asarray(run.estimate.altitude, float)
    velocity = np.asarray(run.estimate.vertical_velocity, float)
    problem = check_estimate(run, altitude, velocity)
    if problem is not None:  # never a figure from an estimate that cannot be trusted
        return Row(label, name, math.nan, math.nan, math.nan, None, ns, altitude, str(problem))
    statistics = error_statistics(run.time, altitude - run.reference_altitude, skip)
    velocity_rms = error_statistics(run.time, velocity - run.reference_velocity, skip).rms \
        if run.reference_velocity is not None and np.isfinite(run.reference_velocity).any() else math.nan
    return Row(label, name, statistics.rms, statistics.max, velocity_rms, None, ns, altitude)


def plot_log_comparison(data, rows: Sequence[Row], path: str, agl: bool = False) -> None:
    """Every estimator's altitude and its difference to the log's own estimate, overlaid (needs matplotlib).

    The same figure as :func:`plot_comparison`, with the log's reference in
    place of the truth; long logs are decimated for display (min/max per
    pixel column) and the file is written atomically.
    """
    from . import runner
    from .plotting import _pyplot, decimate, save_figure

    plt = _pyplot()
    run = runner.run_log(data, agl=agl)
    t, reference = run.time, run.reference_altitude
    figure, (top, bottom) = plt.subplots(2, 1, figsize=(11, 7), sharex=True)
    _overlay(top, bottom, t, reference, rows, decimate, run.reference_name or "log's estimate")
    top.set_ylabel("altitude above start (m)" if agl else "altitude (m)")
    bottom.set_ylabel("estimate − log's estimate (m)")
    bottom.set_xlabel("time (s)")
    top.set_title(str(data.source))
    figure.tight_layout()
    save_figure(figure, path, dpi=120)
    plt.close(figure)


def _overlay(top, bottom, t, reference, rows, decimate, reference_label, error_limit=None):
    """Draw the raw baro first (underneath, grey dots), then the reference and each estimator's line."""
    for row in rows:
        if row.estimator == "raw baro":
            finite = np.isfinite(row.altitude)
            for axis, values in ((top, row.altitude), (bottom, row.altitude - reference)):
                x, y = decimate(t[finite], values[finite])
                style = dict(linestyle="none", marker=".", markersize=1.5) if x.size == int(finite.sum()) \
                    else dict(linewidth=0.6)  # decimated: a line spans each pixel column's min..max
                axis.plot(x, y, color="0.65", label=row.estimator, zorder=1, **style)
    x, y = decimate(t, reference)
    top.plot(x, y, color="black", linewidth=1.5, label=reference_label, zorder=2)
    for row in rows:
        if row.estimator != "raw baro":
            x, y = decimate(t, row.altitude)
            top.plot(x, y, label=row.estimator, linewidth=1, zorder=3)
            x, y = decimate(t, row.altitude - reference)
            bottom.plot(x, y, label=row.estimator, linewidth=1, zorder=3)
    top.legend(loc="best", fontsize=8)
    if error_limit is not None:
        bottom.set_ylim(-error_limit, error_limit)
    for axis in (top, bottom):
        axis.grid(alpha=0.3)


def plot_comparison(name: str, path: str, seed: int = 0, fit_seed: int = 1, attitude: str = "truth") -> None:
    """Altitude error of every estimator over time for one scenario, overlaid (needs matplotlib).

    The raw baro is drawn underneath the estimators' lines; the file is written atomically.
    """
    from .plotting import _pyplot, decimate, save_figure

    plt = _pyplot()
    result = run_scenario(name, seed=seed, attitude=attitude)
    rows = compare_scenario(name, seed, fit_seed, attitude, repeat=0)
    figure, (top, bottom) = plt.subplots(2, 1, figsize=(11, 7), sharex=True)
    _overlay(top, bottom, result.time, result.trajectory.altitude, rows, decimate, "truth", error_limit=3)
    top.set_ylabel("altitude (m)")
    bottom.set_ylabel("altitude error (m)")
    bottom.set_xlabel("time (s)")
    top.set_title(f"{name}, seed {seed}")
    figure.tight_layout()
    save_figure(figure, path, dpi=120)
    plt.close(figure)
