/**
 * @file sized_kalman.c
 * @brief Out-of-line copies of every public function of
 * fusion_altitude_kalman.h, for measuring code size and stack
 * (docs/embedded.md), as sized_observer.c does for fusion_altitude.h: each public
 * function is wrapped in an external function Sized<Name>, marked flatten so
 * that the function and everything it calls is inlined into the wrapper.
 */

#include "fusion_altitude_kalman.h"

#if defined(__GNUC__)
#define SIZED __attribute__((flatten))
#else
#define SIZED
#endif

//------------------------------------------------------------------------------
// Out-of-line wrappers, one per public function

const char *SizedFusionAltitudeKalmanStatusMessage(const FusionAltitudeKalmanStatus status);
FusionAltitudeKalmanSettings SizedFusionAltitudeKalmanSettingsDefault(void);
FusionAltitudeKalmanStatus SizedFusionAltitudeKalmanSettingsCheck(const FusionAltitudeKalmanSettings *const settings);
FusionAltitudeKalmanMeasurements SizedFusionAltitudeKalmanMeasurementsNone(void);
FusionAltitudeKalmanStatus SizedFusionAltitudeKalmanInitialiseWith(FusionAltitudeKalman *const kalman, const FusionAltitudeKalmanSettings *const settings);
void SizedFusionAltitudeKalmanInitialise(FusionAltitudeKalman *const kalman);
FusionAltitudeKalmanStatus SizedFusionAltitudeKalmanSetSettings(FusionAltitudeKalman *const kalman, const FusionAltitudeKalmanSettings *const settings);
FusionAltitudeKalmanStatus SizedFusionAltitudeKalmanUpdate(FusionAltitudeKalman *const kalman, const float accel, const float dt,
        const FusionAltitudeKalmanMeasurements *const measurements);
FusionAltitudeKalmanSettings SizedFusionAltitudeKalmanGetSettings(const FusionAltitudeKalman *const kalman);
float SizedFusionAltitudeKalmanGetHeightAboveGround(const FusionAltitudeKalman *const kalman);
float SizedFusionAltitudeKalmanGetAltitude(const FusionAltitudeKalman *const kalman);
float SizedFusionAltitudeKalmanGetAltitudeVariance(const FusionAltitudeKalman *const kalman);
float SizedFusionAltitudeKalmanGetVerticalVelocity(const FusionAltitudeKalman *const kalman);
float SizedFusionAltitudeKalmanGetAccelBias(const FusionAltitudeKalman *const kalman);
float SizedFusionAltitudeKalmanGetBaroOffset(const FusionAltitudeKalman *const kalman);
float SizedFusionAltitudeKalmanGetGpsOffset(const FusionAltitudeKalman *const kalman);
float SizedFusionAltitudeKalmanGetCovariance(const FusionAltitudeKalman *const kalman, const FusionAltitudeKalmanState i,
        const FusionAltitudeKalmanState j);
FusionAltitudeKalmanSensor SizedFusionAltitudeKalmanGetSensor(const FusionAltitudeKalman *const kalman,
        const FusionAltitudeKalmanSensorIndex sensor);

SIZED const char *SizedFusionAltitudeKalmanStatusMessage(const FusionAltitudeKalmanStatus status) {
    return FusionAltitudeKalmanStatusMessage(status);
}

SIZED FusionAltitudeKalmanSettings SizedFusionAltitudeKalmanSettingsDefault(void) {
    return FusionAltitudeKalmanSettingsDefault();
}

SIZED FusionAltitudeKalmanStatus SizedFusionAltitudeKalmanSettingsCheck(const FusionAltitudeKalmanSettings *const settings) {
    return FusionAltitudeKalmanSettingsCheck(settings);
}

SIZED FusionAltitudeKalmanMeasurements SizedFusionAltitudeKalmanMeasurementsNone(void) {
    return FusionAltitudeKalmanMeasurementsNone();
}

SIZED FusionAltitudeKalmanStatus SizedFusionAltitudeKalmanInitialiseWith(FusionAltitudeKalman *const kalman, const FusionAltitudeKalmanSettings *const settings) {
    return FusionAltitudeKalmanInitialiseWith(kalman, settings);
}

SIZED void SizedFusionAltitudeKalmanInitialise(FusionAltitudeKalman *const kalman) {
    FusionAltitudeKalmanInitialise(kalman);
}

SIZED FusionAltitudeKalmanStatus SizedFusionAltitudeKalmanSetSettings(FusionAltitudeKalman *const kalman, const FusionAltitudeKalmanSettings *const settings) {
    return FusionAltitudeKalmanSetSettings(kalman, settings);
}

SIZED FusionAltitudeKalmanStatus SizedFusionAltitudeKalmanUpdate(FusionAltitudeKalman *const kalman, const float accel, const float dt,
        const FusionAltitudeKalmanMeasurements *const measurements) {
    return FusionAltitudeKalmanUpdate(kalman, accel, dt, measurements);
}

SIZED FusionAltitudeKalmanSettings SizedFusionAltitudeKalmanGetSettings(const FusionAltitudeKalman *const kalman) {
    return FusionAltitudeKalmanGetSettings(kalman);
}

SIZED float SizedFusionAltitudeKalmanGetHeightAboveGround(const FusionAltitudeKalman *const kalman) {
    return FusionAltitudeKalmanGetHeightAboveGround(kalman);
}

SIZED float SizedFusionAltitudeKalmanGetAltitude(const FusionAltitudeKalman *const kalman) {
    return FusionAltitudeKalmanGetAltitude(kalman);
}

SIZED float SizedFusionAltitudeKalmanGetAltitudeVariance(const FusionAltitudeKalman *const kalman) {
    return FusionAltitudeKalmanGetAltitudeVariance(kalman);
}

SIZED float SizedFusionAltitudeKalmanGetVerticalVelocity(const FusionAltitudeKalman *const kalman) {
    return FusionAltitudeKalmanGetVerticalVelocity(kalman);
}

SIZED float SizedFusionAltitudeKalmanGetAccelBias(const FusionAltitudeKalman *const kalman) {
    return FusionAltitudeKalmanGetAccelBias(kalman);
}

SIZED float SizedFusionAltitudeKalmanGetBaroOffset(const FusionAltitudeKalman *const kalman) {
    return FusionAltitudeKalmanGetBaroOffset(kalman);
}

SIZED float SizedFusionAltitudeKalmanGetGpsOffset(const FusionAltitudeKalman *const kalman) {
    return FusionAltitudeKalmanGetGpsOffset(kalman);
}

uint32_t SizedFusionAltitudeKalmanGetGapCount(const FusionAltitudeKalman *const kalman);

SIZED uint32_t SizedFusionAltitudeKalmanGetGapCount(const FusionAltitudeKalman *const kalman) {
    return FusionAltitudeKalmanGetGapCount(kalman);
}

SIZED float SizedFusionAltitudeKalmanGetCovariance(const FusionAltitudeKalman *const kalman, const FusionAltitudeKalmanState i,
        const FusionAltitudeKalmanState j) {
    return FusionAltitudeKalmanGetCovariance(kalman, i, j);
}

SIZED FusionAltitudeKalmanSensor SizedFusionAltitudeKalmanGetSensor(const FusionAltitudeKalman *const kalman,
        const FusionAltitudeKalmanSensorIndex sensor) {
    return FusionAltitudeKalmanGetSensor(kalman, sensor);
}

bool SizedFusionAltitudeKalmanIsBaroTimedOut(const FusionAltitudeKalman *const kalman);

SIZED bool SizedFusionAltitudeKalmanIsBaroTimedOut(const FusionAltitudeKalman *const kalman) {
    return FusionAltitudeKalmanIsBaroTimedOut(kalman);
}

bool SizedFusionAltitudeKalmanIsRangeTimedOut(const FusionAltitudeKalman *const kalman);

SIZED bool SizedFusionAltitudeKalmanIsRangeTimedOut(const FusionAltitudeKalman *const kalman) {
    return FusionAltitudeKalmanIsRangeTimedOut(kalman);
}

bool SizedFusionAltitudeKalmanIsGpsTimedOut(const FusionAltitudeKalman *const kalman);

SIZED bool SizedFusionAltitudeKalmanIsGpsTimedOut(const FusionAltitudeKalman *const kalman) {
    return FusionAltitudeKalmanIsGpsTimedOut(kalman);
}

float SizedFusionAltitudeKalmanGetNis(const FusionAltitudeKalman *const kalman, const FusionAltitudeKalmanSensorIndex sensor);

SIZED float SizedFusionAltitudeKalmanGetNis(const FusionAltitudeKalman *const kalman, const FusionAltitudeKalmanSensorIndex sensor) {
    return FusionAltitudeKalmanGetNis(kalman, sensor);
}
