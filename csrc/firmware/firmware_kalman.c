/**
 * @file firmware_kalman.c
 * @brief A firmware-style translation unit that calls every public function
 * of fusion_altitude_kalman.h: set-up with tuned settings, and a 100 Hz task
 * with a 25 Hz baro, a 20 Hz rangefinder and a 5 Hz GPS. It is cross-compiled
 * for each target with warnings as errors and its object code is checked for
 * double instructions and libm calls (together with sized_kalman.c, which
 * holds one out-of-line copy of each public function).
 */

#include "fusion_altitude_kalman.h"

//------------------------------------------------------------------------------
// A 100 Hz task as firmware would write it (sensor inputs and outputs are
// volatile so that nothing is optimised away)

volatile float firmwareKalmanAccel;         /* m/s^2, earth frame, +up, gravity removed */
volatile float firmwareKalmanBaroAltitude;  /* m */
volatile bool firmwareKalmanBaroReady;
volatile float firmwareKalmanRangeDistance; /* m */
volatile bool firmwareKalmanRangeReady;
volatile float firmwareKalmanGpsAltitude;   /* m */
volatile float firmwareKalmanGpsAccuracy;   /* m, NaN if the receiver reports none */
volatile int32_t firmwareKalmanGpsSatellites;
volatile bool firmwareKalmanGpsReady;
volatile bool firmwareKalmanLanding;
volatile float firmwareKalmanHeight;           /* m above ground */
volatile float firmwareKalmanAltitude;         /* m, baro-referenced */
volatile float firmwareKalmanAltitudeSigma2;   /* m^2 */
volatile float firmwareKalmanVerticalVelocity; /* m/s */
volatile float firmwareKalmanAccelBias;        /* m/s^2 */
volatile float firmwareKalmanBaroOffset;       /* m */
volatile float firmwareKalmanGpsOffset;        /* m */
volatile uint32_t firmwareKalmanGapCount;
volatile bool firmwareKalmanBaroAided; /* false while the baro is timed out (GPS or rangefinder carry on) */
volatile bool firmwareKalmanRangeTimedOut;
volatile bool firmwareKalmanGpsTimedOut;
volatile float firmwareKalmanVelocitySigma2;   /* m^2/s^2 */
volatile uint32_t firmwareKalmanGpsRejections;
volatile float firmwareKalmanBaroNis;
const char *volatile firmwareKalmanError;

static FusionAltitudeKalman firmwareKalman;

bool FirmwareKalmanSetup(void);
void FirmwareKalmanTask(void);

/* Settings for a small multirotor with a 0.02 m lidar, checked before use. */
bool FirmwareKalmanSetup(void) {
    FusionAltitudeKalmanInitialise(&firmwareKalman);
    FusionAltitudeKalmanSettings settings = FusionAltitudeKalmanSettingsDefault();
    settings.rangeNoise = 0.02f;
    settings.rangeMaximum = 12.0f;
    settings.rejectionTimeout = 0.5f;
    if (FusionAltitudeKalmanSettingsCheck(&settings) != FusionAltitudeKalmanStatusOk) {
        return false;
    }
    const FusionAltitudeKalmanStatus status = FusionAltitudeKalmanInitialiseWith(&firmwareKalman, &settings);
    if (status != FusionAltitudeKalmanStatusOk) {
        firmwareKalmanError = FusionAltitudeKalmanStatusMessage(status);
        return false;
    }
    return true;
}

/* One 100 Hz step: each sensor's sample when ready, NaN (no sample) otherwise. */
void FirmwareKalmanTask(void) {
    FusionAltitudeKalmanMeasurements m = FusionAltitudeKalmanMeasurementsNone();
    if (firmwareKalmanBaroReady) {
        m.baroAltitude = firmwareKalmanBaroAltitude;
    }
    if (firmwareKalmanRangeReady) {
        m.rangeDistance = firmwareKalmanRangeDistance;
    }
    if (firmwareKalmanGpsReady) {
        m.gpsAltitude = firmwareKalmanGpsAltitude;
        m.gpsVerticalAccuracy = firmwareKalmanGpsAccuracy;
        m.gpsSatellites = firmwareKalmanGpsSatellites;
    }
    m.groundEffect = firmwareKalmanLanding;
    const bool anySample = firmwareKalmanBaroReady || firmwareKalmanRangeReady || firmwareKalmanGpsReady;
    const FusionAltitudeKalmanStatus status =
        FusionAltitudeKalmanUpdate(&firmwareKalman, firmwareKalmanAccel, 0.01f, anySample ? &m : NULL);
    if (status != FusionAltitudeKalmanStatusOk) {
        firmwareKalmanError = FusionAltitudeKalmanStatusMessage(status);
        return;
    }
    firmwareKalmanHeight = FusionAltitudeKalmanGetHeightAboveGround(&firmwareKalman);
    firmwareKalmanAltitude = FusionAltitudeKalmanGetAltitude(&firmwareKalman);
    firmwareKalmanAltitudeSigma2 = FusionAltitudeKalmanGetAltitudeVariance(&firmwareKalman);
    firmwareKalmanVerticalVelocity = FusionAltitudeKalmanGetVerticalVelocity(&firmwareKalman);
    firmwareKalmanAccelBias = FusionAltitudeKalmanGetAccelBias(&firmwareKalman);
    firmwareKalmanBaroOffset = FusionAltitudeKalmanGetBaroOffset(&firmwareKalman);
    firmwareKalmanGpsOffset = FusionAltitudeKalmanGetGpsOffset(&firmwareKalman);
    firmwareKalmanGapCount = FusionAltitudeKalmanGetGapCount(&firmwareKalman);
    firmwareKalmanBaroAided = !FusionAltitudeKalmanIsBaroTimedOut(&firmwareKalman);
    firmwareKalmanRangeTimedOut = FusionAltitudeKalmanIsRangeTimedOut(&firmwareKalman);
    firmwareKalmanGpsTimedOut = FusionAltitudeKalmanIsGpsTimedOut(&firmwareKalman);
    firmwareKalmanVelocitySigma2 =
        FusionAltitudeKalmanGetCovariance(&firmwareKalman, FusionAltitudeKalmanStateVelocity, FusionAltitudeKalmanStateVelocity);
    firmwareKalmanGpsRejections = FusionAltitudeKalmanGetSensor(&firmwareKalman, FusionAltitudeKalmanSensorGps).rejections;
    const FusionAltitudeKalmanSensor baro = FusionAltitudeKalmanGetSensor(&firmwareKalman, FusionAltitudeKalmanSensorBaro);
    if (baro.result == FusionAltitudeKalmanResultFused) {
        firmwareKalmanBaroNis = FusionAltitudeKalmanGetNis(&firmwareKalman, FusionAltitudeKalmanSensorBaro);
    }
    /* Guard against a corrupted RAM image: back to the checked settings, or the defaults. */
    FusionAltitudeKalmanSettings settings = FusionAltitudeKalmanGetSettings(&firmwareKalman);
    if (FusionAltitudeKalmanSettingsCheck(&settings) != FusionAltitudeKalmanStatusOk) {
        settings = FusionAltitudeKalmanSettingsDefault();
        (void) FusionAltitudeKalmanSetSettings(&firmwareKalman, &settings);
    }
}
