"""Running estimators on recorded logs (:class:`fusion_altitude.logs.LogData`) and writing the results."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np

from ._observer import AltitudeEstimator, AltitudeSettings
from ._observer_glue import AltitudeBatch
from .logs import LogData
from .metrics import ErrorStatistics, error_statistics
from .tuning import _bandwidth_of, settings_for_baro_rate

__all__ = ["LogRun", "run_observer", "sample_periods", "run_log", "write_csv"]


@dataclass
class LogRun(LogData):
    """A :class:`LogData` with the observer's outputs (``estimate``, per grid step)."""

    estimate: Optional[AltitudeBatch] = None

    def comparison(self, transient: float = 0.0) -> Optional[ErrorStatistics]:
        """Statistics of fused − reference altitude (m) after ``transient`` s; None without a reference."""
        if self.reference_altitude is None:
            return None
        return error_statistics(self.time, self.estimate.altitude - self.reference_altitude, transient)

    def baro_comparison(self, transient: float = 0.0) -> Optional[ErrorStatistics]:
        """Statistics of baro − reference altitude (m) after ``transient`` s; None without a reference."""
        if self.reference_altitude is None:
            return None
        return error_statistics(self.time, self.baro_altitude - self.reference_altitude, transient)


def run_observer(time, vertical_acceleration, baro_altitude, settings: Optional[AltitudeSettings] = None,
                 clipped=None, clipped_settings: Optional[AltitudeSettings] = None,
                 progress: Optional[Callable[[int, int], None]] = None, chunk: int = 50_000,
                 compensate_baro_rate: bool = True) -> AltitudeBatch:
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
        than the grid (:func:`settings_for_baro_rate`), so ``settings`` keeps
        its designed bandwidth.

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
    dt = sample_periods(time)
    settings = settings or AltitudeSettings()
    n_baro = int(np.sum(np.isfinite(baro)))
    if compensate_baro_rate and n_baro > 0:
        settings = settings_for_baro_rate(settings, n / n_baro)
    estimator = AltitudeEstimator(settings)
    normal = estimator.settings
    if clipped is None:
        clipped = np.zeros(n, dtype=bool)
    clipped = np.asarray(clipped, dtype=bool)
    if clipped.any() and clipped_settings is None:
        omega = _bandwidth_of(normal)
        clipped_settings = AltitudeSettings.from_bandwidth(4 * omega, 0.7, 0.0)
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
    return out


def sample_periods(time) -> np.ndarray:
    """Per-sample dt, s, from timestamps: dt[i] = time[i] − time[i−1], and dt[0] = dt[1]
    (the first sample only sets the reference)."""
    time = np.asarray(time, dtype=float)
    dt = np.empty(time.size)
    dt[1:] = np.diff(time)
    dt[:1] = dt[1] if time.size > 1 else 0.01
    return dt


def run_log(data: LogData, settings: Optional[AltitudeSettings] = None,
            progress: Optional[Callable[[int, int], None]] = None) -> LogRun:
    """Run the observer on a :class:`LogData` (clipped samples handled as in :func:`run_observer`)."""
    estimate = run_observer(data.time, data.vertical_acceleration, data.baro_altitude, settings,
                            clipped=data.clipped, progress=progress)
    return LogRun(**{name: getattr(data, name) for name in LogData.__dataclass_fields__}, estimate=estimate)


def write_csv(run: LogRun, path: str) -> None:
    """Write the run per grid step: time s, baro_altitude m, vertical_acceleration m/s², altitude m,
    vertical_velocity m/s, accel_bias m/s², baro_residual m and, if present, reference_altitude m."""
    columns = [("time", run.time), ("baro_altitude", run.baro_altitude),
               ("vertical_acceleration", run.vertical_acceleration), ("altitude", run.estimate.altitude),
               ("vertical_velocity", run.estimate.vertical_velocity), ("accel_bias", run.estimate.accel_bias),
               ("baro_residual", run.estimate.baro_residual)]
    if run.reference_altitude is not None:
        columns.append(("reference_altitude", run.reference_altitude))
    table = np.column_stack([np.asarray(values, dtype=float) for _, values in columns])
    np.savetxt(path, table, delimiter=",", header=",".join(name for name, _ in columns), comments="", fmt="%.6g")
