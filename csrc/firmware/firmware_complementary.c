/**
 * @file firmware_complementary.c
 * @brief A firmware-style translation unit that calls every public function
 * of fusion_altitude_complementary.h: set-up with checked settings and a
 * 100 Hz task with a 25 Hz baro. Cross-compiled for each target with
 * warnings as errors; its object code is checked for double instructions and
 * libm calls (with sized_complementary.c, one out-of-line copy of each
 * public function).
 */

#include "fusion_altitude_complementary.h"

volatile float firmwareComplementaryAccel;        /* m/s^2, earth frame, +up, gravity removed */
volatile float firmwareComplementaryBaroAltitude; /* m */
volatile bool firmwareComplementaryBaroReady;
volatile float firmwareComplementaryAltitude;          /* m */
volatile float firmwareComplementaryVerticalVelocity;  /* m/s */
volatile float firmwareComplementaryBaroFiltered;      /* m */
volatile float firmwareComplementaryBaroVelocity;      /* m/s, NaN without baro */
volatile uint32_t firmwareComplementaryGapCount;
volatile uint32_t firmwareComplementaryBaroTimeouts;
volatile bool firmwareComplementaryBaroAided;
const char *volatile firmwareComplementaryError;

static FusionAltitudeComplementary firmwareComplementary;

bool FirmwareComplementarySetup(float groundAltitude);
void FirmwareComplementaryTask(void);

/* Faster blend for a small multirotor, checked before use; reference at the ground baro reading. */
bool FirmwareComplementarySetup(const float groundAltitude) {
    FusionAltitudeComplementaryInitialise(&firmwareComplementary);
    FusionAltitudeComplementarySettings settings = FusionAltitudeComplementarySettingsDefault();
    settings.velocityTimeConstant = 4.0f;
    settings.altitudeTimeConstant = 2.0f;
    FusionAltitudeComplementaryStatus status = FusionAltitudeComplementarySettingsCheck(&settings);
    if (status == FusionAltitudeComplementaryStatusOk) {
        status = FusionAltitudeComplementarySetSettings(&firmwareComplementary, &settings);
    }
    if (status == FusionAltitudeComplementaryStatusOk) {
        status = FusionAltitudeComplementaryReset(&firmwareComplementary, groundAltitude);
    }
    if (status != FusionAltitudeComplementaryStatusOk) {
        firmwareComplementaryError = FusionAltitudeComplementaryStatusMessage(status);
        return false;
    }
    return true;
}

/* One 100 Hz step: the baro sample when ready, NaN (no sample) otherwise. */
void FirmwareComplementaryTask(void) {
    const float accel = firmwareComplementaryAccel;
    const float baro = firmwareComplementaryBaroReady ? firmwareComplementaryBaroAltitude : FusionAltitudeNaN();
    if (FusionAltitudeComplementaryCheckInputs(accel, baro, 0.01f) != FusionAltitudeComplementaryStatusOk) {
        firmwareComplementaryError = "bad sample";
        return;
    }
    const FusionAltitudeComplementaryStatus status = FusionAltitudeComplementaryUpdate(&firmwareComplementary, accel, baro, 0.01f);
    if (status != FusionAltitudeComplementaryStatusOk) {
        firmwareComplementaryError = FusionAltitudeComplementaryStatusMessage(status);
        return;
    }
    if (!FusionAltitudeComplementaryIsReferenceSet(&firmwareComplementary)) {
        return;
    }
    firmwareComplementaryAltitude = FusionAltitudeComplementaryGetAltitude(&firmwareComplementary);
    firmwareComplementaryVerticalVelocity = FusionAltitudeComplementaryGetVerticalVelocity(&firmwareComplementary);
    firmwareComplementaryBaroFiltered = FusionAltitudeComplementaryGetBaroFiltered(&firmwareComplementary);
    firmwareComplementaryBaroVelocity = FusionAltitudeComplementaryGetBaroVelocity(&firmwareComplementary);
    firmwareComplementaryGapCount = FusionAltitudeComplementaryGetGapCount(&firmwareComplementary);
    firmwareComplementaryBaroTimeouts = FusionAltitudeComplementaryGetBaroTimeouts(&firmwareComplementary);
    firmwareComplementaryBaroAided = !FusionAltitudeComplementaryIsBaroTimedOut(&firmwareComplementary);
    /* Guard against a corrupted RAM image: back to the defaults. */
    const FusionAltitudeComplementarySettings settings = FusionAltitudeComplementaryGetSettings(&firmwareComplementary);
    if (FusionAltitudeComplementarySettingsCheck(&settings) != FusionAltitudeComplementaryStatusOk) {
        const FusionAltitudeComplementarySettings defaults = FusionAltitudeComplementarySettingsDefault();
        (void) FusionAltitudeComplementarySetSettings(&firmwareComplementary, &defaults);
    }
}
