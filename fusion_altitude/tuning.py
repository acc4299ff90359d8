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
from typing import Callable, List, NamedTuple, Optional, Sequence, Tuple

import numpy as np

from ._core import _sweep, _observer_glue, _sweep_glue
from ._core._c_tables import FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT, FUSION_ALTITUDE_DEFAULT_GAP_PERIOD, FUSION_ALTITUDE_MAXIMUM_GAIN
from ._core._observer_glue import Status
from ._core._sweep_glue import SweepResult
from ._core._observer import AltitudeSettings

#: Settings per thread below which a sweep stays on one thread. Measured on the
#: 2-core dev machine (``python benchmarks/compare.py``, 10^5 samples, metrics
#: only): K = 1024 goes from 0.38 to 0.25 ns per sample·setting on two threads,
#: K = 64 gains nothing (0.37 vs 0.39: two 32-lane chunks are too little work
#: per thread to pay for the threads and the duplicated input check).
MIN_SETTINGS_PER_THREAD = 64


#: A log's update longer than this many nominal (median) periods is a gap (:func:`gap_period_for`).
GAP_PERIODS = 10.0

#: The observer's default gap period, s (C FUSION_ALTITUDE_DEFAULT_GAP_PERIOD).
DEFAULT_GAP_PERIOD = FUSION_ALTITUDE_DEFAULT_GAP_PERIOD

#: The observer's default baro timeout, s (C FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT).
DEFAULT_BARO_TIMEOUT = FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT


def nominal_dt(dt) -> float:
    """The nominal sample period of per-sample periods ``dt`` (s): the median of the finite positive ones
    (a scalar is its own), taken from their float32 values as the C cores see them; 0 when there is none.
    Gaps do not move it."""
    values = np.asarray(dt, dtype=np.float32).astype(np.float64).reshape(-1)  # as the cores see it
    values = values[np.isfinite(values) & (values > 0)]
    return float(np.median(values)) if values.size else 0.0


def gap_period_for(dt, default: float = DEFAULT_GAP_PERIOD) -> float:
    """The gap period for a log, s: ``max(default, GAP_PERIODS × nominal dt)``.

    An estimator's default gap period (0.5 s; 1.5 s for the alpha-beta fusion)
    is made for 50–1000 Hz updates. On a slow log (a 1 Hz CSV) every step
    would exceed it, every step would be a gap and the estimate would silently
    be the raw baro; ten nominal periods keep a real logging gap a gap at any
    rate. ``run``, ``compare``, ``fit`` (and the fleet fit, through
    :func:`sweep`) all use this one rule.
    """
    return max(float(default), GAP_PERIODS * nominal_dt(dt))


#: s after each logging gap left out of every fit metric (:func:`without_gap_transients`): one time constant of
#: the default gains' bias loop, 1/(ζ·ω_b) = 1/(0.7 × 0.3 rad/s) ≈ 4.76 s.
GAP_SETTLING = 1.0 / (0.7 * 0.3)


def without_gap_transients(dt, mask=None, window: float = GAP_SETTLING):
    """``mask`` with the samples of each logging gap's transient cleared: from the first sample after a gap
    (a dt above :func:`gap_period_for` of ``dt``) to ``window`` s after it.

    Every candidate restarts after a gap, and its restart transient (fast
    gains settle sooner) would otherwise rank the gains: on the simulated
    ``realistic`` flight with one 2 s gap in the training part the fit
    chose ω = 4.9 rad/s (held-out RMS 0.035 m against the default's 0.028 m);
    with the window it chooses ω = 1.43 rad/s as on the log without a gap
    (0.0271 m). :func:`fit`, :func:`fit_held_out` and the fleet fit all
    score through it.

    Parameters
    ----------
    dt : float or array_like
        Per-sample periods, s (a scalar: no gap).
    mask : array_like of bool, optional
        Samples that count; None: all.
    window : float
        s after the first sample after each gap.

    Returns
    -------
    numpy.ndarray of bool or None
        The mask (a new array), or ``mask`` unchanged (None stays None) when there is no gap.
    """
    values = np.asarray(dt, dtype=np.float64)
    if values.ndim == 0:
        return mask
    gaps = np.flatnonzero(values.astype(np.float32) > np.float32(gap_period_for(values)))
    if gaps.size == 0:
        return mask
    time = np.cumsum(values)
    keep = np.ones(values.size, dtype=bool) if mask is None else np.array(mask, dtype=bool, copy=True)
    for index in gaps:
        keep[(time >= time[index]) & (time < time[index] + window)] = False
    return keep


def _all_gains_valid(gains: np.ndarray) -> bool:
    """FusionAltitudeSettingsCheck on every row of float32 (K, 3) gains at once (Kh 1/s, Kv 1/s², Kb 1/s³):
    finite, >= 0, <= FUSION_ALTITUDE_MAXIMUM_GAIN, and Routh–Hurwitz (Kh·Kv > Kb in float32 when Kb > 0; Kh > 0
    when Kv > 0). A K-row loop of AltitudeSettings costs ~10 µs a row, which on a short log is most of a large
    sweep's time."""
    kh, kv, kb = (np.asarray(gains[:, i], dtype=np.float32) for i in range(3))
    top = np.float32(FUSION_ALTITUDE_MAXIMUM_GAIN)
    with np.errstate(over="ignore", invalid="ignore"):
        finite = np.isfinite(kh) & np.isfinite(kv) & np.isfinite(kb) & (kh >= 0) & (kv >= 0) & (kb >= 0) \
            & (kh <= top) & (kv <= top) & (kb <= top)
        stable = np.where(kb > 0, kh * kv > kb, ~((kv > 0) & ~(kh > 0)))
    return bool(np.all(finite & stable))


def sweep(accel, baro_altitude, dt, settings, reference=None, mask=None, outputs: bool = False,
          threads: Optional[int] = None, out: Optional[Sequence[np.ndarray]] = None,
          gap_period: Optional[float] = None, baro_timeout: float = DEFAULT_BARO_TIMEOUT) -> SweepResult:
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
    gap_period : float, optional
        s, shared by every setting: a step whose dt exceeds it is a gap (as
        ``AltitudeSettings.gap_period``); default :func:`gap_period_for` of
        ``dt`` (0.5 s, or ten nominal periods on a log slower than 20 Hz).
    baro_timeout : float, default 2.0
        s, shared by every setting: with no baro sample for longer than this
        the observers stop dead-reckoning (as ``AltitudeSettings.baro_timeout``).

    Returns
    -------
    SweepResult
        Per-setting error statistics (mean, RMS, max |error|) of altitude −
        reference after each sample, and the outputs when asked.

    Notes
    -----
    The settings share one timeline: a baro step that the stability rule (``FusionAltitudeIsStepStable``) makes
    a gap for any setting is a gap for all of them, so column k equals its own observer except at such steps.

    Raises
    ------
    ValueError
        Bad inputs (naming the argument and first bad index, as
        ``update_batch``), an unstable setting (naming ``settings[k]``), or
        neither ``reference`` nor ``outputs``.
    """
    inputs = _SweepInputs(*_sweep_glue.prepare_sweep(accel, baro_altitude, dt, settings, reference, mask,
                                                     outputs or out is not None))
    _check_sweep_gains(inputs.gains, settings)
    gap_period = _sweep_gap_period(inputs, gap_period, baro_timeout)
    return _run_sweep(inputs, outputs or out is not None, out, threads, gap_period, float(baro_timeout))


class _SweepInputs(NamedTuple):
    """:func:`sweep`'s inputs as the kernel takes them (``_sweep_glue.prepare_sweep``)."""

    accel: np.ndarray  # float32 (T,), m/s²
    baro_altitude: np.ndarray  # float32 (T,), m, NaN without a sample
    dt: np.ndarray  # float32 (T,) or (1,), s
    dt_is_array: bool
    gains: np.ndarray  # float32 (K, 3)
    reference: Optional[np.ndarray]  # float32 (T,), m, or None
    mask: Optional[np.ndarray]  # uint8 (T,), or None


def _check_sweep_gains(gains: np.ndarray, settings) -> None:
    """ValueError naming ``settings[k]`` (with AltitudeSettings' own message) for the first bad row of gains."""
    if _all_gains_valid(gains):
        return
    given = np.asarray(settings, dtype=float).reshape(gains.shape)  # the values as given, not as float32
    for k, row in enumerate(given):
        try:
            AltitudeSettings(*row.tolist())
        except ValueError as error:
            raise ValueError(f"settings[{k}]: {error}") from None


def _sweep_gap_period(inputs: _SweepInputs, gap_period: Optional[float], baro_timeout: float) -> float:
    """The sweep's gap period, s (default :func:`gap_period_for` of dt); ValueError for a bad period or timeout."""
    if gap_period is None:
        gap_period = gap_period_for(inputs.dt if inputs.dt_is_array else inputs.dt[:1])
    gap_period = float(gap_period)
    if not gap_period > 0:
        raise ValueError(f"gap_period must be > 0 (s; +inf: never a gap), got {gap_period!r}")
    if not float(baro_timeout) > 0:
        raise ValueError(f"baro_timeout must be > 0 (s; +inf: never times out), got {baro_timeout!r}")
    return gap_period


def _run_sweep(inputs: _SweepInputs, outputs: bool, out, threads: Optional[int], gap_period: float,
               baro_timeout: float) -> SweepResult:
    """Run the sweep kernel over the settings, split across ``threads``; raise the first sample's input error."""
    n, count = inputs.accel.shape[0], inputs.gains.shape[0]
    gains_by_row = np.ascontiguousarray(inputs.gains.T)
    state = np.empty((4, count), np.float32)
    output_arrays = _observer_glue.output_arrays((n, count), out) if outputs else None
    metric_arrays = [np.zeros(count, np.float32) for _ in range(5)] if inputs.reference is not None else None
    if metric_arrays is not None:
        metric_arrays[2][:] = 0.0  # max |error| starts at 0
    if threads is None:
        threads = max(1, min(os.cpu_count() or 1, count // MIN_SETTINGS_PER_THREAD))
    threads = max(1, min(int(threads), count))
    bounds = np.linspace(0, count, threads + 1).astype(int)

    def run(part: int) -> Tuple[int, int, int]:
        return _sweep.run(inputs.accel, inputs.baro_altitude, inputs.dt, inputs.dt_is_array, gains_by_row,
                          int(bounds[part]), int(bounds[part + 1]), state, output_arrays, metric_arrays,
                          inputs.reference, inputs.mask, gap_period, baro_timeout)

    if threads == 1:
        results = [run(0)]
    else:
        with ThreadPoolExecutor(max_workers=threads) as pool:
            results = list(pool.map(run, range(threads)))
    status, bad, metric_samples = results[0]
    if status != Status.OK:
        t = inputs.dt[bad if inputs.dt_is_array else 0]
        _observer_glue.raise_update_error(status, float(inputs.accel[bad]), float(inputs.baro_altitude[bad]),
                                          float(t), bad, inputs.dt_is_array)
    sums = tuple(metric_arrays[:3]) if metric_arrays is not None else None
    return _sweep_glue.sweep_result(inputs.gains, metric_samples, sums, output_arrays)


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


LANDSCAPE_DTYPE = np.dtype([("omega", "f8"), ("zeta", "f8"), ("omega_b", "f8"), ("rms_error", "f8")])


def _stable_candidates(candidates: Sequence[Tuple[float, float, float]], dt_check: float) -> List[Tuple]:
    stable = []
    for omega, zeta, omega_b in candidates:
        try:
            settings = AltitudeSettings.from_bandwidth(omega, zeta, omega_b)
            if stable_at(settings, dt_check):
                stable.append((omega, zeta, omega_b, settings.as_tuple()))
        except ValueError:
            continue
    return stable


def stable_at(settings: AltitudeSettings, dt_check: float) -> bool:
    """Jury's test at ``dt_check`` (s) and the core's stability rule there (``FusionAltitudeIsStepStable``: Jury
    with the 1.5 margin): gains past the rule would make every baro step a gap, in a sweep for every setting."""
    import warnings

    from .reference.observer import step_stable
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            settings.validate(dt_check)
        except ValueError:
            return False
    dt32 = np.float32(dt_check)
    return step_stable(*(np.float32(g) for g in settings.as_tuple()), dt32, dt32)


def fit(accel, baro_altitude, dt, reference, mask=None, omega_range: Tuple[float, float] = (0.05, 20.0),
        zetas: Sequence[float] = (0.5, 0.7, 1.0, 1.4), bias_ratios: Sequence[float] = (0.0, 0.05, 0.1, 0.2, 0.35),
        refinements: int = 3, threads: Optional[int] = None, steps_per_baro: float = 1.0,
        stability_dt: Optional[float] = None,
        progress: Optional[Callable[[int, int], None]] = None) -> FitResult:
    """Find the observer gains that best match a reference altitude.

    A coarse grid over ω (log-spaced in ``omega_range``, rad/s), ζ and
    ω_b = ratio·ω, then ``refinements`` rounds of a finer grid around the best
    point. Every candidate must pass Routh–Hurwitz and Jury's test at the
    log's nominal period (``stability_dt``, default the median ``dt``, so a
    logging gap does not rule out every useful gain); the metric is the RMS
    of altitude − reference over ``mask``, without the transient after each
    logging gap (:func:`without_gap_transients`).

    Parameters
    ----------
    accel, baro_altitude, dt
        As for :func:`sweep` (m/s², m, s).
    reference : array_like
        Better altitude for (part of) the log, m; NaN where unknown.
    mask : array_like of bool, optional
        Samples that count, e.g. after the start-up transient.
    omega_range : (float, float)
        Lowest and highest ω searched, rad/s.
    steps_per_baro : float, default 1
        Grid steps per baro sample (:func:`steps_per_baro`): every candidate
        and the default run with :func:`settings_for_baro_rate` applied, as
        ``run`` and ``compare`` run them; the returned settings are the
        designed (uncompensated) ones. Stability is checked for the designed
        gains at ``stability_dt · steps_per_baro``.
    stability_dt : float, optional
        Period of the stability check, s; default the median of ``dt``.
    progress : callable(done, total), optional
        Called after each search round (coarse grid, refinements, default).

    Returns
    -------
    FitResult

    Raises
    ------
    ValueError
        A non-positive ``dt``, a bad ``omega_range``, or no stable candidate.
    """
    dt_check = stability_period(dt, steps_per_baro, stability_dt)
    mask = without_gap_transients(dt, mask)
    tick = _round_counter(progress, refinements + 2)

    def evaluate_rms(gains: np.ndarray) -> np.ndarray:
        return score(accel, baro_altitude, dt, reference, mask, gains, steps_per_baro, threads).rms_error

    ranked = search(evaluate_rms, dt_check, omega_range, zetas, bias_ratios, refinements, tick)
    default = score(accel, baro_altitude, dt, reference, mask, np.array([AltitudeSettings().as_tuple()]),
                    steps_per_baro)
    tick()
    return fit_result(ranked, float(default.rms_error[0]))


def _round_counter(progress: Optional[Callable[[int, int], None]], total: int) -> Callable[[], None]:
    """A function that counts the search rounds done and reports each to ``progress(done, total)``, if given."""
    done = [0]

    def tick() -> None:
        done[0] += 1
        if progress is not None:
            progress(done[0], total)

    return tick


def fit_result(ranked: Sequence[Tuple[Tuple[float, float, float], float]], default_rms_error: float) -> FitResult:
    """The :class:`FitResult` of :func:`search`'s ranked candidates ((ω, ζ, ω_b), RMS m; best first) and the
    default gains' RMS error, m."""
    (omega, zeta, omega_b), best_rms = ranked[0]
    landscape = np.array([(*key, value) for key, value in ranked], dtype=LANDSCAPE_DTYPE)
    return FitResult(AltitudeSettings.from_bandwidth(omega, zeta, omega_b), omega, zeta, omega_b, best_rms,
                     default_rms_error, landscape)


# The pieces of :func:`fit`, public so that the fleet fit (fusion_altitude.fleet.fit_many) runs the very same
# steps on many logs: change the fit here and both follow.


def stability_period(dt, steps_per_baro: float = 1.0, stability_dt: Optional[float] = None) -> float:
    """The period at which :func:`fit` checks a candidate's stability, s.

    ``stability_dt`` (default the median of the positive ``dt``: a logging gap
    does not rule out every useful gain) times ``max(steps_per_baro, 1)`` (the
    designed gains, run at 1 baro sample per ``steps_per_baro`` steps with
    :func:`settings_for_baro_rate`, act once per baro period).

    Raises
    ------
    ValueError
        The period is not finite and > 0.
    """
    dt_values = np.asarray(dt, dtype=np.float64)
    if stability_dt is None:
        positive = dt_values[np.isfinite(dt_values) & (dt_values > 0)] if dt_values.ndim else dt_values.reshape(1)
        stability_dt = float(np.median(positive)) if positive.size else 0.0
    dt_check = float(stability_dt) * max(float(steps_per_baro), 1.0)
    if not math.isfinite(dt_check) or dt_check <= 0:
        raise ValueError(f"dt must be finite and > 0 (s), got {float(stability_dt)}")
    return dt_check


def training_mask(time, skip: float) -> np.ndarray:
    """Samples ``fusion-altitude fit`` scores: after the first ``skip`` s (``time > time[0] + skip``)."""
    time = np.asarray(time, dtype=float)
    return time > time[0] + skip


def score(accel, baro_altitude, dt, reference, mask, gains, steps_per_baro: float = 1.0,
          threads: Optional[int] = None) -> SweepResult:
    """The metric of :func:`fit`: designed gains (K, 3) run as ``run`` runs them, scored against ``reference``.

    Each row (Kh 1/s, Kv 1/s², Kb 1/s³) is multiplied by ``max(steps_per_baro, 1)``
    (:func:`settings_for_baro_rate`) and swept over the log (:func:`sweep`); the
    result's ``rms_error`` is what :func:`fit` ranks by, its
    ``sum_squared_error`` and ``metric_samples`` what the fleet fit adds over logs.
    """
    gains = np.asarray(gains, dtype=np.float64) * max(float(steps_per_baro), 1.0)
    return sweep(accel, baro_altitude, dt, gains, reference=reference, mask=mask, threads=threads)


def search(evaluate_rms: Callable[[np.ndarray], np.ndarray], dt_check: float,
           omega_range: Tuple[float, float] = (0.05, 20.0), zetas: Sequence[float] = (0.5, 0.7, 1.0, 1.4),
           bias_ratios: Sequence[float] = (0.0, 0.05, 0.1, 0.2, 0.35), refinements: int = 3,
           round_done: Optional[Callable[[], None]] = None) -> List[Tuple[Tuple[float, float, float], float]]:
    """The candidate search of :func:`fit`, the metric supplied by the caller.

    A coarse grid over ω (24 values log-spaced in ``omega_range``, rad/s), ζ
    and ω_b = ratio·ω, then ``refinements`` rounds of a finer grid around the
    best point. Only candidates stable at ``dt_check`` (s, :func:`stability_period`)
    are evaluated: ``evaluate_rms`` gets their designed gains as a (K, 3) array
    and returns K RMS errors (m; a non-finite one ranks last). ``round_done`` is
    called after each round.

    Returns
    -------
    list of ((ω, ζ, ω_b), rms)
        Every evaluated candidate, best first.

    Raises
    ------
    ValueError
        A bad ``omega_range`` or no stable candidate.
    """
    low, high = (float(v) for v in omega_range)
    if not (0 < low < high and math.isfinite(high)):
        raise ValueError(f"omega_range must be 0 < low < high, got ({low:g}, {high:g})")
    evaluated = {}

    def evaluate(candidates):
        fresh = [c for c in _stable_candidates(candidates, dt_check) if c[:3] not in evaluated]
        if fresh:
            rms_values = evaluate_rms(np.array([c[3] for c in fresh]))
            for candidate, rms in zip(fresh, rms_values):
                # a candidate that overflowed float32 on this log (stable on paper, not in practice) ranks last
                evaluated[candidate[:3]] = float(rms) if math.isfinite(rms) else math.inf
        if round_done is not None:
            round_done()

    omegas = np.geomspace(low, high, 24)
    evaluate([(w, z, r * w) for w in omegas for z in zetas for r in bias_ratios])
    if not evaluated:
        raise ValueError(f"no stable candidate at the nominal period {dt_check:g} s: lower omega_range or sample "
                         "faster")
    step = (high / low) ** (1 / 23)
    for _ in range(refinements):
        omega, zeta, omega_b = min(evaluated, key=evaluated.get)
        ratio = omega_b / omega
        step = math.sqrt(step)
        ratios = sorted({max(0.0, ratio * f) for f in (0.6, 0.8, 1.0, 1.25, 1.6)} | ({0.0} if ratio == 0 else set()))
        evaluate([(omega * step**i, z, r * omega * step**i) for i in range(-3, 4)
                  for z in (zeta * 0.8, zeta * 0.9, zeta, zeta * 1.1, zeta * 1.25) for r in ratios])
    return sorted(evaluated.items(), key=lambda item: item[1])


class HeldOutFit(NamedTuple):
    """What :func:`fit_held_out` returns.

    Attributes
    ----------
    fit : FitResult
        The fit on the training part.
    settings : AltitudeSettings
        The gains to use: the fitted ones if they beat (or equal) the default
        on the held-out part, else the default (VTOL) gains.
    fitted_rms_error, default_rms_error : float
        RMS altitude − reference on the held-out part, m, of the fitted and
        the default gains (both baro-rate compensated).
    generalises : bool
        Whether the fitted gains won on the held-out part.
    train_until : float
        Time splitting training (before) and held-out (from) samples, s.
    """

    fit: FitResult
    settings: AltitudeSettings
    fitted_rms_error: float
    default_rms_error: float
    generalises: bool
    train_until: float


def fit_held_out(time, accel, baro_altitude, reference, train_until: float, skip: float = 0.0,
                 **fit_options) -> HeldOutFit:
    """Fit on the samples before ``train_until`` and score fitted vs default gains on the rest.

    Parameters
    ----------
    time : array_like
        Sample times, s, increasing.
    accel, baro_altitude, reference : array_like
        As for :func:`fit` (m/s², m, m).
    train_until : float
        Absolute time, s: samples before it (and after ``skip``) train, the
        samples from it on are held out (both without the transient after
        each logging gap, :func:`without_gap_transients`). The whole log is run in both cases
        (the held-out part starts from the state the training part left).
    skip : float, default 0
        Seconds after the first sample left out of the training metric.
    **fit_options
        Passed to :func:`fit` (``omega_range``, ``steps_per_baro``, ``progress``...).

    Returns
    -------
    HeldOutFit

    Raises
    ------
    ValueError
        No reference sample on one side of ``train_until``.
    """
    time = np.asarray(time, dtype=float)
    reference = np.asarray(reference, dtype=float)
    has_reference = np.isfinite(reference)
    train = training_mask(time, skip) & (time < train_until) & has_reference
    held_out = (time >= train_until) & has_reference
    if not train.any():
        raise ValueError(f"train_until {train_until:g} s leaves no reference sample to train on")
    if not held_out.any():
        raise ValueError(f"train_until {train_until:g} s leaves no reference sample to hold out")
    dt = _sample_periods(time)
    result = fit(accel, baro_altitude, dt, reference, mask=train, **fit_options)
    factor = max(float(fit_options.get("steps_per_baro", 1.0)), 1.0)
    scores = sweep(accel, baro_altitude, dt, np.array([result.settings.as_tuple(), AltitudeSettings().as_tuple()])
                   * factor, reference=reference, mask=without_gap_transients(dt, held_out))
    fitted_rms, default_rms = (float(v) for v in scores.rms_error)
    generalises = bool(fitted_rms <= default_rms)
    return HeldOutFit(result, result.settings if generalises else AltitudeSettings(), fitted_rms, default_rms,
                      generalises, float(train_until))


def _sample_periods(time: np.ndarray) -> np.ndarray:
    dt = np.empty(time.size)
    dt[1:] = np.diff(time)
    dt[:1] = dt[1] if time.size > 1 else 0.01
    return dt


def steps_per_baro(baro_altitude) -> float:
    """Grid steps per baro sample (≥ 1) where the baro is present: the median number of steps from one baro
    sample to the next; 1 when there are fewer than two baro samples.

    The one figure ``run``, ``fit`` and ``compare`` pass to :func:`settings_for_baro_rate`. The median of the
    intervals, not samples / baro samples: on a log whose baro stream stops early (a PX4 log with the baro up to
    14.4 s of 72 s) the average over the whole log would be 5× the baro's own rate and the gains 5× too high.
    """
    baro = np.asarray(baro_altitude, dtype=float)
    finite = np.flatnonzero(np.isfinite(baro))
    if finite.size < 2:
        return 1.0
    return max(float(np.median(np.diff(finite))), 1.0)


#: A log's baro timeout is at least this many of its baro periods (:func:`baro_timeout_for`).
BARO_TIMEOUT_PERIODS = 5.0


def baro_timeout_for(time, baro_altitude, default: float = DEFAULT_BARO_TIMEOUT) -> float:
    """The baro timeout for a log, s: ``max(default, BARO_TIMEOUT_PERIODS × the log's baro period)``, so a slow baro
    (a 1 Hz CSV) does not time out between its own samples while a baro that stops still does."""
    period = baro_interval(time, baro_altitude)
    return max(float(default), BARO_TIMEOUT_PERIODS * period) if np.isfinite(period) else float(default)


def not_baro_aided(dt, baro_altitude, baro_timeout: float) -> np.ndarray:
    """Per sample, True where the estimate is not baro-aided: more than ``baro_timeout`` s (the cores' rule,
    ``sinceBaro > baroTimeout``) since the latest baro sample, from the first baro sample on; the cores' own flag
    (``baro_timed_out``) at the end of a run is the same rule (float64 sums here)."""
    baro = np.isfinite(np.asarray(baro_altitude, dtype=float))
    dt = np.broadcast_to(np.asarray(dt, dtype=float), baro.shape)
    since = np.zeros(baro.size)
    elapsed = 0.0
    started = False
    for i in range(baro.size):
        if baro[i]:
            elapsed, started = 0.0, True
        elif started:
            elapsed += dt[i]
        since[i] = elapsed if started else 0.0
    return since > baro_timeout


def baro_interval(time, baro_altitude) -> float:
    """The log's baro period, s: the median time from one baro sample to the next (the baro's rate where it is
    present, whatever the rest of the log holds); NaN with fewer than two baro samples."""
    time = np.asarray(time, dtype=float)
    finite = np.flatnonzero(np.isfinite(np.asarray(baro_altitude, dtype=float)))
    if finite.size < 2:
        return float("nan")
    return float(np.median(np.diff(time[finite])))


#: Shortest period :func:`report` accepts, s (its settling times simulate 600 s at this step in float64).
MIN_REPORT_DT = 1e-4


class TuneReport(NamedTuple):
    """What :func:`report` returns: what a set of gains does at a sample period.

    Attributes
    ----------
    settings : AltitudeSettings
        The gains (1/s, 1/s², 1/s³).
    dt : float
        Sample period, s.
    poles : list of (complex, float, complex)
        Per pole: continuous pole s (rad/s), its time constant 1/|Re s| (s),
        and the discrete pole z (at ``dt``) paired with it (the z nearest
        exp(s·dt)).
    step_settling, bias_settling : float
        2 % settling time of the altitude after a baro step and of the bias
        estimate after an accel-bias step, s (inf when bias estimation is off).
    checks : list of (str, bool, str)
        Named checks with their result and the figure checked.
    noise_gain : float
        Altitude noise sd per m of white baro noise per sample.
    noise_bandwidth : float
        Equivalent noise bandwidth of baro → altitude, Hz.
    stable : bool
        Routh–Hurwitz and Jury both pass.
    """

    settings: AltitudeSettings
    dt: float
    poles: list
    step_settling: float
    bias_settling: float
    checks: list
    noise_gain: float
    noise_bandwidth: float
    stable: bool


def report(settings: AltitudeSettings, dt: float, omega: Optional[float] = None,
           omega_b: Optional[float] = None) -> TuneReport:
    """Poles, settling times, stability checks and noise bandwidth of ``settings`` at period ``dt``.

    Parameters
    ----------
    settings : AltitudeSettings
        The gains.
    dt : float
        Sample period, s, finite and >= :data:`MIN_REPORT_DT` (1e-4 s).
    omega, omega_b : float, optional
        The bandwidths the gains were built from (rad/s); with both, the
        loop-separation check ω_b ≤ ω/5 is added.

    Returns
    -------
    TuneReport

    Raises
    ------
    ValueError
        ``dt`` not finite or below :data:`MIN_REPORT_DT`.
    """
    import itertools
    import warnings

    from . import metrics

    dt = float(dt)
    if not (math.isfinite(dt) and dt >= MIN_REPORT_DT):
        raise ValueError(f"dt must be finite and >= {MIN_REPORT_DT:g} s (the settling times simulate 600 s "
                         f"step by step), got {dt:g}")
    kh, kv, kb = settings.as_tuple()
    s_poles = sorted(np.roots([1.0, kh, kv, kb]), key=lambda p: (abs(p), p.imag))
    z_poles = list(metrics.discrete_poles(kh, kv, kb, dt))
    targets = [np.exp(p * dt) for p in s_poles]
    best = min(itertools.permutations(range(len(z_poles))),
               key=lambda order: sum(abs(z_poles[j] - t) for j, t in zip(order, targets)))
    poles = [(complex(s), 1.0 / abs(s.real) if s.real != 0 else math.inf, complex(z_poles[j]))
             for s, j in zip(s_poles, best)]
    largest = float(max(abs(z) for z in z_poles))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            settings.validate(dt)
            jury = (True, f"max |z| = {largest:.6f} < 1")
        except ValueError:
            jury = (False, f"max |z| = {largest:.6f} >= 1: diverges at this rate")
    fastest = float(max(abs(s) for s in s_poles))
    checks = [("Routh-Hurwitz: Kh·Kv > Kb", kh * kv > kb, f"{kh * kv:.4g} > {kb:.4g}"),
              ("Jury: discrete update stable at this dt", jury[0], jury[1]),
              ("discretisation: ω·dt < 0.1 (fastest pole)", fastest * dt < 0.1, f"{fastest * dt:.4g}")]
    if omega is not None and omega_b is not None:
        checks.append(("loop separation: ω_b ≤ ω/5", omega_b <= omega / 5 * (1 + 1e-9),
                       f"{omega_b:g} vs {omega / 5:g}"))
    with np.errstate(over="ignore", invalid="ignore"):  # an unstable choice overflows: inf, not a warning
        return TuneReport(settings, dt, poles, metrics.step_settling_time(kh, kv, kb, dt),
                          metrics.bias_settling_time(kh, kv, kb, dt), checks, metrics.noise_gain(kh, kv, kb, dt),
                          metrics.noise_bandwidth(kh, kv, kb, dt), bool(checks[0][1] and checks[1][1]))


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
    return AltitudeSettings(kh * steps_per_baro, kv * steps_per_baro, kb * steps_per_baro, **other_fields(settings))


def other_fields(settings: AltitudeSettings) -> dict:
    """Settings other than the three gains (the gap period and the baro timeout, where the core has them), to carry
    over."""
    return {name: getattr(settings, name) for name in ("gap_period", "baro_timeout") if hasattr(settings, name)}


def bandwidth_of(settings: AltitudeSettings) -> float:
    """Position-loop bandwidth ω (rad/s) of gains built with ζ = 0.7, ω_b = ω/5 (inverts Kh = 1.6·ω)."""
    return settings.position_gain / 1.6


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
