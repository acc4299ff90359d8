/**
 * @file cycles_alphabeta.c
 * @brief Calls SizedFusionAltitudeAlphaBetaUpdate (sized_alphabeta.c) once on
 * each path, on bare-metal Cortex-M4F under QEMU with every executed
 * instruction logged, as cycles_observer.c does for the observer. The traced calls,
 * after a warm-up through the inline function (not traced):
 *   1. IMU and all four sensors sampled, every filter updated and weighted
 *   2. IMU and baro only (the common 25 Hz tick)
 *   3. IMU only (every other filter predicts)
 *   4. rejected: accel infinite
 * Exits non-zero if a call does not take its path.
 */

#include "fusion_altitude_alphabeta.h"

FusionAltitudeAlphaBetaStatus SizedFusionAltitudeAlphaBetaUpdate(FusionAltitudeAlphaBeta *const fusion, const float accel, const float dt,
                                                                 const FusionAltitudeAlphaBetaMeasurements *const m);

static FusionAltitudeAlphaBetaMeasurements Samples(const bool baro, const bool others) {
    FusionAltitudeAlphaBetaMeasurements m = FusionAltitudeAlphaBetaMeasurementsNone();
    if (baro) {
        m.baroAltitude = 2.1f;
    }
    if (others) {
        m.lidarAltitude = 2.0f;
        m.sonarAltitude = 2.05f;
        m.gpsAltitude = 1.5f;
    }
    return m;
}

static int Weighted(const FusionAltitudeAlphaBeta *const fusion) {
    int weighted = 0;
    for (int i = 0; i < FUSION_ALTITUDE_ALPHABETA_SENSORS; i++) {
        weighted += (FusionAltitudeAlphaBetaGetWeight(fusion, (FusionAltitudeAlphaBetaSensorIndex) i) > 0.0f) ? 1 : 0;
    }
    return weighted;
}

int main(void) {
    static FusionAltitudeAlphaBeta fusion;
    FusionAltitudeAlphaBetaInitialise(&fusion);
    FusionAltitudeAlphaBetaMeasurements m = Samples(true, true);
    for (int i = 0; i < 10; i++) {
        (void) FusionAltitudeAlphaBetaUpdate(&fusion, 0.0f, 0.01f, &m);
    }
    int failures = (FusionAltitudeAlphaBetaIsStarted(&fusion) && (Weighted(&fusion) == 5)) ? 0 : 1;
    failures += (SizedFusionAltitudeAlphaBetaUpdate(&fusion, 0.0f, 0.01f, &m) != FusionAltitudeAlphaBetaStatusOk) ? 1 : 0;
    failures += (Weighted(&fusion) == 5) ? 0 : 1;
    m = Samples(true, false);
    failures += (SizedFusionAltitudeAlphaBetaUpdate(&fusion, 0.0f, 0.01f, &m) != FusionAltitudeAlphaBetaStatusOk) ? 1 : 0;
    m = Samples(false, false);
    failures += (SizedFusionAltitudeAlphaBetaUpdate(&fusion, 0.0f, 0.01f, &m) != FusionAltitudeAlphaBetaStatusOk) ? 1 : 0;
    failures += (Weighted(&fusion) == 5) ? 0 : 1;
    failures += (SizedFusionAltitudeAlphaBetaUpdate(&fusion, FusionAltitudeAlphaBetaInfinity(), 0.01f, &m) != FusionAltitudeAlphaBetaStatusInvalidAccel) ? 1 : 0;
    return failures;
}
