# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False
"""Cython binding of csrc/fusion_altitude_sweep.h: K observers over one stream.

``run`` runs the settings [k_start, k_stop) of a sweep with the GIL released;
:func:`fusion_altitude.sweep` prepares the arrays and splits K across threads.
"""

from libc.stdint cimport uint8_t

from fusion_altitude._core.cobserver cimport FusionAltitudeStatus, FusionAltitudeStatusOk
from fusion_altitude._core.csweep cimport *

BLOCK = FUSION_ALTITUDE_SWEEP_BLOCK


def run(const float[::1] accel, const float[::1] baro_altitude, const float[::1] dt, bint dt_is_array,
        const float[:, ::1] gains, Py_ssize_t k_start, Py_ssize_t k_stop,
        float[:, ::1] state, object outputs, object metrics, const float[::1] reference, const uint8_t[::1] mask,
        float gap_period=0.5, float baro_timeout=2.0):
    """Run settings k_start..k_stop-1 over all samples (inputs already float32 and checked for shape).

    ``gains`` is (3, K) (Kh, Kv, Kb rows); ``state`` is (4, K) scratch (h, v, b, r).
    ``outputs`` is None or 4 arrays (T, K) float32; ``metrics`` is None or 5
    arrays (K,) float32: sum_error, sum_squared_error, max_abs_error and two
    zeroed scratch rows. ``gap_period`` and ``baro_timeout`` (s) are shared by every setting.
    Returns (status, bad_index, metric_samples).
    """
    cdef Py_ssize_t samples = accel.shape[0]
    cdef Py_ssize_t count = k_stop - k_start
    cdef FusionAltitudeSweep sweep
    cdef FusionAltitudeSweepOutputs out
    cdef FusionAltitudeSweepMetrics acc
    cdef FusionAltitudeSweepOutputs *out_pointer = NULL
    cdef FusionAltitudeSweepMetrics *acc_pointer = NULL
    cdef float[:, ::1] h_out, v_out, b_out, r_out
    cdef float[::1] sum_error, sum_squared, max_abs, block_sum, block_squared
    cdef size_t bad_index = 0
    cdef FusionAltitudeStatus status
    if count <= 0 or samples == 0:
        return (0, 0, 0)
    sweep.count = count
    sweep.positionGain = &gains[0, k_start]
    sweep.velocityGain = &gains[1, k_start]
    sweep.biasGain = &gains[2, k_start]
    sweep.altitude = &state[0, k_start]
    sweep.verticalVelocity = &state[1, k_start]
    sweep.accelBias = &state[2, k_start]
    sweep.baroResidual = &state[3, k_start]
    FusionAltitudeSweepInitialise(&sweep)
    sweep.gapPeriod = gap_period
    sweep.baroTimeout = baro_timeout
    sweep.ruleBefore = k_start  # the stability rule checks every setting, whichever part this thread runs
    sweep.ruleAfter = gains.shape[1] - k_stop
    if outputs is not None:
        h_out, v_out, b_out, r_out = outputs
        out.altitude = &h_out[0, k_start]
        out.verticalVelocity = &v_out[0, k_start]
        out.accelBias = &b_out[0, k_start]
        out.baroResidual = &r_out[0, k_start]
        out.stride = h_out.shape[1]
        out_pointer = &out
    if metrics is not None:
        sum_error, sum_squared, max_abs, block_sum, block_squared = metrics
        acc.reference = &reference[0]
        acc.mask = &mask[0] if mask is not None else NULL
        acc.sumError = &sum_error[k_start]
        acc.sumSquaredError = &sum_squared[k_start]
        acc.maxAbsError = &max_abs[k_start]
        acc.blockSumError = &block_sum[k_start]
        acc.blockSumSquaredError = &block_squared[k_start]
        acc.samplesInBlock = 0
        acc.metricSamples = 0
        acc_pointer = &acc
    with nogil:
        status = FusionAltitudeSweepUpdate(&sweep, &accel[0], &baro_altitude[0], &dt[0], 1 if dt_is_array else 0,
                                           samples, out_pointer, acc_pointer, &bad_index)
        if status == FusionAltitudeStatusOk and acc_pointer != NULL:
            FusionAltitudeSweepFlushMetrics(&sweep, acc_pointer)
    return (<int>status, bad_index, acc.metricSamples if acc_pointer != NULL else 0)
