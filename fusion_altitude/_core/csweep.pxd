# cython: language_level=3
"""Declarations of csrc/fusion_altitude_sweep.h, and nothing else."""

from libc.stdint cimport uint8_t

from fusion_altitude._core.cobserver cimport FusionAltitudeStatus


cdef extern from "fusion_altitude_sweep.h" nogil:
    unsigned int FUSION_ALTITUDE_SWEEP_BLOCK

    ctypedef struct FusionAltitudeSweep:
        size_t count
        const float *positionGain
        const float *velocityGain
        const float *biasGain
        float *altitude
        float *verticalVelocity
        float *accelBias
        float *baroResidual
        float gapPeriod
        float baroTimeout
        float gapTime
        float sinceRestart
        float sinceBaro
        unsigned int gapCount
        unsigned int baroTimeouts
        bint referenceSet
        bint baroTimedOut
        size_t ruleBefore
        size_t ruleAfter

    ctypedef struct FusionAltitudeSweepOutputs:
        float *altitude
        float *verticalVelocity
        float *accelBias
        float *baroResidual
        size_t stride

    ctypedef struct FusionAltitudeSweepMetrics:
        const float *reference
        const uint8_t *mask
        float *sumError
        float *sumSquaredError
        float *maxAbsError
        float *blockSumError
        float *blockSumSquaredError
        size_t samplesInBlock
        size_t metricSamples

    void FusionAltitudeSweepInitialise(FusionAltitudeSweep *sweep)
    void FusionAltitudeSweepFlushMetrics(const FusionAltitudeSweep *sweep, FusionAltitudeSweepMetrics *metrics)
    FusionAltitudeStatus FusionAltitudeSweepUpdate(FusionAltitudeSweep *sweep, const float *accel, const float *baroAltitude,
                                                   const float *dt, size_t dtStride, size_t samples,
                                                   const FusionAltitudeSweepOutputs *outputs,
                                                   FusionAltitudeSweepMetrics *metrics, size_t *badIndex)
