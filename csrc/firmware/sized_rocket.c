/**
 * @file sized_rocket.c
 * @brief Out-of-line copies of every public function of
 * fusion_altitude_rocket.h, for measuring code size and stack, as sized.c
 * does for fusion_altitude.h: each public function is wrapped in an external
 * function Sized<Name>, marked flatten so that the function and everything it
 * calls (the observer included) is inlined into the wrapper.
 */

#include "fusion_altitude_rocket.h"

#if defined(__GNUC__)
#define SIZED __attribute__((flatten))
#else
#define SIZED
#endif

//------------------------------------------------------------------------------
// Out-of-line wrappers, one per public function

const char * SizedFusionAltitudeRocketStatusMessage(const FusionAltitudeRocketStatus status);

SIZED const char * SizedFusionAltitudeRocketStatusMessage(const FusionAltitudeRocketStatus status) {
    return FusionAltitudeRocketStatusMessage(status);
}

FusionAltitudeSettings SizedFusionAltitudeRocketObserverSettings(void);

SIZED FusionAltitudeSettings SizedFusionAltitudeRocketObserverSettings(void) {
    return FusionAltitudeRocketObserverSettings();
}

FusionAltitudeRocketSettings SizedFusionAltitudeRocketSettingsDefault(void);

SIZED FusionAltitudeRocketSettings SizedFusionAltitudeRocketSettingsDefault(void) {
    return FusionAltitudeRocketSettingsDefault();
}

FusionAltitudeRocketStatus SizedFusionAltitudeRocketSettingsCheck(const FusionAltitudeRocketSettings *const settings);

SIZED FusionAltitudeRocketStatus SizedFusionAltitudeRocketSettingsCheck(const FusionAltitudeRocketSettings *const settings) {
    return FusionAltitudeRocketSettingsCheck(settings);
}

FusionAltitudeRocketStatus SizedFusionAltitudeRocketInitialise(FusionAltitudeRocket *const rocket, const FusionAltitudeRocketSettings *const settings);

SIZED FusionAltitudeRocketStatus SizedFusionAltitudeRocketInitialise(FusionAltitudeRocket *const rocket, const FusionAltitudeRocketSettings *const settings) {
    return FusionAltitudeRocketInitialise(rocket, settings);
}

FusionAltitudeRocketStatus SizedFusionAltitudeRocketCheckInputs(const float accel, const float baroAltitude, const float dt);

SIZED FusionAltitudeRocketStatus SizedFusionAltitudeRocketCheckInputs(const float accel, const float baroAltitude, const float dt) {
    return FusionAltitudeRocketCheckInputs(accel, baroAltitude, dt);
}

FusionAltitudeRocketStatus SizedFusionAltitudeRocketUpdate(FusionAltitudeRocket *const rocket, const float accel, const float baroAltitude, const float dt);

SIZED FusionAltitudeRocketStatus SizedFusionAltitudeRocketUpdate(FusionAltitudeRocket *const rocket, const float accel, const float baroAltitude, const float dt) {
    return FusionAltitudeRocketUpdate(rocket, accel, baroAltitude, dt);
}

FusionAltitudeRocketStatus SizedFusionAltitudeRocketUpdateWithVerticalAccel(FusionAltitudeRocket *const rocket, const float accel, const float baroAltitude, const float dt);

SIZED FusionAltitudeRocketStatus SizedFusionAltitudeRocketUpdateWithVerticalAccel(FusionAltitudeRocket *const rocket, const float accel, const float baroAltitude, const float dt) {
    return FusionAltitudeRocketUpdateWithVerticalAccel(rocket, accel, baroAltitude, dt);
}

float SizedFusionAltitudeRocketGetHeight(const FusionAltitudeRocket *const rocket);

SIZED float SizedFusionAltitudeRocketGetHeight(const FusionAltitudeRocket *const rocket) {
    return FusionAltitudeRocketGetHeight(rocket);
}

float SizedFusionAltitudeRocketGetVerticalVelocity(const FusionAltitudeRocket *const rocket);

SIZED float SizedFusionAltitudeRocketGetVerticalVelocity(const FusionAltitudeRocket *const rocket) {
    return FusionAltitudeRocketGetVerticalVelocity(rocket);
}

float SizedFusionAltitudeRocketGetAccelBias(const FusionAltitudeRocket *const rocket);

SIZED float SizedFusionAltitudeRocketGetAccelBias(const FusionAltitudeRocket *const rocket) {
    return FusionAltitudeRocketGetAccelBias(rocket);
}

float SizedFusionAltitudeRocketGetPadAltitude(const FusionAltitudeRocket *const rocket);

SIZED float SizedFusionAltitudeRocketGetPadAltitude(const FusionAltitudeRocket *const rocket) {
    return FusionAltitudeRocketGetPadAltitude(rocket);
}

FusionAltitudeRocketPhase SizedFusionAltitudeRocketGetPhase(const FusionAltitudeRocket *const rocket);

SIZED FusionAltitudeRocketPhase SizedFusionAltitudeRocketGetPhase(const FusionAltitudeRocket *const rocket) {
    return FusionAltitudeRocketGetPhase(rocket);
}

FusionAltitudeRocketBaro SizedFusionAltitudeRocketGetBaro(const FusionAltitudeRocket *const rocket);

SIZED FusionAltitudeRocketBaro SizedFusionAltitudeRocketGetBaro(const FusionAltitudeRocket *const rocket) {
    return FusionAltitudeRocketGetBaro(rocket);
}

bool SizedFusionAltitudeRocketIsLockedOut(const FusionAltitudeRocket *const rocket);

SIZED bool SizedFusionAltitudeRocketIsLockedOut(const FusionAltitudeRocket *const rocket) {
    return FusionAltitudeRocketIsLockedOut(rocket);
}

bool SizedFusionAltitudeRocketIsCalibrated(const FusionAltitudeRocket *const rocket);

SIZED bool SizedFusionAltitudeRocketIsCalibrated(const FusionAltitudeRocket *const rocket) {
    return FusionAltitudeRocketIsCalibrated(rocket);
}

FusionAltitudeRocketEvent SizedFusionAltitudeRocketGetEvent(const FusionAltitudeRocket *const rocket, const FusionAltitudeRocketEventId event);

SIZED FusionAltitudeRocketEvent SizedFusionAltitudeRocketGetEvent(const FusionAltitudeRocket *const rocket, const FusionAltitudeRocketEventId event) {
    return FusionAltitudeRocketGetEvent(rocket, event);
}

uint32_t SizedFusionAltitudeRocketGetGapCount(const FusionAltitudeRocket *const rocket);

SIZED uint32_t SizedFusionAltitudeRocketGetGapCount(const FusionAltitudeRocket *const rocket) {
    return FusionAltitudeRocketGetGapCount(rocket);
}

float SizedFusionAltitudeRocketGetTime(const FusionAltitudeRocket *const rocket);

SIZED float SizedFusionAltitudeRocketGetTime(const FusionAltitudeRocket *const rocket) {
    return FusionAltitudeRocketGetTime(rocket);
}
