"""Gain sweeps and automatic tuning of the complementary observer.

:func:`sweep` runs K settings over one log in one pass of the C kernel
(``csrc/fusion_altitude_sweep.h``), column k equal bit for bit to
``AltitudeEstimator(settings[k]).update_batch(...)``; :func:`fit` searches the
bandwidth parameters ω, ζ, ω_b for the gains that best match a reference.
"""

from __future__ import annotations

import math
import os
from concurrent.futures import ThreadPoolExecutor
from typing import List, NamedTuple, Optional, Sequence, Tuple

import numpy as np

from . import _sweep, _observer_glue, _sweep_glue
from ._observer_glue import Status
from ._sweep_glue import SweepResult
from ._observer import AltitudeSettings

#: Settings per thread below which a sweep stays on one thread. Measured on the
#: 2-core dev machine (``python benchmarks/compare.py``, 10^5 samples, metrics
#: only): K = 1024 goes from 0.38 to 0.25 ns per sample·setting on two threads,
#: K = 64 gains nothing (0.37 vs 0.39: two 32-lane chunks are too little work
#: per thread to pay for the threads and the duplicated input check).
MIN_SETTINGS_PER_THREAD = 64


def sweep(accel, baro_altitude, dt, settings, reference=None, mask=None, outputs: bool = False,
          threads: Optional[int] = None, out: Optional[Sequence[np.ndarray]] = None) -> SweepResult:
    """Run K observer settings over one input stream.

    Parameters
    ----------
    accel : array_like
        Vertical acceleration per sample, m/s², earth frame, +up, gravity removed.
    baro_altitude : array_like
        Barometric altitude per sample, m; NaN where there is no baro sample.
    dt : float or array_like
        Sample period, s: one value or one per sample.
    settings : sequence of AltitudeSettings, or array_like of shape (K, 3)
        The gains (position_gain 1/s, velocity_gain 1/s², bias_gain 1/s³) of
        each setting; each must pass the checks of :class:`AltitudeSettings`.
    reference : array_like, optional
        Reference altitude per sample, m (RTK GPS, motion capture, simulator
        truth...); NaN where unknown. Enables the metrics.
    mask : array_like of bool, optional
        Samples that count in the metrics (default all with a finite reference).
    outputs : bool, default False
        Also return the (T, K) per-sample states.
    threads : int, optional
        Threads to split the K settings across; default: the CPU count, keeping
        at least 64 settings per thread (below that a split does not pay).
    out : AltitudeBatch or sequence of 4 arrays, optional
        Preallocated C-contiguous float32 (T, K) arrays for the outputs (implies
        ``outputs=True``); reusing them avoids page faults on large sweeps.

    Returns
    -------
    SweepResult
        Per-setting error statistics (mean, RMS, max |error|) of altitude −
        reference after each sample, and the outputs when asked.

    Raises
    ------
    ValueError
        Bad inputs (naming the argument and first bad index, as
        ``update_batch``), an unstable setting (naming ``settings[k]``), or
        neither ``reference`` nor ``outputs``.
    """
    outputs = outputs or out is not None
    accel32, baro32, dt32, dt_is_array, gains, reference32, mask8 = _sweep_glue.prepare_sweep(
        accel, baro_altitude, dt, settings, reference, mask, outputs)
    for k, row in enumerate(gains):
        try:
            AltitudeSettings(*row.tolist())
        except ValueError as error:
            raise ValueError(f"settings[{k}]: {error}") from None
    n, count = accel32.shape[0], gains.shape[0]
    gains_by_row = np.ascontiguousarray(gains.T)
    state = np.empty((4, count), np.float32)
    output_arrays = _observer_glue.output_arrays((n, count), out) if outputs else None
    metric_arrays = [np.zeros(count, np.float32) for _ in range(5)] if reference32 is not None else None
    if metric_arrays is not None:
        metric_arrays[2][:] = 0.0  # max |error| starts at 0
    if threads is None:
        threads = max(1, min(os.cpu_count() or 1, count // MIN_SETTINGS_PER_THREAD))
    threads = max(1, min(int(threads), count))
    bounds = np.linspace(0, count, threads + 1).astype(int)

    def run(part: int) -> Tuple[int, int, int]:
        return _sweep.run(accel32, baro32, dt32, dt_is_array, gains_by_row, int(bounds[part]), int(bounds[part + 1]),
                          state, output_arrays, metric_arrays, reference32, mask8)

    if threads == 1:
        results = [run(0)]
    else:
        with ThreadPoolExecutor(max_workers=threads) as pool:
            results = list(pool.map(run, range(threads)))
    status, bad, metric_samples = results[0]
    if status != Status.OK:
        t = dt32[bad if dt_is_array else 0]
        _observer_glue.raise_update_error(status, float(accel32[bad]), float(baro32[bad]), float(t), bad, dt_is_array)
    sums = tuple(metric_arrays[:3]) if metric_arrays is not None else None
    return _sweep_glue.sweep_result(gains, metric_samples, sums, output_arrays)


class FitResult(NamedTuple):
    """What :func:`fit` returns.

    Attributes
    ----------
    settings : AltitudeSettings
        The best gains found.
    omega, zeta, omega_b : float
        Their bandwidth parameters (rad/s, 1, rad/s).
    rms_error : float
        RMS altitude error of the best gains against the reference, m.
    default_rms_error : float
        The same metric for the default (VTOL) gains, m, for comparison.
    landscape : numpy.ndarray
        Every evaluated candidate, a structured array with fields ``omega``,
        ``zeta``, ``omega_b``, ``rms_error`` (m), best first; inf where the
        estimate overflowed.
    """

    settings: AltitudeSettings
    omega: float
    zeta: float
    omega_b: float
    rms_error: float
    default_rms_error: float
    landscape: np.ndarray


_LANDSCAPE = np.dtype([("omega", "f8"), ("zeta", "f8"), ("omega_b", "f8"), ("rms_error", "f8")])


def _stable_candidates(candidates: Sequence[Tuple[float, float, float]], dt_check: float) -> List[Tuple]:
    stable = []
    for omega, zeta, omega_b in candidates:
        try:
            settings = AltitudeSettings.from_bandwidth(omega, zeta, omega_b)
            if _stable_at(settings, dt_check):
                stable.append((omega, zeta, omega_b, settings.as_tuple()))
        except ValueError:
            continue
    return stable


def _stable_at(settings: AltitudeSettings, dt_check: float) -> bool:
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            settings.validate(dt_check)
        except ValueError:
            return False
    return True


def fit(accel, baro_altitude, dt, reference, mask=None, omega_range: Tuple[float, float] = (0.05, 20.0),
        zetas: Sequence[float] = (0.5, 0.7, 1.0, 1.4), bias_ratios: Sequence[float] = (0.0, 0.05, 0.1, 0.2, 0.35),
        refinements: int = 3, threads: Optional[int] = None) -> FitResult:
    """Find the observer gains that best match a reference altitude.

    A coarse grid over ω (log-spaced in ``omega_range``, rad/s), ζ and
    ω_b = ratio·ω, then ``refinements`` rounds of a finer grid around the best
    point. Every candidate must pass Routh–Hurwitz and Jury's test at the
    largest ``dt`` of the log; the metric is the RMS of altitude − reference
    over ``mask``.

    Parameters
    ----------
    accel, baro_altitude, dt
        As for :func:`sweep` (m/s², m, s).
    reference : array_like
        Better altitude for (part of) the log, m; NaN where unknown.
    mask : array_like of bool, optional
        Samples that count, e.g. after the start-up transient.

    Returns
    -------
    FitResult
    """
    dt_values = np.asarray(dt, dtype=np.float64)
    dt_check = float(np.max(dt_values)) if dt_values.size else 0.0
    if not math.isfinite(dt_check) or dt_check <= 0:
        raise ValueError(f"dt must be finite and > 0 (s), got {dt_check!r}")
    low, high = omega_range
    if not (0 < low < high and math.isfinite(high)):
        raise ValueError(f"omega_range must be 0 < low < high, got {omega_range!r}")
    evaluated = {}

    def evaluate(candidates):
        fresh = [c for c in _stable_candidates(candidates, dt_check) if c[:3] not in evaluated]
        if not fresh:
            return
        result = sweep(accel, baro_altitude, dt, np.array([c[3] for c in fresh]), reference=reference, mask=mask,
                       threads=threads)
        for candidate, rms in zip(fresh, result.rms_error):
            # a candidate that overflowed float32 on this log (stable on paper, not in practice) ranks last
            evaluated[candidate[:3]] = float(rms) if math.isfinite(rms) else math.inf

    omegas = np.geomspace(low, high, 24)
    evaluate([(w, z, r * w) for w in omegas for z in zetas for r in bias_ratios])
    if not evaluated:
        raise ValueError("no stable candidate at this dt: lower omega_range or sample faster")
    step = (high / low) ** (1 / 23)
    for _ in range(refinements):
        omega, zeta, omega_b = min(evaluated, key=evaluated.get)
        ratio = omega_b / omega
        step = math.sqrt(step)
        ratios = sorted({max(0.0, ratio * f) for f in (0.6, 0.8, 1.0, 1.25, 1.6)} | ({0.0} if ratio == 0 else set()))
        evaluate([(omega * step**i, z, r * omega * step**i) for i in range(-3, 4)
                  for z in (zeta * 0.8, zeta * 0.9, zeta, zeta * 1.1, zeta * 1.25) for r in ratios])
    ranked = sorted(evaluated.items(), key=lambda item: item[1])
    (omega, zeta, omega_b), best_rms = ranked[0]
    default = sweep(accel, baro_altitude, dt, [AltitudeSettings()], reference=reference, mask=mask)
    landscape = np.array([(*key, value) for key, value in ranked], dtype=_LANDSCAPE)
    return FitResult(AltitudeSettings.from_bandwidth(omega, zeta, omega_b), omega, zeta, omega_b, best_rms,
                     float(default.rms_error[0]), landscape)


def settings_for_baro_rate(settings: AltitudeSettings, steps_per_baro: float) -> AltitudeSettings:
    """Gains that keep the designed bandwidth when baro samples arrive on only 1 of ``steps_per_baro`` steps.

    The C core applies the baro correction ``K·r·dt`` with the dt of the step
    that carries the baro sample; steps without baro only integrate. With the
    baro at 1/N of the IMU rate the corrections are therefore N times too
    small and every loop runs N times slower than designed (the balloon
    scenario: 10 Hz IMU, 1 Hz baro). Multiplying all three gains by N makes
    each correction ``K·r·(N·dt)``, the designed observer sampled at the baro
    rate. ``steps_per_baro`` ≤ 1 returns ``settings`` unchanged.
    """
    if steps_per_baro <= 1.0:
        return settings
    kh, kv, kb = settings.as_tuple()
    return AltitudeSettings(kh * steps_per_baro, kv * steps_per_baro, kb * steps_per_baro)


def _bandwidth_of(settings: AltitudeSettings) -> float:
    """Position-loop bandwidth ω (rad/s) of gains built with ζ = 0.7, ω_b = ω/5 (inverts Kh = 1.6·ω)."""
    return settings.position_gain / 1.6
