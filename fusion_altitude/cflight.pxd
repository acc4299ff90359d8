# cython: language_level=3
"""Declarations of csrc/fusion_altitude_flight.h, and nothing else."""

from libc.stdint cimport uint32_t

from fusion_altitude.cobserver cimport FusionAltitudeSettings, FusionAltitude


cdef extern from "fusion_altitude_flight.h" nogil:
    float FUSION_ALTITUDE_ROCKET_MACH_LOCKOUT
    int FUSION_ALTITUDE_ROCKET_NUMBER_OF_EVENTS

    ctypedef enum FusionAltitudeRocketStatus:
        FusionAltitudeRocketStatusOk
        FusionAltitudeRocketStatusInvalidGapPeriod

    ctypedef enum FusionAltitudeRocketPhase:
        FusionAltitudeRocketPhasePad

    ctypedef enum FusionAltitudeRocketBaro:
        FusionAltitudeRocketBaroNone

    ctypedef enum FusionAltitudeRocketEventId:
        FusionAltitudeRocketEventLaunch

    ctypedef struct FusionAltitudeRocketEvent:
        bint occurred
        uint32_t sample
        float time
        float height
        float velocity

    ctypedef struct FusionAltitudeRocketSettings:
        FusionAltitudeSettings observer
        float stationaryAccel
        float calibrationWindow
        float launchAccel
        float launchTime
        float burnoutAccel
        float burnoutTime
        float apogeeMargin
        float lockoutSpeed
        float spikeThreshold
        float spikeTime
        float offsetRate
        float mainAltitude
        float landedSpeed
        float landedTime
        float gapPeriod

    ctypedef struct FusionAltitudeRocket:
        FusionAltitudeRocketSettings settings
        FusionAltitude observer
        FusionAltitudeRocketPhase phase
        FusionAltitudeRocketBaro baro
        FusionAltitudeRocketEvent events[6]
        uint32_t gapCount
        float accelBias
        float padAltitude
        bint lockout

    const char *FusionAltitudeRocketStatusMessage(FusionAltitudeRocketStatus status)
    FusionAltitudeSettings FusionAltitudeRocketObserverSettings()
    FusionAltitudeRocketSettings FusionAltitudeRocketSettingsDefault()
    FusionAltitudeRocketStatus FusionAltitudeRocketSettingsCheck(const FusionAltitudeRocketSettings *settings)
    FusionAltitudeRocketStatus FusionAltitudeRocketInitialise(FusionAltitudeRocket *rocket,
                                                              const FusionAltitudeRocketSettings *settings)
    FusionAltitudeRocketStatus FusionAltitudeRocketCheckInputs(float accel, float baroAltitude, float dt)
    FusionAltitudeRocketStatus FusionAltitudeRocketUpdate(FusionAltitudeRocket *rocket, float accel, float baroAltitude,
                                                          float dt)
    FusionAltitudeRocketStatus FusionAltitudeRocketUpdateWithVerticalAccel(FusionAltitudeRocket *rocket, float accel,
                                                                           float baroAltitude, float dt)
    float FusionAltitudeRocketGetHeight(const FusionAltitudeRocket *rocket)
    float FusionAltitudeRocketGetVerticalVelocity(const FusionAltitudeRocket *rocket)
    float FusionAltitudeRocketGetAccelBias(const FusionAltitudeRocket *rocket)
    float FusionAltitudeRocketGetPadAltitude(const FusionAltitudeRocket *rocket)
    FusionAltitudeRocketPhase FusionAltitudeRocketGetPhase(const FusionAltitudeRocket *rocket)
    FusionAltitudeRocketBaro FusionAltitudeRocketGetBaro(const FusionAltitudeRocket *rocket)
    bint FusionAltitudeRocketIsLockedOut(const FusionAltitudeRocket *rocket)
    bint FusionAltitudeRocketIsCalibrated(const FusionAltitudeRocket *rocket)
    FusionAltitudeRocketEvent FusionAltitudeRocketGetEvent(const FusionAltitudeRocket *rocket,
                                                           FusionAltitudeRocketEventId event)
    uint32_t FusionAltitudeRocketGetGapCount(const FusionAltitudeRocket *rocket)
    float FusionAltitudeRocketGetTime(const FusionAltitudeRocket *rocket)
