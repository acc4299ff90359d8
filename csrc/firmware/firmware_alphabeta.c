/**
 * @file firmware_alphabeta.c
 * @brief A firmware-style translation unit that calls every public function
 * of fusion_altitude_alphabeta.h: set-up with checked settings and a 100 Hz
 * task with a 25 Hz baro, 20 Hz lidar, 10 Hz sonar and 5 Hz GPS.
 * Cross-compiled for each target with warnings as errors; its object code is
 * checked for double instructions and libm calls (with sized_alphabeta.c,
 * one out-of-line copy of each public function).
 */

#include "fusion_altitude_alphabeta.h"

volatile float firmwareAlphaBetaAccel; /* m/s^2, earth frame, +up, gravity removed */
volatile bool firmwareAlphaBetaAccelReady;
volatile float firmwareAlphaBetaSamples[4]; /* m: baro, lidar, sonar, GPS */
volatile bool firmwareAlphaBetaReady[4];
volatile float firmwareAlphaBetaAltitude;         /* m */
volatile uint32_t firmwareAlphaBetaGapCount;
volatile bool firmwareAlphaBetaBaroTimedOut;     /* the baro silent for longer than its timeout */
volatile uint32_t firmwareAlphaBetaBaroTimeouts; /* baro silences longer than its timeout so far */
volatile float firmwareAlphaBetaVerticalVelocity; /* m/s */
volatile float firmwareAlphaBetaLidarWeight;
volatile int32_t firmwareAlphaBetaBaroQuality;
volatile float firmwareAlphaBetaGains[2]; /* alpha, beta of the baro filter */
const char *volatile firmwareAlphaBetaError;

static FusionAltitudeAlphaBeta firmwareAlphaBeta;

bool FirmwareAlphaBetaSetup(void);
void FirmwareAlphaBetaTask(void);

/* A 12 m lidar and a longer GPS timeout, checked before use. */
bool FirmwareAlphaBetaSetup(void) {
    FusionAltitudeAlphaBetaInitialise(&firmwareAlphaBeta);
    FusionAltitudeAlphaBetaSettings settings = FusionAltitudeAlphaBetaSettingsDefault();
    settings.sensors[FusionAltitudeAlphaBetaSensorLidar].altitudeMax = 12.0f;
    settings.sensors[FusionAltitudeAlphaBetaSensorGps].timeout = 2.5f;
    if (FusionAltitudeAlphaBetaSensorSettingsCheck(&settings.sensors[FusionAltitudeAlphaBetaSensorLidar]) != FusionAltitudeAlphaBetaStatusOk) {
        return false;
    }
    FusionAltitudeAlphaBetaStatus status = FusionAltitudeAlphaBetaSettingsCheck(&settings);
    if (status == FusionAltitudeAlphaBetaStatusOk) {
        status = FusionAltitudeAlphaBetaInitialiseWith(&firmwareAlphaBeta, &settings);
    }
    if (status != FusionAltitudeAlphaBetaStatusOk) {
        firmwareAlphaBetaError = FusionAltitudeAlphaBetaStatusMessage(status);
        return false;
    }
    return true;
}

/* One 100 Hz step: each sensor's sample when ready, NaN (no sample) otherwise. */
void FirmwareAlphaBetaTask(void) {
    FusionAltitudeAlphaBetaMeasurements m = FusionAltitudeAlphaBetaMeasurementsNone();
    if (firmwareAlphaBetaReady[0]) {
        m.baroAltitude = firmwareAlphaBetaSamples[0];
    }
    if (firmwareAlphaBetaReady[1]) {
        m.lidarAltitude = firmwareAlphaBetaSamples[1];
    }
    if (firmwareAlphaBetaReady[2]) {
        m.sonarAltitude = firmwareAlphaBetaSamples[2];
    }
    if (firmwareAlphaBetaReady[3]) {
        m.gpsAltitude = firmwareAlphaBetaSamples[3];
    }
    const float accel = firmwareAlphaBetaAccelReady ? firmwareAlphaBetaAccel : FusionAltitudeNaN();
    if (FusionAltitudeAlphaBetaCheckInputs(accel, 0.01f, &m) != FusionAltitudeAlphaBetaStatusOk) {
        firmwareAlphaBetaError = "bad sample";
        return;
    }
    const FusionAltitudeAlphaBetaStatus status = FusionAltitudeAlphaBetaUpdate(&firmwareAlphaBeta, accel, 0.01f, &m);
    if (status != FusionAltitudeAlphaBetaStatusOk) {
        firmwareAlphaBetaError = FusionAltitudeAlphaBetaStatusMessage(status);
        return;
    }
    if (!FusionAltitudeAlphaBetaIsStarted(&firmwareAlphaBeta)) {
        return;
    }
    firmwareAlphaBetaAltitude = FusionAltitudeAlphaBetaGetAltitude(&firmwareAlphaBeta);
    firmwareAlphaBetaGapCount = FusionAltitudeAlphaBetaGetGapCount(&firmwareAlphaBeta);
    firmwareAlphaBetaBaroTimedOut = FusionAltitudeAlphaBetaIsTimedOut(&firmwareAlphaBeta, FusionAltitudeAlphaBetaSensorBaro);
    firmwareAlphaBetaBaroTimeouts = FusionAltitudeAlphaBetaGetTimeoutCount(&firmwareAlphaBeta, FusionAltitudeAlphaBetaSensorBaro);
    firmwareAlphaBetaVerticalVelocity = FusionAltitudeAlphaBetaGetVerticalVelocity(&firmwareAlphaBeta);
    firmwareAlphaBetaLidarWeight = FusionAltitudeAlphaBetaGetWeight(&firmwareAlphaBeta, FusionAltitudeAlphaBetaSensorLidar);
    const int32_t quality = FusionAltitudeAlphaBetaGetQuality(&firmwareAlphaBeta, FusionAltitudeAlphaBetaSensorBaro);
    firmwareAlphaBetaBaroQuality = quality;
    float alpha;
    float beta;
    FusionAltitudeAlphaBetaGains(quality, &alpha, &beta);
    firmwareAlphaBetaGains[0] = alpha;
    firmwareAlphaBetaGains[1] = beta;
    /* Guard against a corrupted RAM image: back to the defaults. */
    const FusionAltitudeAlphaBetaSettings settings = FusionAltitudeAlphaBetaGetSettings(&firmwareAlphaBeta);
    if (FusionAltitudeAlphaBetaSettingsCheck(&settings) != FusionAltitudeAlphaBetaStatusOk) {
        const FusionAltitudeAlphaBetaSettings defaults = FusionAltitudeAlphaBetaSettingsDefault();
        (void) FusionAltitudeAlphaBetaSetSettings(&firmwareAlphaBeta, &defaults);
    }
}
