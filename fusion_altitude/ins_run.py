"""Run the inertial navigation filter over a log's arrays: the one call a command
line (``fusion-altitude run --estimator ins``) or a notebook needs.

Nothing here is an estimator: it turns sample times into step periods,
checks the arrays and calls :meth:`fusion_altitude.InsEstimator.update_batch`.
"""

from __future__ import annotations

from typing import Optional

import numpy as np

from ._core._ins import InsEstimator, InsSettings
from ._core._ins_glue import InsBatch

__all__ = ["ins_run", "step_periods"]


def step_periods(time) -> np.ndarray:
    """Step periods (s) from sample times (s): dt[i] = time[i] − time[i−1]; the first is the median period.

    Raises
    ------
    ValueError
        ``time`` not 1-D with at least 2 finite, strictly increasing samples (naming the first bad index).
    """
    t = np.asarray(time, dtype=float)
    if t.ndim != 1 or t.size < 2:
        raise ValueError(f"time must be 1-D with at least 2 samples, got shape {t.shape}")
    if not np.all(np.isfinite(t)):
        raise ValueError(f"time at index {int(np.argmax(~np.isfinite(t)))} is not finite")
    dt = np.diff(t)
    if np.any(dt <= 0):
        raise ValueError(f"time must increase strictly; it does not at index {int(np.argmax(dt <= 0)) + 1}")
    return np.concatenate([[np.median(dt)], dt])


def ins_run(time, gyro, accel, baro_altitude=None, mag=None, settings: Optional[InsSettings] = None,
            gyro_units: str = "rad/s", accel_units: str = "m/s^2") -> InsBatch:
    """The INS over a log: raw gyro and accelerometer (body frame), optional baro and magnetometer.

    Parameters
    ----------
    time : array_like, shape (N,)
        Sample times, s, strictly increasing (the IMU's clock).
    gyro, accel : array_like, shape (N, 3)
        Angular rate (rad/s or ``gyro_units``) and specific force (m/s² or ``accel_units``), body frame,
        any right-handed axes (PX4 FRD, ArduPilot FRD, a CSV's own): the first sample whose
        accelerometer reads about 1 g sets "up".
    baro_altitude : array_like, shape (N,), optional
        Baro altitude, m, on the IMU's grid; NaN on steps without a sample.
    mag : array_like, shape (N, 3), optional
        Magnetometer, body frame, any unit; all-NaN rows: no sample.
    settings : InsSettings, optional
    gyro_units, accel_units : str
        "rad/s" or "deg/s"; "m/s^2" or "g".

    Returns
    -------
    InsBatch
        Per step: ``altitude`` (m, +up, in the baro's datum), ``height_above_start`` (m above the
        first baro sample's height, +up; ``altitude`` is it plus ``baro_bias``), ``vertical_velocity``
        (m/s, +up), local and global quaternions, gyro bias, accel z bias, baro bias, stationary flag.
    """
    dt = step_periods(time)
    return InsEstimator(settings, gyro_units=gyro_units, accel_units=accel_units).update_batch(
        gyro, accel, dt, baro_altitude, mag)
