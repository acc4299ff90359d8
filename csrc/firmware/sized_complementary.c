/**
 * @file sized_complementary.c
 * @brief Out-of-line copies of every public function of
 * fusion_altitude_complementary.h, for measuring code size and stack
 * (docs/embedded.md), as sized_observer.c does for fusion_altitude.h: each public
 * function is wrapped in an external function Sized<Name>, marked flatten so
 * that the function and everything it calls is inlined into the wrapper.
 */

#include "fusion_altitude_complementary.h"

#if defined(__GNUC__)
#define SIZED __attribute__((flatten))
#else
#define SIZED
#endif

//------------------------------------------------------------------------------
// Out-of-line wrappers, one per public function

const char *SizedFusionAltitudeComplementaryStatusMessage(const FusionAltitudeComplementaryStatus status);

SIZED const char *SizedFusionAltitudeComplementaryStatusMessage(const FusionAltitudeComplementaryStatus status) {
    return FusionAltitudeComplementaryStatusMessage(status);
}

FusionAltitudeComplementarySettings SizedFusionAltitudeComplementarySettingsDefault(void);

SIZED FusionAltitudeComplementarySettings SizedFusionAltitudeComplementarySettingsDefault(void) {
    return FusionAltitudeComplementarySettingsDefault();
}

FusionAltitudeComplementaryStatus SizedFusionAltitudeComplementarySettingsCheck(const FusionAltitudeComplementarySettings *const settings);

SIZED FusionAltitudeComplementaryStatus SizedFusionAltitudeComplementarySettingsCheck(const FusionAltitudeComplementarySettings *const settings) {
    return FusionAltitudeComplementarySettingsCheck(settings);
}

void SizedFusionAltitudeComplementaryInitialise(FusionAltitudeComplementary *const filter);

SIZED void SizedFusionAltitudeComplementaryInitialise(FusionAltitudeComplementary *const filter) {
    FusionAltitudeComplementaryInitialise(filter);
}

FusionAltitudeComplementaryStatus SizedFusionAltitudeComplementarySetSettings(FusionAltitudeComplementary *const filter, const FusionAltitudeComplementarySettings *const settings);

SIZED FusionAltitudeComplementaryStatus SizedFusionAltitudeComplementarySetSettings(FusionAltitudeComplementary *const filter, const FusionAltitudeComplementarySettings *const settings) {
    return FusionAltitudeComplementarySetSettings(filter, settings);
}

FusionAltitudeComplementaryStatus SizedFusionAltitudeComplementaryReset(FusionAltitudeComplementary *const filter, const float baroAltitude);

SIZED FusionAltitudeComplementaryStatus SizedFusionAltitudeComplementaryReset(FusionAltitudeComplementary *const filter, const float baroAltitude) {
    return FusionAltitudeComplementaryReset(filter, baroAltitude);
}

FusionAltitudeComplementaryStatus SizedFusionAltitudeComplementaryCheckInputs(const float accel, const float baroAltitude, const float dt);

SIZED FusionAltitudeComplementaryStatus SizedFusionAltitudeComplementaryCheckInputs(const float accel, const float baroAltitude, const float dt) {
    return FusionAltitudeComplementaryCheckInputs(accel, baroAltitude, dt);
}

FusionAltitudeComplementaryStatus SizedFusionAltitudeComplementaryUpdate(FusionAltitudeComplementary *const filter, const float accel, const float baroAltitude, const float dt);

SIZED FusionAltitudeComplementaryStatus SizedFusionAltitudeComplementaryUpdate(FusionAltitudeComplementary *const filter, const float accel, const float baroAltitude, const float dt) {
    return FusionAltitudeComplementaryUpdate(filter, accel, baroAltitude, dt);
}

FusionAltitudeComplementarySettings SizedFusionAltitudeComplementaryGetSettings(const FusionAltitudeComplementary *const filter);

SIZED FusionAltitudeComplementarySettings SizedFusionAltitudeComplementaryGetSettings(const FusionAltitudeComplementary *const filter) {
    return FusionAltitudeComplementaryGetSettings(filter);
}

float SizedFusionAltitudeComplementaryGetAltitude(const FusionAltitudeComplementary *const filter);

SIZED float SizedFusionAltitudeComplementaryGetAltitude(const FusionAltitudeComplementary *const filter) {
    return FusionAltitudeComplementaryGetAltitude(filter);
}

float SizedFusionAltitudeComplementaryGetVerticalVelocity(const FusionAltitudeComplementary *const filter);

SIZED float SizedFusionAltitudeComplementaryGetVerticalVelocity(const FusionAltitudeComplementary *const filter) {
    return FusionAltitudeComplementaryGetVerticalVelocity(filter);
}

float SizedFusionAltitudeComplementaryGetBaroFiltered(const FusionAltitudeComplementary *const filter);

SIZED float SizedFusionAltitudeComplementaryGetBaroFiltered(const FusionAltitudeComplementary *const filter) {
    return FusionAltitudeComplementaryGetBaroFiltered(filter);
}

float SizedFusionAltitudeComplementaryGetBaroVelocity(const FusionAltitudeComplementary *const filter);

SIZED float SizedFusionAltitudeComplementaryGetBaroVelocity(const FusionAltitudeComplementary *const filter) {
    return FusionAltitudeComplementaryGetBaroVelocity(filter);
}

bool SizedFusionAltitudeComplementaryIsReferenceSet(const FusionAltitudeComplementary *const filter);

SIZED bool SizedFusionAltitudeComplementaryIsReferenceSet(const FusionAltitudeComplementary *const filter) {
    return FusionAltitudeComplementaryIsReferenceSet(filter);
}

uint32_t SizedFusionAltitudeComplementaryGetGapCount(const FusionAltitudeComplementary *const filter);
uint32_t SizedFusionAltitudeComplementaryGetBaroTimeouts(const FusionAltitudeComplementary *const filter);
bool SizedFusionAltitudeComplementaryIsBaroTimedOut(const FusionAltitudeComplementary *const filter);

SIZED uint32_t SizedFusionAltitudeComplementaryGetGapCount(const FusionAltitudeComplementary *const filter) {
    return FusionAltitudeComplementaryGetGapCount(filter);
}

SIZED uint32_t SizedFusionAltitudeComplementaryGetBaroTimeouts(const FusionAltitudeComplementary *const filter) {
    return FusionAltitudeComplementaryGetBaroTimeouts(filter);
}

SIZED bool SizedFusionAltitudeComplementaryIsBaroTimedOut(const FusionAltitudeComplementary *const filter) {
    return FusionAltitudeComplementaryIsBaroTimedOut(filter);
}
