/**
 * @file firmware_observer.c
 * @brief A firmware-style translation unit that calls every public function
 * of fusion_altitude.h: set-up with tuning and a warm start, and a 100 Hz task.
 * It is cross-compiled for each target with warnings as errors and its object
 * code is checked for double instructions and libm calls (together with
 * sized_observer.c, which holds one out-of-line copy of each public function).
 */

#include "fusion_altitude.h"

//------------------------------------------------------------------------------
// A 100 Hz task as firmware would write it (sensor inputs and outputs are
// volatile so that nothing is optimised away)

volatile float firmwareAccel;        /* m/s^2, earth frame, +up, gravity removed */
volatile float firmwareBaroAltitude; /* m */
volatile bool firmwareBaroReady;
volatile float firmwareAltitude;         /* m */
volatile float firmwareVerticalVelocity; /* m/s */
volatile float firmwareAccelBias;        /* m/s^2 */
volatile uint32_t firmwareGapCount;
volatile uint32_t firmwareBaroTimeouts;
volatile bool firmwareBaroAided;
volatile float firmwareBaroResidual;     /* m */
const char *volatile firmwareError;

static FusionAltitude firmwareEstimator;

bool FirmwareSetup(const float groundAltitude, const float groundAccelBias);
void FirmwareTask(void);

/* Tunes for a fixed-wing at 100 Hz and warm-starts from a ground calibration. */
bool FirmwareSetup(const float groundAltitude, const float groundAccelBias) {
    FusionAltitudeInitialise(&firmwareEstimator);
    FusionAltitudeSettings settings;
    if (FusionAltitudeSettingsFromPreset(&settings, FusionAltitudePresetFixedWing) != FusionAltitudeStatusOk) {
        return false;
    }
    if (FusionAltitudeSettingsFromBandwidth(&settings, 0.5f, 0.7f, 0.1f) != FusionAltitudeStatusOk) {
        return false;
    }
    if (FusionAltitudeSettingsValidate(&settings, 0.01f) != FusionAltitudeStatusOk) {
        return false;
    }
    if (FusionAltitudeSetSettings(&firmwareEstimator, &settings) != FusionAltitudeStatusOk) {
        return false;
    }
    if (FusionAltitudeResetWithBias(&firmwareEstimator, groundAltitude, groundAccelBias) != FusionAltitudeStatusOk) {
        return false;
    }
    return FusionAltitudeIsReferenceSet(&firmwareEstimator);
}

/* One 100 Hz step: baro when a sample is ready, FUSION_ALTITUDE_NO_BARO otherwise. */
void FirmwareTask(void) {
    const float baro = firmwareBaroReady ? firmwareBaroAltitude : FUSION_ALTITUDE_NO_BARO;
    const float accel = firmwareAccel;
    const FusionAltitudeStatus status = FusionAltitudeUpdate(&firmwareEstimator, accel, baro, 0.01f);
    if (status != FusionAltitudeStatusOk) {
        /* Same status as the update: which input was bad, for the log. */
        firmwareError = FusionAltitudeStatusMessage(FusionAltitudeCheckInputs(accel, baro, 0.01f));
        if (FusionAltitudeIsFinite(firmwareBaroAltitude) && !FusionAltitudeIsNaN(firmwareBaroAltitude)) {
            (void) FusionAltitudeReset(&firmwareEstimator, firmwareBaroAltitude);
        }
        return;
    }
    firmwareAltitude = FusionAltitudeGetAltitude(&firmwareEstimator);
    firmwareVerticalVelocity = FusionAltitudeGetVerticalVelocity(&firmwareEstimator);
    firmwareAccelBias = FusionAltitudeGetAccelBias(&firmwareEstimator);
    firmwareGapCount = FusionAltitudeGetGapCount(&firmwareEstimator); /* logging gaps and scheduler stalls seen */
    firmwareBaroTimeouts = FusionAltitudeGetBaroTimeouts(&firmwareEstimator); /* baro outages past the timeout */
    firmwareBaroAided = !FusionAltitudeIsBaroTimedOut(&firmwareEstimator);  /* false: altitude not baro-aided */
    const float residual = FusionAltitudeGetBaroResidual(&firmwareEstimator);
    if (!FusionAltitudeIsNaN(residual)) { /* NaN (0x7FC00000): no baro this step */
        firmwareBaroResidual = residual;
    }
    /* Guard against a corrupted RAM image: fall back to the defaults. */
    const FusionAltitudeSettings settings = FusionAltitudeGetSettings(&firmwareEstimator);
    if (FusionAltitudeSettingsCheck(&settings) != FusionAltitudeStatusOk) {
        const FusionAltitudeSettings defaults = FusionAltitudeSettingsDefault();
        (void) FusionAltitudeSetSettings(&firmwareEstimator, &defaults);
    }
    if (FusionAltitudeFloatBits(firmwareAltitude) == FusionAltitudeFloatBits(FusionAltitudeNaN())) {
        FusionAltitudeInitialise(&firmwareEstimator);
    }
}
