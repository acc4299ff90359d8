/**
 * @file sized_alphabeta.c
 * @brief Out-of-line copies of every public function of
 * fusion_altitude_alphabeta.h, for measuring code size and stack
 * (docs/embedded.md), as sized_observer.c does for fusion_altitude.h: each public
 * function is wrapped in an external function Sized<Name>, marked flatten so
 * that the function and everything it calls is inlined into the wrapper.
 */

#include "fusion_altitude_alphabeta.h"

#if defined(__GNUC__)
#define SIZED __attribute__((flatten))
#else
#define SIZED
#endif

//------------------------------------------------------------------------------
// Out-of-line wrappers, one per public function

const char *SizedFusionAltitudeAlphaBetaStatusMessage(const FusionAltitudeAlphaBetaStatus status);

SIZED const char *SizedFusionAltitudeAlphaBetaStatusMessage(const FusionAltitudeAlphaBetaStatus status) {
    return FusionAltitudeAlphaBetaStatusMessage(status);
}

FusionAltitudeAlphaBetaSettings SizedFusionAltitudeAlphaBetaSettingsDefault(void);

SIZED FusionAltitudeAlphaBetaSettings SizedFusionAltitudeAlphaBetaSettingsDefault(void) {
    return FusionAltitudeAlphaBetaSettingsDefault();
}

FusionAltitudeAlphaBetaStatus SizedFusionAltitudeAlphaBetaSensorSettingsCheck(const FusionAltitudeAlphaBetaSensorSettings *const sensor);

SIZED FusionAltitudeAlphaBetaStatus SizedFusionAltitudeAlphaBetaSensorSettingsCheck(const FusionAltitudeAlphaBetaSensorSettings *const sensor) {
    return FusionAltitudeAlphaBetaSensorSettingsCheck(sensor);
}

FusionAltitudeAlphaBetaStatus SizedFusionAltitudeAlphaBetaSettingsCheck(const FusionAltitudeAlphaBetaSettings *const settings);

SIZED FusionAltitudeAlphaBetaStatus SizedFusionAltitudeAlphaBetaSettingsCheck(const FusionAltitudeAlphaBetaSettings *const settings) {
    return FusionAltitudeAlphaBetaSettingsCheck(settings);
}

void SizedFusionAltitudeAlphaBetaGains(const int32_t quality, float *const alpha, float *const beta);

SIZED void SizedFusionAltitudeAlphaBetaGains(const int32_t quality, float *const alpha, float *const beta) {
    FusionAltitudeAlphaBetaGains(quality, alpha, beta);
}

FusionAltitudeAlphaBetaMeasurements SizedFusionAltitudeAlphaBetaMeasurementsNone(void);

SIZED FusionAltitudeAlphaBetaMeasurements SizedFusionAltitudeAlphaBetaMeasurementsNone(void) {
    return FusionAltitudeAlphaBetaMeasurementsNone();
}

void SizedFusionAltitudeAlphaBetaInitialise(FusionAltitudeAlphaBeta *const fusion);

SIZED void SizedFusionAltitudeAlphaBetaInitialise(FusionAltitudeAlphaBeta *const fusion) {
    FusionAltitudeAlphaBetaInitialise(fusion);
}

FusionAltitudeAlphaBetaStatus SizedFusionAltitudeAlphaBetaInitialiseWith(FusionAltitudeAlphaBeta *const fusion, const FusionAltitudeAlphaBetaSettings *const settings);

SIZED FusionAltitudeAlphaBetaStatus SizedFusionAltitudeAlphaBetaInitialiseWith(FusionAltitudeAlphaBeta *const fusion, const FusionAltitudeAlphaBetaSettings *const settings) {
    return FusionAltitudeAlphaBetaInitialiseWith(fusion, settings);
}

FusionAltitudeAlphaBetaStatus SizedFusionAltitudeAlphaBetaSetSettings(FusionAltitudeAlphaBeta *const fusion, const FusionAltitudeAlphaBetaSettings *const settings);

SIZED FusionAltitudeAlphaBetaStatus SizedFusionAltitudeAlphaBetaSetSettings(FusionAltitudeAlphaBeta *const fusion, const FusionAltitudeAlphaBetaSettings *const settings) {
    return FusionAltitudeAlphaBetaSetSettings(fusion, settings);
}

FusionAltitudeAlphaBetaStatus SizedFusionAltitudeAlphaBetaCheckInputs(const float accel, const float dt, const FusionAltitudeAlphaBetaMeasurements *const m);

SIZED FusionAltitudeAlphaBetaStatus SizedFusionAltitudeAlphaBetaCheckInputs(const float accel, const float dt, const FusionAltitudeAlphaBetaMeasurements *const m) {
    return FusionAltitudeAlphaBetaCheckInputs(accel, dt, m);
}

FusionAltitudeAlphaBetaStatus SizedFusionAltitudeAlphaBetaUpdate(FusionAltitudeAlphaBeta *const fusion, const float accel, const float dt, const FusionAltitudeAlphaBetaMeasurements *const m);

SIZED FusionAltitudeAlphaBetaStatus SizedFusionAltitudeAlphaBetaUpdate(FusionAltitudeAlphaBeta *const fusion, const float accel, const float dt, const FusionAltitudeAlphaBetaMeasurements *const m) {
    return FusionAltitudeAlphaBetaUpdate(fusion, accel, dt, m);
}

FusionAltitudeAlphaBetaSettings SizedFusionAltitudeAlphaBetaGetSettings(const FusionAltitudeAlphaBeta *const fusion);

SIZED FusionAltitudeAlphaBetaSettings SizedFusionAltitudeAlphaBetaGetSettings(const FusionAltitudeAlphaBeta *const fusion) {
    return FusionAltitudeAlphaBetaGetSettings(fusion);
}

float SizedFusionAltitudeAlphaBetaGetAltitude(const FusionAltitudeAlphaBeta *const fusion);

SIZED float SizedFusionAltitudeAlphaBetaGetAltitude(const FusionAltitudeAlphaBeta *const fusion) {
    return FusionAltitudeAlphaBetaGetAltitude(fusion);
}

float SizedFusionAltitudeAlphaBetaGetVerticalVelocity(const FusionAltitudeAlphaBeta *const fusion);

SIZED float SizedFusionAltitudeAlphaBetaGetVerticalVelocity(const FusionAltitudeAlphaBeta *const fusion) {
    return FusionAltitudeAlphaBetaGetVerticalVelocity(fusion);
}

float SizedFusionAltitudeAlphaBetaGetWeight(const FusionAltitudeAlphaBeta *const fusion, const FusionAltitudeAlphaBetaSensorIndex sensor);

SIZED float SizedFusionAltitudeAlphaBetaGetWeight(const FusionAltitudeAlphaBeta *const fusion, const FusionAltitudeAlphaBetaSensorIndex sensor) {
    return FusionAltitudeAlphaBetaGetWeight(fusion, sensor);
}

int32_t SizedFusionAltitudeAlphaBetaGetQuality(const FusionAltitudeAlphaBeta *const fusion, const FusionAltitudeAlphaBetaSensorIndex sensor);

SIZED int32_t SizedFusionAltitudeAlphaBetaGetQuality(const FusionAltitudeAlphaBeta *const fusion, const FusionAltitudeAlphaBetaSensorIndex sensor) {
    return FusionAltitudeAlphaBetaGetQuality(fusion, sensor);
}

bool SizedFusionAltitudeAlphaBetaIsStarted(const FusionAltitudeAlphaBeta *const fusion);

SIZED bool SizedFusionAltitudeAlphaBetaIsStarted(const FusionAltitudeAlphaBeta *const fusion) {
    return FusionAltitudeAlphaBetaIsStarted(fusion);
}

uint32_t SizedFusionAltitudeAlphaBetaGetGapCount(const FusionAltitudeAlphaBeta *const fusion);

SIZED uint32_t SizedFusionAltitudeAlphaBetaGetGapCount(const FusionAltitudeAlphaBeta *const fusion) {
    return FusionAltitudeAlphaBetaGetGapCount(fusion);
}

bool SizedFusionAltitudeAlphaBetaIsTimedOut(const FusionAltitudeAlphaBeta *const fusion, const FusionAltitudeAlphaBetaSensorIndex sensor);

SIZED bool SizedFusionAltitudeAlphaBetaIsTimedOut(const FusionAltitudeAlphaBeta *const fusion, const FusionAltitudeAlphaBetaSensorIndex sensor) {
    return FusionAltitudeAlphaBetaIsTimedOut(fusion, sensor);
}

uint32_t SizedFusionAltitudeAlphaBetaGetTimeoutCount(const FusionAltitudeAlphaBeta *const fusion, const FusionAltitudeAlphaBetaSensorIndex sensor);

SIZED uint32_t SizedFusionAltitudeAlphaBetaGetTimeoutCount(const FusionAltitudeAlphaBeta *const fusion, const FusionAltitudeAlphaBetaSensorIndex sensor) {
    return FusionAltitudeAlphaBetaGetTimeoutCount(fusion, sensor);
}
