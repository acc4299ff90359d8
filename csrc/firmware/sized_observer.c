/**
 * @file sized_observer.c
 * @brief Out-of-line copies of every public function of fusion_altitude.h,
 * for measuring code size and stack (docs/embedded.md).
 *
 * The public functions are static inline. Each is wrapped here in an external
 * function named Sized<Name> that only forwards its arguments and is marked
 * flatten, so the compiler inlines the public function and everything it
 * calls into the wrapper. The wrapper's symbol size (nm --size-sort) is then
 * the code that function costs on its own at one call site, and its
 * -fstack-usage line is that function's worst-case stack.
 */

#include "fusion_altitude.h"

#if defined(__GNUC__)
#define SIZED __attribute__((flatten))
#else
#define SIZED
#endif

//------------------------------------------------------------------------------
// Out-of-line wrappers, one per public function

uint32_t SizedFusionAltitudeFloatBits(const float value);
bool SizedFusionAltitudeIsFinite(const float value);
bool SizedFusionAltitudeIsNaN(const float value);
float SizedFusionAltitudeNaN(void);
const char *SizedFusionAltitudeStatusMessage(const FusionAltitudeStatus status);
FusionAltitudeSettings SizedFusionAltitudeSettingsDefault(void);
FusionAltitudeStatus SizedFusionAltitudeSettingsCheck(const FusionAltitudeSettings *const settings);
FusionAltitudeStatus SizedFusionAltitudeSettingsValidate(const FusionAltitudeSettings *const settings, const float dt);
FusionAltitudeStatus SizedFusionAltitudeSettingsFromBandwidth(FusionAltitudeSettings *const settings, const float omega,
                                                              const float zeta, const float omegaBias);
FusionAltitudeStatus SizedFusionAltitudeSettingsFromPreset(FusionAltitudeSettings *const settings, const FusionAltitudePreset preset);
void SizedFusionAltitudeInitialise(FusionAltitude *const altitude);
FusionAltitudeStatus SizedFusionAltitudeSetSettings(FusionAltitude *const altitude, const FusionAltitudeSettings *const settings);
FusionAltitudeStatus SizedFusionAltitudeReset(FusionAltitude *const altitude, const float baroAltitude);
FusionAltitudeStatus SizedFusionAltitudeResetWithBias(FusionAltitude *const altitude, const float baroAltitude, const float accelBias);
FusionAltitudeStatus SizedFusionAltitudeCheckInputs(const float accel, const float baroAltitude, const float dt);
FusionAltitudeStatus SizedFusionAltitudeUpdate(FusionAltitude *const altitude, const float accel, const float baroAltitude, const float dt);
FusionAltitudeSettings SizedFusionAltitudeGetSettings(const FusionAltitude *const altitude);
float SizedFusionAltitudeGetAltitude(const FusionAltitude *const altitude);
float SizedFusionAltitudeGetVerticalVelocity(const FusionAltitude *const altitude);
float SizedFusionAltitudeGetAccelBias(const FusionAltitude *const altitude);
float SizedFusionAltitudeGetBaroResidual(const FusionAltitude *const altitude);
bool SizedFusionAltitudeIsReferenceSet(const FusionAltitude *const altitude);
uint32_t SizedFusionAltitudeGetGapCount(const FusionAltitude *const altitude);
uint32_t SizedFusionAltitudeGetBaroTimeouts(const FusionAltitude *const altitude);
bool SizedFusionAltitudeIsBaroTimedOut(const FusionAltitude *const altitude);
bool SizedFusionAltitudeIsStepStable(const FusionAltitudeSettings *const settings, const float dt, const float interval);
float SizedFusionAltitudeInfinity(void);

SIZED uint32_t SizedFusionAltitudeFloatBits(const float value) {
    return FusionAltitudeFloatBits(value);
}

SIZED bool SizedFusionAltitudeIsFinite(const float value) {
    return FusionAltitudeIsFinite(value);
}

SIZED bool SizedFusionAltitudeIsNaN(const float value) {
    return FusionAltitudeIsNaN(value);
}

SIZED float SizedFusionAltitudeNaN(void) {
    return FusionAltitudeNaN();
}

SIZED const char *SizedFusionAltitudeStatusMessage(const FusionAltitudeStatus status) {
    return FusionAltitudeStatusMessage(status);
}

SIZED FusionAltitudeSettings SizedFusionAltitudeSettingsDefault(void) {
    return FusionAltitudeSettingsDefault();
}

SIZED FusionAltitudeStatus SizedFusionAltitudeSettingsCheck(const FusionAltitudeSettings *const settings) {
    return FusionAltitudeSettingsCheck(settings);
}

SIZED FusionAltitudeStatus SizedFusionAltitudeSettingsValidate(const FusionAltitudeSettings *const settings, const float dt) {
    return FusionAltitudeSettingsValidate(settings, dt);
}

FusionAltitudeStatus SizedFusionAltitudeSettingsFromBandwidth(FusionAltitudeSettings *const settings, const float omega,
                                                              const float zeta, const float omegaBias) {
    return FusionAltitudeSettingsFromBandwidth(settings, omega, zeta, omegaBias);
}

SIZED FusionAltitudeStatus SizedFusionAltitudeSettingsFromPreset(FusionAltitudeSettings *const settings, const FusionAltitudePreset preset) {
    return FusionAltitudeSettingsFromPreset(settings, preset);
}

SIZED void SizedFusionAltitudeInitialise(FusionAltitude *const altitude) {
    FusionAltitudeInitialise(altitude);
}

SIZED FusionAltitudeStatus SizedFusionAltitudeSetSettings(FusionAltitude *const altitude, const FusionAltitudeSettings *const settings) {
    return FusionAltitudeSetSettings(altitude, settings);
}

SIZED FusionAltitudeStatus SizedFusionAltitudeReset(FusionAltitude *const altitude, const float baroAltitude) {
    return FusionAltitudeReset(altitude, baroAltitude);
}

SIZED FusionAltitudeStatus SizedFusionAltitudeResetWithBias(FusionAltitude *const altitude, const float baroAltitude, const float accelBias) {
    return FusionAltitudeResetWithBias(altitude, baroAltitude, accelBias);
}

SIZED FusionAltitudeStatus SizedFusionAltitudeCheckInputs(const float accel, const float baroAltitude, const float dt) {
    return FusionAltitudeCheckInputs(accel, baroAltitude, dt);
}

SIZED FusionAltitudeStatus SizedFusionAltitudeUpdate(FusionAltitude *const altitude, const float accel, const float baroAltitude, const float dt) {
    return FusionAltitudeUpdate(altitude, accel, baroAltitude, dt);
}

SIZED FusionAltitudeSettings SizedFusionAltitudeGetSettings(const FusionAltitude *const altitude) {
    return FusionAltitudeGetSettings(altitude);
}

SIZED float SizedFusionAltitudeGetAltitude(const FusionAltitude *const altitude) {
    return FusionAltitudeGetAltitude(altitude);
}

SIZED float SizedFusionAltitudeGetVerticalVelocity(const FusionAltitude *const altitude) {
    return FusionAltitudeGetVerticalVelocity(altitude);
}

SIZED float SizedFusionAltitudeGetAccelBias(const FusionAltitude *const altitude) {
    return FusionAltitudeGetAccelBias(altitude);
}

SIZED float SizedFusionAltitudeGetBaroResidual(const FusionAltitude *const altitude) {
    return FusionAltitudeGetBaroResidual(altitude);
}

SIZED bool SizedFusionAltitudeIsReferenceSet(const FusionAltitude *const altitude) {
    return FusionAltitudeIsReferenceSet(altitude);
}

SIZED uint32_t SizedFusionAltitudeGetGapCount(const FusionAltitude *const altitude) {
    return FusionAltitudeGetGapCount(altitude);
}

SIZED uint32_t SizedFusionAltitudeGetBaroTimeouts(const FusionAltitude *const altitude) {
    return FusionAltitudeGetBaroTimeouts(altitude);
}

SIZED bool SizedFusionAltitudeIsBaroTimedOut(const FusionAltitude *const altitude) {
    return FusionAltitudeIsBaroTimedOut(altitude);
}

SIZED bool SizedFusionAltitudeIsStepStable(const FusionAltitudeSettings *const settings, const float dt, const float interval) {
    return FusionAltitudeIsStepStable(settings, dt, interval);
}

SIZED float SizedFusionAltitudeInfinity(void) {
    return FusionAltitudeInfinity();
}
