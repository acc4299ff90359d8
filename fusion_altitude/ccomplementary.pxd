# cython: language_level=3
"""Declarations of csrc/fusion_altitude_complementary.h (the scalar getters: generated, in _*_fields.pxi), and nothing else."""


cdef extern from "fusion_altitude_complementary.h" nogil:
    ctypedef enum FusionAltitudeComplementaryStatus:
        FusionAltitudeComplementaryStatusOk
        FusionAltitudeComplementaryStatusInvalidAccel
        FusionAltitudeComplementaryStatusInvalidBaroAltitude
        FusionAltitudeComplementaryStatusInvalidDt
        FusionAltitudeComplementaryStatusInvalidTimeConstant
        FusionAltitudeComplementaryStatusInvalidCoefficient

    ctypedef struct FusionAltitudeComplementarySettings:
        float accelTimeConstant
        float baroTimeConstant
        bint perSampleCoefficients
        float velocityCoefficient
        float altitudeCoefficient
        float velocityTimeConstant
        float altitudeTimeConstant

    ctypedef struct FusionAltitudeComplementary:
        FusionAltitudeComplementarySettings settings
        float altitude
        float verticalVelocity
        float accelFiltered
        float baroFiltered
        float baroVelocity
        float sinceBaro
        bint referenceSet

    const char *FusionAltitudeComplementaryStatusMessage(FusionAltitudeComplementaryStatus status)
    FusionAltitudeComplementarySettings FusionAltitudeComplementarySettingsDefault()
    FusionAltitudeComplementaryStatus FusionAltitudeComplementarySettingsCheck(
        const FusionAltitudeComplementarySettings *settings)
    void FusionAltitudeComplementaryInitialise(FusionAltitudeComplementary *filter)
    FusionAltitudeComplementaryStatus FusionAltitudeComplementarySetSettings(
        FusionAltitudeComplementary *filter, const FusionAltitudeComplementarySettings *settings)
    FusionAltitudeComplementaryStatus FusionAltitudeComplementaryReset(FusionAltitudeComplementary *filter,
                                                                       float baroAltitude)
    FusionAltitudeComplementaryStatus FusionAltitudeComplementaryCheckInputs(float accel, float baroAltitude, float dt)
    FusionAltitudeComplementaryStatus FusionAltitudeComplementaryUpdate(FusionAltitudeComplementary *filter, float accel,
                                                                        float baroAltitude, float dt)
    FusionAltitudeComplementarySettings FusionAltitudeComplementaryGetSettings(const FusionAltitudeComplementary *filter)
