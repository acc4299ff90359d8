/**
 * @file firmware_rocket.c
 * @brief A firmware-style translation unit that calls every public function
 * of fusion_altitude_rocket.h: set-up with checked settings and a 100 Hz task
 * with a 50 Hz baro that fires the drogue at apogee and the main at the main
 * altitude. Cross-compiled for each target with warnings as errors; its
 * object code is checked for double instructions and libm calls (with
 * sized_rocket.c, one out-of-line copy of each public function).
 */

#include "fusion_altitude_rocket.h"

volatile float firmwareRocketAccel;  /* m/s^2, long axis (nose up) minus g */
volatile float firmwareRocketBaro;   /* m, pressure altitude */
volatile bool firmwareRocketBaroReady;
volatile bool firmwareRocketInsReady; /* an INS vertical acceleration is in firmwareRocketAccel */
volatile float firmwareRocketHeight;  /* m above the pad */
volatile float firmwareRocketVelocity; /* m/s */
volatile float firmwareRocketBias;    /* m/s^2 */
volatile float firmwareRocketPad;     /* m */
volatile float firmwareRocketTime;    /* s */
volatile uint32_t firmwareRocketGaps;
volatile bool firmwareRocketDrogue;
volatile bool firmwareRocketMain;
volatile bool firmwareRocketLockedOut;
volatile bool firmwareRocketCalibrated;
volatile int firmwareRocketBaroFate;
volatile float firmwareRocketApogee; /* m above the pad */
volatile float firmwareRocketGains[3];
const char *volatile firmwareRocketError;

static FusionAltitudeRocket firmwareRocket;

bool FirmwareRocketSetup(void);
void FirmwareRocketTask(void);

/* Main at 300 m, lockout at 120 m/s, checked before use. */
bool FirmwareRocketSetup(void) {
    FusionAltitudeRocketSettings settings = FusionAltitudeRocketSettingsDefault();
    settings.observer = FusionAltitudeRocketObserverSettings();
    settings.mainAltitude = 300.0f;
    settings.lockoutSpeed = 120.0f;
    FusionAltitudeRocketStatus status = FusionAltitudeRocketSettingsCheck(&settings);
    if (status == FusionAltitudeRocketStatusOk) {
        status = FusionAltitudeRocketInitialise(&firmwareRocket, &settings);
    }
    if (status != FusionAltitudeRocketStatusOk) {
        firmwareRocketError = FusionAltitudeRocketStatusMessage(status);
        return false;
    }
    const FusionAltitudeSettings gains = settings.observer;
    firmwareRocketGains[0] = gains.positionGain;
    firmwareRocketGains[1] = gains.velocityGain;
    firmwareRocketGains[2] = gains.biasGain;
    return true;
}

/* One 100 Hz step. */
void FirmwareRocketTask(void) {
    const float accel = firmwareRocketAccel;
    const float baro = firmwareRocketBaroReady ? firmwareRocketBaro : FUSION_ALTITUDE_NO_BARO;
    if (FusionAltitudeRocketCheckInputs(accel, baro, 0.01f) != FusionAltitudeRocketStatusOk) {
        firmwareRocketError = "bad sample";
        return;
    }
    const FusionAltitudeRocketStatus status = firmwareRocketInsReady
                                                  ? FusionAltitudeRocketUpdateWithVerticalAccel(&firmwareRocket, accel, baro, 0.01f)
                                                  : FusionAltitudeRocketUpdate(&firmwareRocket, accel, baro, 0.01f);
    if (status != FusionAltitudeRocketStatusOk) {
        firmwareRocketError = FusionAltitudeRocketStatusMessage(status);
        return;
    }
    firmwareRocketHeight = FusionAltitudeRocketGetHeight(&firmwareRocket);
    firmwareRocketVelocity = FusionAltitudeRocketGetVerticalVelocity(&firmwareRocket);
    firmwareRocketBias = FusionAltitudeRocketGetAccelBias(&firmwareRocket);
    firmwareRocketPad = FusionAltitudeRocketGetPadAltitude(&firmwareRocket);
    firmwareRocketTime = FusionAltitudeRocketGetTime(&firmwareRocket);
    firmwareRocketGaps = FusionAltitudeRocketGetGapCount(&firmwareRocket);
    firmwareRocketLockedOut = FusionAltitudeRocketIsLockedOut(&firmwareRocket);
    firmwareRocketCalibrated = FusionAltitudeRocketIsCalibrated(&firmwareRocket);
    firmwareRocketBaroFate = (int) FusionAltitudeRocketGetBaro(&firmwareRocket);
    const FusionAltitudeRocketPhase phase = FusionAltitudeRocketGetPhase(&firmwareRocket);
    if ((phase >= FusionAltitudeRocketPhaseDrogue) && !firmwareRocketDrogue) {
        firmwareRocketDrogue = true; /* fire the drogue charge */
        firmwareRocketApogee = FusionAltitudeRocketGetEvent(&firmwareRocket, FusionAltitudeRocketEventApogee).height;
    }
    if ((phase >= FusionAltitudeRocketPhaseMain) && !firmwareRocketMain) {
        firmwareRocketMain = true; /* fire the main charge */
    }
}
