"""Glue of the gain sweep shared by ``fusion_altitude.sweep`` and
``fusion_altitude.reference.sweep``: argument checks and the result type.
"""

from __future__ import annotations

from typing import NamedTuple, Optional, Tuple

import numpy as np

from ._common import as_float32_vector
from ._observer_glue import AltitudeBatch, prepare_inputs


class SweepResult(NamedTuple):
    """What :func:`fusion_altitude.sweep` returns for K settings.

    Attributes
    ----------
    gains : numpy.ndarray
        (K, 3) float32: position_gain (1/s), velocity_gain (1/s²), bias_gain (1/s³).
    metric_samples : int
        Samples that entered the metrics (mask true and reference finite); 0
        without a reference.
    mean_error, rms_error, max_abs_error : numpy.ndarray or None
        (K,) float64 statistics of altitude − reference, m; None without a reference.
    sum_error, sum_squared_error : numpy.ndarray or None
        (K,) float32 sums they come from (m, m²), as the C kernel accumulated them.
    outputs : AltitudeBatch or None
        With ``outputs=True``: (T, K) float32 arrays, column k = setting k.
    """

    gains: np.ndarray
    metric_samples: int
    mean_error: Optional[np.ndarray]
    rms_error: Optional[np.ndarray]
    max_abs_error: Optional[np.ndarray]
    sum_error: Optional[np.ndarray]
    sum_squared_error: Optional[np.ndarray]
    outputs: Optional[AltitudeBatch]


def prepare_sweep(accel: object, baro_altitude: object, dt: object, settings: object, reference: object,
                  mask: object, outputs: bool):
    """Check and convert the arguments of ``sweep``.

    Returns (accel, baro_altitude, dt, dt_is_array, gains (K, 3) float32,
    reference float32 or None, mask uint8 or None).
    """
    accel32, baro32, dt32, dt_is_array = prepare_inputs(accel, baro_altitude, dt)
    n = accel32.shape[0]
    if reference is None and not outputs:
        raise ValueError("nothing to compute: give reference= (for metrics) or outputs=True")
    if isinstance(settings, np.ndarray) and settings.dtype.kind in "fiu":
        rows = settings
    else:
        try:
            rows = [s.as_tuple() if hasattr(s, "as_tuple") else s for s in settings]  # type: ignore[union-attr]
        except TypeError:
            raise TypeError("settings must be a sequence of AltitudeSettings or a (K, 3) gain array") from None
    with np.errstate(over="ignore"):
        gains = np.array(rows, dtype=np.float32).reshape(-1, 3) if len(rows) else np.zeros((0, 3), np.float32)
    if np.ndim(rows) not in (1, 2) or (np.ndim(rows) == 2 and np.shape(rows)[1] != 3):
        raise ValueError(f"settings must be a (K, 3) gain array, got shape {np.shape(rows)}")
    if gains.shape[0] == 0:
        raise ValueError("settings is empty")
    reference32 = None
    mask8 = None
    if reference is not None:
        reference32 = as_float32_vector(reference, "reference")
        if reference32.shape[0] != n:
            raise ValueError(f"reference has {reference32.shape[0]} samples but accel has {n}")
        if mask is not None:
            mask_array = np.asarray(mask)
            if mask_array.dtype != bool or mask_array.shape != (n,):
                raise ValueError(f"mask must be a boolean array of shape ({n},), got {mask_array.dtype} {mask_array.shape}")
            mask8 = np.ascontiguousarray(mask_array.view(np.uint8))
    elif mask is not None:
        raise ValueError("mask needs a reference")
    return accel32, baro32, dt32, dt_is_array, gains, reference32, mask8


def sweep_result(gains: np.ndarray, metric_samples: int, sums: Optional[Tuple[np.ndarray, np.ndarray, np.ndarray]],
                 outputs: Optional[AltitudeBatch]) -> SweepResult:
    """Assemble a SweepResult; mean and RMS in float64 from the float32 sums."""
    if sums is None:
        return SweepResult(gains, 0, None, None, None, None, None, outputs)
    sum_error, sum_squared, max_abs = sums
    with np.errstate(invalid="ignore", divide="ignore"):
        count = float(metric_samples)
        mean = sum_error.astype(np.float64) / count
        rms = np.sqrt(sum_squared.astype(np.float64) / count)
    if metric_samples == 0:
        max_abs = np.full_like(max_abs, np.nan)
    return SweepResult(gains, metric_samples, mean, rms, max_abs.astype(np.float64), sum_error, sum_squared, outputs)
