/**
 * @file sized_ins.c
 * @brief Out-of-line copies of every public function of
 * fusion_altitude_ins.h, for measuring code size and stack, as
 * sized_observer.c does for fusion_altitude.h: each public function is
 * wrapped in an external function Sized<Name>, marked flatten so that the
 * function and everything it calls is inlined into the wrapper (sqrtf stays
 * a call unless -fno-math-errno lets it be one vsqrt.f32 / fsqrt.s).
 * cycles_ins.c traces SizedFusionAltitudeInsUpdate on QEMU.
 */

#include "fusion_altitude_ins.h"

#if defined(__GNUC__)
#define SIZED __attribute__((flatten))
#else
#define SIZED
#endif

//------------------------------------------------------------------------------
// Out-of-line wrappers, one per public function

const char * SizedFusionAltitudeInsStatusMessage(const FusionAltitudeInsStatus status);

SIZED const char * SizedFusionAltitudeInsStatusMessage(const FusionAltitudeInsStatus status) {
    return FusionAltitudeInsStatusMessage(status);
}

FusionAltitudeInsSettings SizedFusionAltitudeInsSettingsDefault(void);

SIZED FusionAltitudeInsSettings SizedFusionAltitudeInsSettingsDefault(void) {
    return FusionAltitudeInsSettingsDefault();
}

FusionAltitudeInsStatus SizedFusionAltitudeInsSettingsCheck(const FusionAltitudeInsSettings *const s);

SIZED FusionAltitudeInsStatus SizedFusionAltitudeInsSettingsCheck(const FusionAltitudeInsSettings *const s) {
    return FusionAltitudeInsSettingsCheck(s);
}

FusionAltitudeInsVector SizedFusionAltitudeInsNoMag(void);

SIZED FusionAltitudeInsVector SizedFusionAltitudeInsNoMag(void) {
    return FusionAltitudeInsNoMag();
}

FusionAltitudeInsStatus SizedFusionAltitudeInsInitialiseWith(FusionAltitudeIns *const ins, const FusionAltitudeInsSettings *const settings);

SIZED FusionAltitudeInsStatus SizedFusionAltitudeInsInitialiseWith(FusionAltitudeIns *const ins, const FusionAltitudeInsSettings *const settings) {
    return FusionAltitudeInsInitialiseWith(ins, settings);
}

void SizedFusionAltitudeInsInitialise(FusionAltitudeIns *const ins);

SIZED void SizedFusionAltitudeInsInitialise(FusionAltitudeIns *const ins) {
    FusionAltitudeInsInitialise(ins);
}

FusionAltitudeInsStatus SizedFusionAltitudeInsSetSettings(FusionAltitudeIns *const ins, const FusionAltitudeInsSettings *const settings);

SIZED FusionAltitudeInsStatus SizedFusionAltitudeInsSetSettings(FusionAltitudeIns *const ins, const FusionAltitudeInsSettings *const settings) {
    return FusionAltitudeInsSetSettings(ins, settings);
}

bool SizedFusionAltitudeInsIsNoMag(const FusionAltitudeInsVector m);

SIZED bool SizedFusionAltitudeInsIsNoMag(const FusionAltitudeInsVector m) {
    return FusionAltitudeInsIsNoMag(m);
}

FusionAltitudeInsStatus SizedFusionAltitudeInsCheckInputs(const FusionAltitudeInsVector gyro, const FusionAltitudeInsVector accel, const FusionAltitudeInsVector mag, const float baroAltitude, const float dt);

SIZED FusionAltitudeInsStatus SizedFusionAltitudeInsCheckInputs(const FusionAltitudeInsVector gyro, const FusionAltitudeInsVector accel, const FusionAltitudeInsVector mag, const float baroAltitude, const float dt) {
    return FusionAltitudeInsCheckInputs(gyro, accel, mag, baroAltitude, dt);
}

FusionAltitudeInsStatus SizedFusionAltitudeInsUpdate(FusionAltitudeIns *const ins, const FusionAltitudeInsVector gyro, const FusionAltitudeInsVector accel, const FusionAltitudeInsVector mag, const float baroAltitude, const float dt);

SIZED FusionAltitudeInsStatus SizedFusionAltitudeInsUpdate(FusionAltitudeIns *const ins, const FusionAltitudeInsVector gyro, const FusionAltitudeInsVector accel, const FusionAltitudeInsVector mag, const float baroAltitude, const float dt) {
    return FusionAltitudeInsUpdate(ins, gyro, accel, mag, baroAltitude, dt);
}

FusionAltitudeInsSettings SizedFusionAltitudeInsGetSettings(const FusionAltitudeIns *const ins);

SIZED FusionAltitudeInsSettings SizedFusionAltitudeInsGetSettings(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsGetSettings(ins);
}

float SizedFusionAltitudeInsGetAltitude(const FusionAltitudeIns *const ins);

SIZED float SizedFusionAltitudeInsGetAltitude(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsGetAltitude(ins);
}

float SizedFusionAltitudeInsGetVerticalVelocity(const FusionAltitudeIns *const ins);

SIZED float SizedFusionAltitudeInsGetVerticalVelocity(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsGetVerticalVelocity(ins);
}

FusionAltitudeInsQuaternion SizedFusionAltitudeInsGetQuaternion(const FusionAltitudeIns *const ins);

SIZED FusionAltitudeInsQuaternion SizedFusionAltitudeInsGetQuaternion(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsGetQuaternion(ins);
}

FusionAltitudeInsQuaternion SizedFusionAltitudeInsGetLocalToGlobal(const FusionAltitudeIns *const ins);

SIZED FusionAltitudeInsQuaternion SizedFusionAltitudeInsGetLocalToGlobal(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsGetLocalToGlobal(ins);
}

FusionAltitudeInsQuaternion SizedFusionAltitudeInsGetGlobalQuaternion(const FusionAltitudeIns *const ins);

SIZED FusionAltitudeInsQuaternion SizedFusionAltitudeInsGetGlobalQuaternion(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsGetGlobalQuaternion(ins);
}

FusionAltitudeInsVector SizedFusionAltitudeInsGetGyroBias(const FusionAltitudeIns *const ins);

SIZED FusionAltitudeInsVector SizedFusionAltitudeInsGetGyroBias(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsGetGyroBias(ins);
}

float SizedFusionAltitudeInsGetAccelZBias(const FusionAltitudeIns *const ins);

SIZED float SizedFusionAltitudeInsGetAccelZBias(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsGetAccelZBias(ins);
}

float SizedFusionAltitudeInsGetBaroBias(const FusionAltitudeIns *const ins);

SIZED float SizedFusionAltitudeInsGetBaroBias(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsGetBaroBias(ins);
}

bool SizedFusionAltitudeInsIsStationary(const FusionAltitudeIns *const ins);

SIZED bool SizedFusionAltitudeInsIsStationary(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsIsStationary(ins);
}

bool SizedFusionAltitudeInsIsAccelRejected(const FusionAltitudeIns *const ins);

SIZED bool SizedFusionAltitudeInsIsAccelRejected(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsIsAccelRejected(ins);
}

uint32_t SizedFusionAltitudeInsGetGapCount(const FusionAltitudeIns *const ins);

SIZED uint32_t SizedFusionAltitudeInsGetGapCount(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsGetGapCount(ins);
}

uint32_t SizedFusionAltitudeInsGetBaroRejections(const FusionAltitudeIns *const ins);

SIZED uint32_t SizedFusionAltitudeInsGetBaroRejections(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsGetBaroRejections(ins);
}

uint32_t SizedFusionAltitudeInsGetBaroResets(const FusionAltitudeIns *const ins);

SIZED uint32_t SizedFusionAltitudeInsGetBaroResets(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsGetBaroResets(ins);
}

bool SizedFusionAltitudeInsIsBaroRejecting(const FusionAltitudeIns *const ins);

SIZED bool SizedFusionAltitudeInsIsBaroRejecting(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsIsBaroRejecting(ins);
}

bool SizedFusionAltitudeInsIsBaroTimedOut(const FusionAltitudeIns *const ins);

SIZED bool SizedFusionAltitudeInsIsBaroTimedOut(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsIsBaroTimedOut(ins);
}

bool SizedFusionAltitudeInsIsHeightHeld(const FusionAltitudeIns *const ins);

SIZED bool SizedFusionAltitudeInsIsHeightHeld(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsIsHeightHeld(ins);
}

uint32_t SizedFusionAltitudeInsGetBaroTimeouts(const FusionAltitudeIns *const ins);

SIZED uint32_t SizedFusionAltitudeInsGetBaroTimeouts(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsGetBaroTimeouts(ins);
}
