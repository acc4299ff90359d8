/**
 * @file cycles_kalman.c
 * @brief Calls SizedFusionAltitudeKalmanUpdate (sized_kalman.c) once on each
 * path, on bare-metal Cortex-M4F under QEMU with every executed instruction
 * logged (-singlestep -d exec,nochain), as cycles_observer.c does for the observer.
 * size_table.py prices each executed instruction with the Cortex-M4 cycle
 * counts. The traced calls, in order (after a warm-up through the inline
 * function, which is not traced):
 *   1. baro, rangefinder and GPS samples, all fused
 *   2. baro sample only, fused (the common 25 Hz tick)
 *   3. no sample (prediction only)
 *   4. worst case: rangefinder terrain reset (ground moved) with baro and GPS fused
 *   5. rejected: accel not finite
 * Exits non-zero if a call does not take its path.
 */

#include "fusion_altitude_kalman.h"

#include <stdint.h>
#include <string.h>

FusionAltitudeKalmanStatus SizedFusionAltitudeKalmanUpdate(FusionAltitudeKalman *const kalman, const float accel, const float dt,
                                                           const FusionAltitudeKalmanMeasurements *const measurements);

static float Infinity(void) {
    const uint32_t bits = 0x7F800000u;
    float value;
    memcpy(&value, &bits, sizeof(value));
    return value;
}

static FusionAltitudeKalmanMeasurements Samples(const bool baro, const float range, const bool gps) {
    FusionAltitudeKalmanMeasurements m = FusionAltitudeKalmanMeasurementsNone();
    if (baro) {
        m.baroAltitude = 120.0f;
    }
    m.rangeDistance = range;
    if (gps) {
        m.gpsAltitude = 160.0f;
        m.gpsSatellites = 9;
    }
    return m;
}

static int Result(const FusionAltitudeKalman *const kalman, const FusionAltitudeKalmanSensorIndex sensor) {
    return (int) kalman->sensors[sensor].result;
}

int main(void) {
    static FusionAltitudeKalman kalman;
    FusionAltitudeKalmanSettings settings = FusionAltitudeKalmanSettingsDefault();
    settings.rejectionTimeout = 0.0f; /* a terrain reset on the second rejected range sample */
    if (FusionAltitudeKalmanInitialiseWith(&kalman, &settings) != FusionAltitudeKalmanStatusOk) {
        return 1;
    }
    const float nan = FusionAltitudeNaN();
    FusionAltitudeKalmanMeasurements m = Samples(true, 1.0f, true);
    for (int i = 0; i < 10; i++) {
        (void) FusionAltitudeKalmanUpdate(&kalman, 0.0f, 0.01f, &m);
    }
    int failures = 0;
    failures += (SizedFusionAltitudeKalmanUpdate(&kalman, 0.0f, 0.01f, &m) != FusionAltitudeKalmanStatusOk) ? 1 : 0;
    failures += (Result(&kalman, FusionAltitudeKalmanSensorBaro) == FusionAltitudeKalmanResultFused) ? 0 : 1;
    failures += (Result(&kalman, FusionAltitudeKalmanSensorRange) == FusionAltitudeKalmanResultFused) ? 0 : 1;
    failures += (Result(&kalman, FusionAltitudeKalmanSensorGps) == FusionAltitudeKalmanResultFused) ? 0 : 1;
    m = Samples(true, nan, false);
    failures += (SizedFusionAltitudeKalmanUpdate(&kalman, 0.0f, 0.01f, &m) != FusionAltitudeKalmanStatusOk) ? 1 : 0;
    failures += (Result(&kalman, FusionAltitudeKalmanSensorBaro) == FusionAltitudeKalmanResultFused) ? 0 : 1;
    m = Samples(false, nan, false);
    failures += (SizedFusionAltitudeKalmanUpdate(&kalman, 0.0f, 0.01f, &m) != FusionAltitudeKalmanStatusOk) ? 1 : 0;
    failures += (Result(&kalman, FusionAltitudeKalmanSensorBaro) == FusionAltitudeKalmanResultNoSample) ? 0 : 1;
    m = Samples(false, 3.0f, false); /* the ground dropped by 2 m: rejected, the streak starts */
    (void) FusionAltitudeKalmanUpdate(&kalman, 0.0f, 0.01f, &m);
    failures += (Result(&kalman, FusionAltitudeKalmanSensorRange) == FusionAltitudeKalmanResultRejected) ? 0 : 1;
    m = Samples(true, 3.0f, true);
    failures += (SizedFusionAltitudeKalmanUpdate(&kalman, 0.0f, 0.01f, &m) != FusionAltitudeKalmanStatusOk) ? 1 : 0;
    failures += (Result(&kalman, FusionAltitudeKalmanSensorRange) == FusionAltitudeKalmanResultReset) ? 0 : 1;
    failures += (Result(&kalman, FusionAltitudeKalmanSensorBaro) == FusionAltitudeKalmanResultFused) ? 0 : 1;
    failures += (Result(&kalman, FusionAltitudeKalmanSensorGps) == FusionAltitudeKalmanResultFused) ? 0 : 1;
    failures += (SizedFusionAltitudeKalmanUpdate(&kalman, Infinity(), 0.01f, &m) != FusionAltitudeKalmanStatusInvalidAccel) ? 1 : 0;
    return failures;
}
