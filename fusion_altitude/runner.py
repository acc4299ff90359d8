"""Running any estimator on a recorded log (:class:`fusion_altitude.logs.LogData`) and writing the results.

The jobs live in modules of their own: the estimator registry in :mod:`fusion_altitude.estimators` (one row
per estimator; :data:`ESTIMATORS`, :func:`register_estimator`), the per-estimator adapters in
:mod:`fusion_altitude.adapters`, the writers in :mod:`fusion_altitude.outputs`; this module runs one of them on a
log (:func:`run_log`) and keeps their names importable from here.

Every 1-D numeric field of an estimator's batch (float, integer or boolean, e.g. a
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
from typing import Callable, Optional

import numpy as np

from ._core._observer import AltitudeSettings
from .adapters import InsLogBatch, ObserverLogBatch, RocketLogBatch, run_observer
from .estimators import (ESTIMATORS, EstimatorEntry, applicable_estimators, default_preset, estimator_names,
                         missing_inputs, observer_rate, register_estimator)
from .logs import LogData
from .metrics import ErrorStatistics, error_statistics
from .outputs import atomic_output, csv_columns, is_special_output, write_csv
from .rocket import rocket_long_axis
from .tuning import nominal_period, sample_periods

# The registry (estimators), the adapters and the writers (outputs) are modules of their own; their names stay
# importable from here, where the applications found them before the split.
__all__ = ["LogRun", "EstimatorEntry", "ESTIMATORS", "register_estimator", "estimator_names", "applicable_estimators",
           "missing_inputs", "default_preset", "observer_rate", "ObserverLogBatch", "InsLogBatch", "RocketLogBatch", "rocket_long_axis",
           "run_observer", "sample_periods", "nominal_period", "run_log", "above_start", "write_csv", "atomic_output",
           "is_special_output", "csv_columns"]


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
    estimate = ESTIMATORS[estimator].function()(data, sample_periods(data.time), options)
    return LogRun(**fields, estimate=estimate, estimator=estimator, datum=datum, events=options.get("events"),
                  gap_period=options.get("gap_period"), gap_count=options.get("gap_count"),
                  baro_rejections=options.get("baro_rejections"), baro_resets=options.get("baro_resets"))
