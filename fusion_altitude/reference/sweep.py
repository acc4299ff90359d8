"""Gain sweep, in plain Python: K observers over one stream, with error metrics.

Mirrors ``csrc/fusion_altitude_sweep.h``: each setting runs exactly the
reference observer, and the metric sums are kept in float32 per block of
``BLOCK`` metric samples before being added to the totals, as the C does, so
the results agree bit for bit.
"""

from __future__ import annotations

import numpy as np

from .._core import _observer_glue, _sweep_glue
from .._core._observer_glue import AltitudeBatch
from .._core._sweep_glue import SweepResult
from .observer import AltitudeEstimator, AltitudeSettings, step_stable

f32 = np.float32
#: FUSION_ALTITUDE_SWEEP_BLOCK
BLOCK = 1024


def sweep(accel, baro_altitude, dt, settings, reference=None, mask=None, outputs: bool = False,
          threads=None, out=None, gap_period: float = 0.5, baro_timeout: float = 2.0) -> SweepResult:
    """Run K observer settings over one input stream (see :func:`fusion_altitude.sweep`).

    ``gap_period`` and ``baro_timeout`` (s) are shared by every setting, as in
    ``FusionAltitudeSweep``; so is the stability rule: a baro step that is a gap
    by it for any setting is a gap for all (``FusionAltitudeSweepUnstableSteps``).
    """
    outputs = outputs or out is not None
    accel32, baro32, dt32, dt_is_array, gains, reference32, mask8 = _sweep_glue.prepare_sweep(
        accel, baro_altitude, dt, settings, reference, mask, outputs)
    for k, row in enumerate(gains):
        try:
            AltitudeSettings(*row)
        except ValueError as error:
            raise ValueError(f"settings[{k}]: {error}") from None
    n, count = accel32.shape[0], gains.shape[0]
    dt_argument = dt32 if dt_is_array else dt32[0]
    made = [AltitudeSettings(*row, gap_period=gap_period, baro_timeout=baro_timeout) for row in gains]
    estimators = [AltitudeEstimator(one) for one in made]
    # validate every input first, as the C does (nothing is applied on a bad sample)
    AltitudeEstimator(made[0]).update_batch(accel32, baro32, dt_argument)
    runs = [AltitudeBatch(*(np.empty(n, np.float32) for _ in range(4))) for _ in range(count)]
    timeline = estimators[0]  # every estimator shares the timeline; the first one decides the rule's inputs
    for i in range(n):
        t = dt32[i] if dt_is_array else dt32[0]
        z = baro32[i]
        unstable = (not np.isnan(z) and timeline._reference_set and not timeline._baro_timed_out
                    and any(not step_stable(*one._gains, t, timeline._since_baro + t) for one in made))
        for estimator, run in zip(estimators, runs):
            estimator._update(accel32[i], z, t, unstable)
            run.altitude[i], run.vertical_velocity[i] = estimator._h, estimator._v
            run.accel_bias[i], run.baro_residual[i] = estimator._b, estimator._r
    output_arrays = None
    if outputs:
        output_arrays = _observer_glue.output_arrays((n, count), out)
        for target, field in zip(output_arrays, AltitudeBatch._fields):
            target[...] = np.stack([getattr(run, field) for run in runs], axis=1).reshape(n, count)
    if reference32 is None:
        return _sweep_glue.sweep_result(gains, 0, None, output_arrays)
    counted = np.isfinite(reference32) & (mask8.astype(bool) if mask8 is not None else True)
    sums = np.zeros((3, count), np.float32)
    for k, run in enumerate(runs):
        total, total_squared, largest = f32(0), f32(0), f32(0)
        block, block_squared, in_block = f32(0), f32(0), 0
        for altitude, target in zip(run.altitude[counted], reference32[counted]):
            error = altitude - target
            block += error
            block_squared += error * error
            largest = max(largest, abs(error))
            in_block += 1
            if in_block == BLOCK:
                total, total_squared = total + block, total_squared + block_squared
                block, block_squared, in_block = f32(0), f32(0), 0
        sums[:, k] = (total + block, total_squared + block_squared, largest)
    return _sweep_glue.sweep_result(gains, int(np.count_nonzero(counted)), tuple(sums), output_arrays)
