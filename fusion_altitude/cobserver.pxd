# cython: language_level=3
"""Declarations of csrc/fusion_altitude.h (the observer) (the scalar getters: generated, in _*_fields.pxi), and nothing else."""


cdef extern from "fusion_altitude.h" nogil:
    float FUSION_ALTITUDE_GRAVITY
    int FUSION_ALTITUDE_VERSION

    ctypedef enum FusionAltitudeStatus:
        FusionAltitudeStatusOk
        FusionAltitudeStatusInvalidAccel
        FusionAltitudeStatusInvalidBaroAltitude
        FusionAltitudeStatusInvalidDt
        FusionAltitudeStatusInvalidAccelBias
        FusionAltitudeStatusInvalidGain
        FusionAltitudeStatusUnstableGains
        FusionAltitudeStatusUnstableDiscrete
        FusionAltitudeStatusInvalidBandwidth
        FusionAltitudeStatusInvalidPreset

    ctypedef enum FusionAltitudePreset:
        FusionAltitudePresetBalloon
        FusionAltitudePresetFixedWing
        FusionAltitudePresetVtol
        FusionAltitudePresetRacing

    ctypedef struct FusionAltitudeSettings:
        float positionGain
        float velocityGain
        float biasGain

    ctypedef struct FusionAltitude:
        FusionAltitudeSettings settings
        float altitude
        float verticalVelocity
        float accelBias
        float baroResidual
        bint referenceSet

    const char *FusionAltitudeStatusMessage(FusionAltitudeStatus status)
    FusionAltitudeSettings FusionAltitudeSettingsDefault()
    FusionAltitudeStatus FusionAltitudeSettingsCheck(const FusionAltitudeSettings *settings)
    FusionAltitudeStatus FusionAltitudeSettingsValidate(const FusionAltitudeSettings *settings, float dt)
    FusionAltitudeStatus FusionAltitudeSettingsFromBandwidth(FusionAltitudeSettings *settings, float omega, float zeta,
                                                             float omegaBias)
    FusionAltitudeStatus FusionAltitudeSettingsFromPreset(FusionAltitudeSettings *settings, FusionAltitudePreset preset)
    void FusionAltitudeInitialise(FusionAltitude *altitude)
    FusionAltitudeStatus FusionAltitudeSetSettings(FusionAltitude *altitude, const FusionAltitudeSettings *settings)
    FusionAltitudeStatus FusionAltitudeReset(FusionAltitude *altitude, float baroAltitude)
    FusionAltitudeStatus FusionAltitudeResetWithBias(FusionAltitude *altitude, float baroAltitude, float accelBias)
    FusionAltitudeStatus FusionAltitudeCheckInputs(float accel, float baroAltitude, float dt)
    FusionAltitudeStatus FusionAltitudeUpdate(FusionAltitude *altitude, float accel, float baroAltitude, float dt)
    FusionAltitudeSettings FusionAltitudeGetSettings(const FusionAltitude *altitude)
