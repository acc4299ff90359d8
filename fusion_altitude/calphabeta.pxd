# cython: language_level=3
"""Declarations of csrc/fusion_altitude_alphabeta.h (the scalar getters: generated, in _*_fields.pxi), and nothing else."""

from libc.stdint cimport int32_t


cdef extern from "fusion_altitude_alphabeta.h" nogil:
    int FUSION_ALTITUDE_ALPHABETA_SENSORS
    int FUSION_ALTITUDE_ALPHABETA_MAX_QUALITY

    ctypedef enum FusionAltitudeAlphaBetaSensorIndex:
        FusionAltitudeAlphaBetaSensorImu
        FusionAltitudeAlphaBetaSensorBaro
        FusionAltitudeAlphaBetaSensorLidar
        FusionAltitudeAlphaBetaSensorSonar
        FusionAltitudeAlphaBetaSensorGps

    ctypedef enum FusionAltitudeAlphaBetaStatus:
        FusionAltitudeAlphaBetaStatusOk
        FusionAltitudeAlphaBetaStatusInvalidAccel
        FusionAltitudeAlphaBetaStatusInvalidDt
        FusionAltitudeAlphaBetaStatusInvalidBaroAltitude
        FusionAltitudeAlphaBetaStatusInvalidLidarAltitude
        FusionAltitudeAlphaBetaStatusInvalidSonarAltitude
        FusionAltitudeAlphaBetaStatusInvalidGpsAltitude
        FusionAltitudeAlphaBetaStatusInvalidThreshold
        FusionAltitudeAlphaBetaStatusInvalidQuality
        FusionAltitudeAlphaBetaStatusInvalidConfidence
        FusionAltitudeAlphaBetaStatusInvalidAltitudeBand
        FusionAltitudeAlphaBetaStatusInvalidGapMax
        FusionAltitudeAlphaBetaStatusInvalidTimeout

    ctypedef struct FusionAltitudeAlphaBetaSensorSettings:
        float threshold
        int32_t qualityMin
        int32_t qualityMax
        float confidence
        float altitudeMin
        float altitudeMax
        float gapMax
        float timeout

    ctypedef struct FusionAltitudeAlphaBetaSettings:
        FusionAltitudeAlphaBetaSensorSettings sensors[5]

    ctypedef struct FusionAltitudeAlphaBetaMeasurements:
        float baroAltitude
        float lidarAltitude
        float sonarAltitude
        float gpsAltitude

    ctypedef struct FusionAltitudeAlphaBetaFilter:
        float altitude
        float velocity
        float sinceSample
        float gap
        float weight
        int32_t quality
        bint started

    ctypedef struct FusionAltitudeAlphaBeta:
        FusionAltitudeAlphaBetaSettings settings
        FusionAltitudeAlphaBetaFilter filters[5]
        float altitude
        float verticalVelocity
        float totalWeight
        bint started

    const char *FusionAltitudeAlphaBetaStatusMessage(FusionAltitudeAlphaBetaStatus status)
    FusionAltitudeAlphaBetaSettings FusionAltitudeAlphaBetaSettingsDefault()
    FusionAltitudeAlphaBetaStatus FusionAltitudeAlphaBetaSettingsCheck(const FusionAltitudeAlphaBetaSettings *settings)
    void FusionAltitudeAlphaBetaGains(int32_t quality, float *alpha, float *beta)
    FusionAltitudeAlphaBetaMeasurements FusionAltitudeAlphaBetaMeasurementsNone()
    void FusionAltitudeAlphaBetaInitialise(FusionAltitudeAlphaBeta *fusion)
    FusionAltitudeAlphaBetaStatus FusionAltitudeAlphaBetaInitialiseWith(FusionAltitudeAlphaBeta *fusion,
                                                                        const FusionAltitudeAlphaBetaSettings *settings)
    FusionAltitudeAlphaBetaStatus FusionAltitudeAlphaBetaSetSettings(FusionAltitudeAlphaBeta *fusion,
                                                                     const FusionAltitudeAlphaBetaSettings *settings)
    FusionAltitudeAlphaBetaStatus FusionAltitudeAlphaBetaCheckInputs(float accel, float dt,
                                                                     const FusionAltitudeAlphaBetaMeasurements *m)
    FusionAltitudeAlphaBetaStatus FusionAltitudeAlphaBetaUpdate(FusionAltitudeAlphaBeta *fusion, float accel, float dt,
                                                                const FusionAltitudeAlphaBetaMeasurements *m)
