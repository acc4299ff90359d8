# cython: language_level=3
"""Declarations of csrc/fusion_altitude_ins.h, and nothing else."""

from libc.stdint cimport uint32_t


cdef extern from "fusion_altitude_ins.h" nogil:
    int FUSION_ALTITUDE_INS_STATES

    ctypedef struct FusionAltitudeInsVector:
        float x
        float y
        float z

    ctypedef struct FusionAltitudeInsQuaternion:
        float w
        float x
        float y
        float z

    ctypedef enum FusionAltitudeInsStatus:
        FusionAltitudeInsStatusOk
        FusionAltitudeInsStatusInvalidGyro
        FusionAltitudeInsStatusInvalidAccel
        FusionAltitudeInsStatusInvalidMag
        FusionAltitudeInsStatusInvalidBaroAltitude
        FusionAltitudeInsStatusInvalidDt
        FusionAltitudeInsStatusInvalidSettings

    ctypedef struct FusionAltitudeInsSettings:
        float gyroNoise
        float gyroBiasRandomWalk
        float accelNoise
        float accelAttitudeNoise
        float accelNormRejection
        float accelRejection
        float recoveryTriggerPeriod
        float baroNoise
        float stationaryGyroThreshold
        float stationaryAccelThreshold
        float stationaryWindow
        float zeroRateNoise
        float zeroVelocityNoise
        float baroBiasTimeConstant
        float accelBiasTimeConstant
        float magTimeConstant
        float initialAttitudeSigma
        float initialGyroBiasSigma
        float initialVelocitySigma
        float gapPeriod

    ctypedef struct FusionAltitudeIns:
        FusionAltitudeInsSettings settings
        float q[4]
        float gyroBias[3]
        float distance
        float velocity
        float P[8][8]
        float accelZBias
        float baroBias
        float yawCos
        float yawSin
        float stationaryTime
        float rejectionTime
        float baroElapsed
        float magElapsed
        uint32_t gapCount
        bint aligned
        bint baroInitialised
        bint magInitialised
        bint stationary
        bint accelRejected

    const char *FusionAltitudeInsStatusMessage(FusionAltitudeInsStatus status)
    FusionAltitudeInsSettings FusionAltitudeInsSettingsDefault()
    FusionAltitudeInsStatus FusionAltitudeInsSettingsCheck(const FusionAltitudeInsSettings *settings)
    FusionAltitudeInsVector FusionAltitudeInsNoMag()
    FusionAltitudeInsStatus FusionAltitudeInsInitialiseWith(FusionAltitudeIns *ins, const FusionAltitudeInsSettings *settings)
    FusionAltitudeInsStatus FusionAltitudeInsSetSettings(FusionAltitudeIns *ins, const FusionAltitudeInsSettings *settings)
    FusionAltitudeInsStatus FusionAltitudeInsUpdate(FusionAltitudeIns *ins, FusionAltitudeInsVector gyro,
                                                    FusionAltitudeInsVector accel, FusionAltitudeInsVector mag,
                                                    float baroAltitude, float dt)
    FusionAltitudeInsSettings FusionAltitudeInsGetSettings(const FusionAltitudeIns *ins)
    float FusionAltitudeInsGetAltitude(const FusionAltitudeIns *ins)
    float FusionAltitudeInsGetVerticalVelocity(const FusionAltitudeIns *ins)
    FusionAltitudeInsQuaternion FusionAltitudeInsGetQuaternion(const FusionAltitudeIns *ins)
    FusionAltitudeInsQuaternion FusionAltitudeInsGetLocalToGlobal(const FusionAltitudeIns *ins)
    FusionAltitudeInsQuaternion FusionAltitudeInsGetGlobalQuaternion(const FusionAltitudeIns *ins)
    FusionAltitudeInsVector FusionAltitudeInsGetGyroBias(const FusionAltitudeIns *ins)
    float FusionAltitudeInsGetAccelZBias(const FusionAltitudeIns *ins)
    float FusionAltitudeInsGetBaroBias(const FusionAltitudeIns *ins)
    bint FusionAltitudeInsIsStationary(const FusionAltitudeIns *ins)
    bint FusionAltitudeInsIsAccelRejected(const FusionAltitudeIns *ins)
    uint32_t FusionAltitudeInsGetGapCount(const FusionAltitudeIns *ins)
