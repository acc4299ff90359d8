# cython: language_level=3
"""Declarations of csrc/fusion_altitude_kalman.h (the scalar getters: generated, in _*_fields.pxi), and nothing else."""

from libc.stdint cimport int32_t, uint32_t


cdef extern from "fusion_altitude_kalman.h" nogil:
    int FUSION_ALTITUDE_KALMAN_STATES
    int FUSION_ALTITUDE_KALMAN_SENSORS

    ctypedef enum FusionAltitudeKalmanState:
        FusionAltitudeKalmanStateHeight
        FusionAltitudeKalmanStateVelocity
        FusionAltitudeKalmanStateBaroOffset
        FusionAltitudeKalmanStateGpsOffset
        FusionAltitudeKalmanStateAccelBias

    ctypedef enum FusionAltitudeKalmanSensorIndex:
        FusionAltitudeKalmanSensorBaro
        FusionAltitudeKalmanSensorRange
        FusionAltitudeKalmanSensorGps

    ctypedef enum FusionAltitudeKalmanResult:
        FusionAltitudeKalmanResultNoSample
        FusionAltitudeKalmanResultFused
        FusionAltitudeKalmanResultRejected
        FusionAltitudeKalmanResultReset
        FusionAltitudeKalmanResultInitialised
        FusionAltitudeKalmanResultUnusable

    ctypedef enum FusionAltitudeKalmanStatus:
        FusionAltitudeKalmanStatusOk
        FusionAltitudeKalmanStatusInvalidAccel
        FusionAltitudeKalmanStatusInvalidDt
        FusionAltitudeKalmanStatusInvalidBaroAltitude
        FusionAltitudeKalmanStatusInvalidGpsAltitude
        FusionAltitudeKalmanStatusInvalidGpsAccuracy
        FusionAltitudeKalmanStatusInvalidNoise
        FusionAltitudeKalmanStatusInvalidRange
        FusionAltitudeKalmanStatusInvalidGps
        FusionAltitudeKalmanStatusInvalidGate
        FusionAltitudeKalmanStatusInvalidGroundEffect

    ctypedef struct FusionAltitudeKalmanSettings:
        float accelNoise
        float accelBiasRandomWalk
        float accelBiasInitialSigma
        bint estimateAccelBias
        float baroNoise
        float baroOffsetRandomWalk
        float rangeNoise
        float rangeMinimum
        float rangeMaximum
        float gpsNoiseBase
        float gpsNoiseSatellite
        int32_t gpsMinimumSatellites
        float gpsOffsetRandomWalk
        float gate
        float rejectionTimeout
        float groundEffectNoiseScale
        float groundEffectDeadZone
        float initialHeightSigma
        float initialVelocitySigma

    ctypedef struct FusionAltitudeKalmanMeasurements:
        float baroAltitude
        float rangeDistance
        float gpsAltitude
        float gpsVerticalAccuracy
        int32_t gpsSatellites
        bint groundEffect

    ctypedef struct FusionAltitudeKalmanSensor:
        float innovation
        float innovationVariance
        float nis
        float rejectingFor
        uint32_t rejections
        uint32_t resets
        FusionAltitudeKalmanResult result
        bint rejecting

    ctypedef struct FusionAltitudeKalman:
        FusionAltitudeKalmanSettings settings
        float x[5]
        float P[5][5]
        FusionAltitudeKalmanSensor sensors[3]
        bint baroInitialised
        bint gpsInitialised

    const char *FusionAltitudeKalmanStatusMessage(FusionAltitudeKalmanStatus status)
    FusionAltitudeKalmanSettings FusionAltitudeKalmanSettingsDefault()
    FusionAltitudeKalmanStatus FusionAltitudeKalmanSettingsCheck(const FusionAltitudeKalmanSettings *settings)
    FusionAltitudeKalmanMeasurements FusionAltitudeKalmanMeasurementsNone()
    FusionAltitudeKalmanStatus FusionAltitudeKalmanInitialiseWith(FusionAltitudeKalman *kalman,
                                                                  const FusionAltitudeKalmanSettings *settings)
    void FusionAltitudeKalmanInitialise(FusionAltitudeKalman *kalman)
    FusionAltitudeKalmanStatus FusionAltitudeKalmanSetSettings(FusionAltitudeKalman *kalman,
                                                               const FusionAltitudeKalmanSettings *settings)
    FusionAltitudeKalmanStatus FusionAltitudeKalmanUpdate(FusionAltitudeKalman *kalman, float accel, float dt,
                                                          const FusionAltitudeKalmanMeasurements *measurements)
    FusionAltitudeKalmanSettings FusionAltitudeKalmanGetSettings(const FusionAltitudeKalman *kalman)
