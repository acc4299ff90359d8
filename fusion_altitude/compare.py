"""Every estimator on the same simulated data: one comparison table (issue 7).

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
- ``raw baro``: the baro samples themselves.

Metrics after the scenario's transient: altitude RMS and max |error| (m), velocity RMS (m/s), time to
recover from the scenario's sensor fault (s after it ends until |altitude error| stays within
``recovery_tolerance``, 0.5 m, for the rest of a 15 s window; ">15" if never) and the C batch speed
(ns/sample, best of ``repeat``).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence

import numpy as np

from ._alphabeta import AlphaBetaFusion, AlphaBetaSettings
from ._complementary import ComplementaryFilter
from ._kalman import KalmanEstimator
from ._observer import AltitudeEstimator, AltitudeSettings
from .metrics import settling_time
from .scenarios import ScenarioResult, run_scenario

__all__ = ["ESTIMATORS", "SCENARIOS", "Row", "compare", "compare_scenario", "format_markdown", "plot_comparison"]

#: Estimator names, in table order.
ESTIMATORS = ("observer", "observer (fit)", "Kalman", "complementary", "alpha-beta", "raw baro")
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


def _best_ns(run, n: int, repeat: int) -> float:
    run()
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
    from .tuning import fit

    training = run_scenario(name, seed=fit_seed, attitude=attitude)
    mask = training.time >= training.time[0] + training.transient
    return fit(training.vertical_acceleration, training.baro_altitude, training.trajectory.dt,
               training.trajectory.altitude, mask=mask).settings


def compare_scenario(name: str, seed: int = 0, fit_seed: int = 1, attitude: str = "truth", repeat: int = 3,
                     estimators: Sequence[str] = ESTIMATORS, recovery_tolerance: float = 0.5) -> List[Row]:
    """Run every estimator on one scenario; one :class:`Row` each, in ``estimators`` order."""
    from .tuning import settings_for_baro_rate

    result = run_scenario(name, seed=seed, attitude=attitude)
    accel, baro, rangefinder, gps, dt = _inputs(result)
    n = accel.size
    steps_per_baro = n / max(int(np.sum(np.isfinite(baro))), 1)
    runners: Dict[str, object] = {}
    observer_settings = settings_for_baro_rate(AltitudeSettings.preset(_preset(name)), steps_per_baro)
    runners["observer"] = lambda: AltitudeEstimator(observer_settings).update_batch(accel, baro, dt)
    if "observer (fit)" in estimators:
        fitted = _fit_settings(name, fit_seed, attitude)
        runners["observer (fit)"] = lambda: AltitudeEstimator(fitted).update_batch(accel, baro, dt)
    runners["Kalman"] = lambda: KalmanEstimator().update_batch(accel, dt, baro, rangefinder, gps)
    runners["complementary"] = lambda: ComplementaryFilter().update_batch(accel, baro, dt)
    ab_settings = AlphaBetaSettings(**{s: {"altitude_min": -math.inf} for s in ("imu", "baro", "gps")}) \
        if name in _BELOW_START else AlphaBetaSettings()
    runners["alpha-beta"] = lambda: AlphaBetaFusion(ab_settings).update_batch(accel, dt, baro, rangefinder, None, gps)

    truth_h = result.trajectory.altitude
    truth_v = result.trajectory.vertical_velocity
    after = result.time > result.time[0] + result.transient
    rows = []
    for estimator in estimators:
        if estimator == "raw baro":
            altitude = baro.astype(float)
            velocity = None
            ns = None
        else:
            out = runners[estimator]()
            altitude = np.asarray(out.altitude, float)
            velocity = np.asarray(out.vertical_velocity, float)
            ns = _best_ns(runners[estimator], n, repeat)
        error = altitude - truth_h
        valid = after & np.isfinite(error)
        rms = float(np.sqrt(np.mean(error[valid] ** 2)))
        worst = float(np.max(np.abs(error[valid])))
        velocity_rms = float(np.sqrt(np.mean((velocity[after] - truth_v[after]) ** 2))) if velocity is not None \
            else math.nan
        recovery = None
        if result.fault_end is not None and estimator != "raw baro":  # the raw baro has no memory to recover
            window = (result.time >= result.fault_end) & (result.time <= result.fault_end + RECOVERY_WINDOW)
            settle = settling_time(result.time[window], error[window], recovery_tolerance)
            recovery = settle if math.isfinite(settle) else math.inf
        rows.append(Row(name, estimator, rms, worst, velocity_rms, recovery, ns, altitude))
    return rows


def _preset(name: str) -> str:
    from .scenarios import _spec

    return _spec(name).preset


def compare(scenarios: Sequence[str] = SCENARIOS, seed: int = 0, fit_seed: int = 1, attitude: str = "truth",
            repeat: int = 3, estimators: Sequence[str] = ESTIMATORS) -> List[Row]:
    """:func:`compare_scenario` for each scenario, concatenated."""
    rows: List[Row] = []
    for name in scenarios:
        rows.extend(compare_scenario(name, seed, fit_seed, attitude, repeat, estimators))
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


def format_markdown(rows: Sequence[Row]) -> str:
    """A Markdown table of the rows."""
    lines = ["| " + " | ".join(HEADER) + " |", "|" + "|".join(["---"] * 2 + ["---:"] * 5) + "|"]
    lines += ["| " + " | ".join(cells) + " |" for cells in table_cells(rows)]
    return "\n".join(lines)


def plot_comparison(name: str, path: str, seed: int = 0, fit_seed: int = 1, attitude: str = "truth") -> None:
    """Altitude error of every estimator over time for one scenario, overlaid (needs matplotlib)."""
    from .plotting import _pyplot

    plt = _pyplot()
    result = run_scenario(name, seed=seed, attitude=attitude)
    rows = compare_scenario(name, seed, fit_seed, attitude, repeat=0)
    figure, (top, bottom) = plt.subplots(2, 1, figsize=(11, 7), sharex=True)
    top.plot(result.time, result.trajectory.altitude, color="black", linewidth=1.5, label="truth")
    for row in rows:
        style = dict(linestyle="none", marker=".", markersize=1.5) if row.estimator == "raw baro" else dict(linewidth=1)
        top.plot(result.time, row.altitude, label=row.estimator, **style)
        bottom.plot(result.time, row.altitude - result.trajectory.altitude, label=row.estimator, **style)
    top.set_ylabel("altitude (m)")
    bottom.set_ylabel("altitude error (m)")
    bottom.set_xlabel("time (s)")
    top.set_title(f"{name}, seed {seed}")
    top.legend(loc="best", fontsize=8)
    bottom.set_ylim(-3, 3)
    for axis in (top, bottom):
        axis.grid(alpha=0.3)
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)
