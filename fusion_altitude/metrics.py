"""Error statistics for altitude estimates: after-transient errors, settling, bias convergence, noise gain."""

from __future__ import annotations

from typing import NamedTuple, Optional

import numpy as np

__all__ = [
    "ErrorStatistics",
    "error_statistics",
    "settling_time",
    "bias_convergence_time",
    "impulse_response",
    "noise_gain",
    "noise_bandwidth",
    "discrete_poles",
    "step_settling_time",
    "bias_settling_time",
]


class ErrorStatistics(NamedTuple):
    """Statistics of an error signal (estimate − truth) after a transient.

    Attributes
    ----------
    mean : float
        Mean error, m (signed).
    rms : float
        Root-mean-square error, m.
    max : float
        Largest absolute error, m.
    p50, p95, p99 : float
        Percentiles of the absolute error, m.
    count : int
        Number of samples used (finite errors after the transient).
    """

    mean: float
    rms: float
    max: float
    p50: float
    p95: float
    p99: float
    count: int


def _after(time, values, transient: float):
    time = np.asarray(time, dtype=float)
    values = np.asarray(values, dtype=float)
    if time.shape != values.shape:
        raise ValueError(f"time has shape {time.shape} but the values have {values.shape}")
    keep = (time > time[0] + transient) & np.isfinite(values) if time.size else np.zeros(0, bool)
    return time[keep], values[keep]


def error_statistics(time, error, transient: float = 5.0) -> ErrorStatistics:
    """Statistics of ``error`` over samples later than ``transient`` s after the first.

    Parameters
    ----------
    time : array_like
        Sample times, s.
    error : array_like
        Estimate − truth, m (or any unit: the results carry it). NaNs are ignored.
    transient : float, default 5.0
        Samples with time ≤ time[0] + transient are excluded, s.

    Returns
    -------
    ErrorStatistics

    Raises
    ------
    ValueError
        No finite sample after the transient, or mismatched shapes.
    """
    _, e = _after(time, error, transient)
    if e.size == 0:
        raise ValueError(f"no finite error samples after the {transient} s transient")
    magnitude = np.abs(e)
    p50, p95, p99 = np.percentile(magnitude, [50, 95, 99])
    return ErrorStatistics(float(np.mean(e)), float(np.sqrt(np.mean(e * e))), float(np.max(magnitude)),
                           float(p50), float(p95), float(p99), int(e.size))


def settling_time(time, error, tolerance: float) -> float:
    """Time (s, from time[0]) after which |error| stays within ``tolerance`` to the end.

    Parameters
    ----------
    time : array_like
        Sample times, s.
    error : array_like
        Error signal (same unit as ``tolerance``); NaN counts as outside.
    tolerance : float
        Band half-width, > 0.

    Returns
    -------
    float
        0 if the error is always inside; ``inf`` if the last sample is outside.
    """
    time = np.asarray(time, dtype=float)
    outside = ~(np.abs(np.asarray(error, dtype=float)) <= tolerance)
    if not outside.any():
        return 0.0
    last = int(np.flatnonzero(outside)[-1])
    if last == time.size - 1:
        return float("inf")
    return float(time[last + 1] - time[0])


def bias_convergence_time(time, bias_estimate, true_bias, tolerance: Optional[float] = None) -> float:
    """Time (s) after which the bias estimate stays within ``tolerance`` of the true bias.

    Parameters
    ----------
    time : array_like
        Sample times, s.
    bias_estimate : array_like
        Estimated accelerometer bias, m/s².
    true_bias : float or array_like
        True bias, m/s².
    tolerance : float, optional
        m/s²; default 20 % of |true_bias| (at least 0.01 m/s²).

    Returns
    -------
    float
        As :func:`settling_time`.
    """
    true = np.asarray(true_bias, dtype=float)
    if tolerance is None:
        tolerance = max(0.2 * float(np.max(np.abs(true))), 0.01)
    return settling_time(time, np.asarray(bias_estimate, dtype=float) - true, tolerance)


def impulse_response(position_gain: float, velocity_gain: float, bias_gain: float, dt: float,
                     duration: Optional[float] = None) -> np.ndarray:
    """Altitude response (m) of the discrete observer to a 1 m baro impulse at the first sample.

    Float64 simulation of the update in ``csrc/fusion_altitude.h`` with zero
    acceleration. ``duration`` (s) defaults to 40 time constants of the
    slowest pole (at least 10 s).
    """
    roots = np.roots([1.0, position_gain, velocity_gain, bias_gain])
    slowest = float(np.min(np.abs(roots.real))) if roots.size else 1.0
    if duration is None:
        duration = max(10.0, 40.0 / max(slowest, 1e-3))
    n = int(min(duration / dt, 5_000_000))
    h = v = b = 0.0
    out = np.empty(n)
    z = 1.0
    for i in range(n):
        r = z - h
        v += (-b + velocity_gain * r) * dt
        h += (v + position_gain * r) * dt
        b -= bias_gain * r * dt
        out[i] = h
        z = 0.0
    return out


def noise_gain(position_gain: float, velocity_gain: float, bias_gain: float, dt: float) -> float:
    """Standard deviation of the altitude estimate per unit white baro noise (dimensionless).

    For baro noise of standard deviation σ (m) at every step, the estimate's
    noise is ``noise_gain · σ``: the square root of the sum of squares of
    :func:`impulse_response`.
    """
    response = impulse_response(position_gain, velocity_gain, bias_gain, dt)
    return float(np.sqrt(np.sum(response * response)))


def noise_bandwidth(position_gain: float, velocity_gain: float, bias_gain: float, dt: float) -> float:
    """Equivalent noise bandwidth of the baro → altitude path, Hz (one-sided).

    White baro noise spread over 0 … 1/(2·dt) Hz comes out with variance
    ``noise_gain² · σ²``; the equivalent brick-wall bandwidth is
    ``noise_gain² / (2·dt)``.
    """
    return noise_gain(position_gain, velocity_gain, bias_gain, dt) ** 2 / (2.0 * dt)


def discrete_poles(position_gain: float, velocity_gain: float, bias_gain: float, dt: float) -> np.ndarray:
    """Eigenvalues z of the observer's discrete update at sample period ``dt`` (s); stable iff all |z| < 1.

    The homogeneous update of (h, v·dt, b·dt²) is the matrix
    [[1−p−q, 1, −1], [−q, 1, −1], [s, 0, 1]] with p = Kh·dt, q = Kv·dt², s = Kb·dt³
    (see ``FusionAltitudeSettingsValidate`` in ``csrc/fusion_altitude.h``).
    """
    p, q, s = position_gain * dt, velocity_gain * dt * dt, bias_gain * dt ** 3
    return np.linalg.eigvals(np.array([[1 - p - q, 1.0, -1.0], [-q, 1.0, -1.0], [s, 0.0, 1.0]]))


def _simulate(position_gain, velocity_gain, bias_gain, dt, duration, accel_bias=0.0, baro_step=0.0):
    n = int(round(duration / dt))
    h = v = b = 0.0
    altitude = np.empty(n)
    bias = np.empty(n)
    for i in range(n):
        r = baro_step - h
        v += (accel_bias - b + velocity_gain * r) * dt
        h += (v + position_gain * r) * dt
        b -= bias_gain * r * dt
        altitude[i] = h
        bias[i] = b
    return np.arange(1, n + 1) * dt, altitude, bias


def step_settling_time(position_gain: float, velocity_gain: float, bias_gain: float, dt: float,
                       tolerance: float = 0.02, duration: float = 600.0) -> float:
    """Time (s) for the altitude estimate to settle within ``tolerance`` (fraction) of a baro step.

    Simulates the discrete observer (float64) from rest with a 1 m step in
    the baro altitude and zero acceleration.
    """
    time, altitude, _ = _simulate(position_gain, velocity_gain, bias_gain, dt, duration, baro_step=1.0)
    return settling_time(np.concatenate([[0.0], time]), np.concatenate([[-1.0], altitude - 1.0]), tolerance)


def bias_settling_time(position_gain: float, velocity_gain: float, bias_gain: float, dt: float,
                       tolerance: float = 0.02, duration: float = 600.0) -> float:
    """Time (s) for the bias estimate to settle within ``tolerance`` (fraction) of a constant accel bias.

    Simulates the discrete observer (float64) from rest with a 1 m/s² accel
    bias and a constant baro; ``inf`` when bias estimation is off (Kb = 0).
    """
    if bias_gain <= 0:
        return float("inf")
    time, _, bias = _simulate(position_gain, velocity_gain, bias_gain, dt, duration, accel_bias=1.0)
    return settling_time(np.concatenate([[0.0], time]), np.concatenate([[-1.0], bias - 1.0]), tolerance)
