/**
 * @file cycles_rocket.c
 * @brief Calls SizedFusionAltitudeRocketUpdate (sized_rocket.c) once on each
 * path, on bare-metal Cortex-M4F under QEMU with every executed instruction
 * logged, as cycles.c does for the observer. The traced calls, after a
 * warm-up through the inline functions (not traced):
 *   1. pad, baro sample, a calibration window completes (the longest pad step)
 *   2. coast below the lockout speed, baro fused (the common flight step)
 *   3. coast above the lockout speed, baro locked out
 *   4. descent, baro fused, accel ignored
 *   5. rejected: accel infinite
 * Exits non-zero if a call does not take its path.
 */

#include "fusion_altitude_rocket.h"

#include <string.h>

FusionAltitudeRocketStatus SizedFusionAltitudeRocketUpdate(FusionAltitudeRocket *const rocket, const float accel,
                                                          const float baroAltitude, const float dt);

static float Infinity(void) {
    const uint32_t bits = 0x7F800000u;
    float value;
    memcpy(&value, &bits, sizeof(value));
    return value;
}

int main(void) {
    static FusionAltitudeRocket rocket;
    static FusionAltitudeRocket fast;
    (void) FusionAltitudeRocketInitialise(&rocket, NULL);
    int failures = 0;
    int step = 0;
    for (; step < 49; step++) { /* one sample short of the first window */
        (void) FusionAltitudeRocketUpdate(&rocket, 0.1f, 1400.0f, 0.01f);
    }
    failures += (FusionAltitudeRocketIsCalibrated(&rocket)) ? 1 : 0;
    for (; !FusionAltitudeRocketIsCalibrated(&rocket) && (step < 60); step++) {
        if (FusionAltitudeRocketIsCalibrated(&rocket)) {
            break;
        }
        FusionAltitudeRocket probe = rocket;
        (void) FusionAltitudeRocketUpdate(&probe, 0.1f, 1400.0f, 0.01f);
        if (FusionAltitudeRocketIsCalibrated(&probe)) { /* the next step completes the window: trace it */
            failures += (SizedFusionAltitudeRocketUpdate(&rocket, 0.1f, 1400.0f, 0.01f) != FusionAltitudeRocketStatusOk) ? 1 : 0;
            break;
        }
        rocket = probe;
    }
    failures += FusionAltitudeRocketIsCalibrated(&rocket) ? 0 : 1;
    /* boost 1.6 s at 60 m/s^2 (96 m/s), then coast */
    for (int i = 0; i < 160; i++) {
        (void) FusionAltitudeRocketUpdate(&rocket, 60.1f, 1400.0f + 0.3f * (float) i, 0.01f);
    }
    for (int i = 0; i < 20; i++) {
        (void) FusionAltitudeRocketUpdate(&rocket, -9.7f, 1480.0f + 0.9f * (float) i, 0.01f);
    }
    fast = rocket;
    failures += (FusionAltitudeRocketGetPhase(&rocket) == FusionAltitudeRocketPhaseCoast) ? 0 : 1;
    failures += (SizedFusionAltitudeRocketUpdate(&rocket, -9.7f, 1498.0f, 0.01f) != FusionAltitudeRocketStatusOk) ? 1 : 0;
    failures += (FusionAltitudeRocketGetBaro(&rocket) == FusionAltitudeRocketBaroFused) ? 0 : 1;
    for (int i = 0; i < 100; i++) { /* push the other copy above the lockout */
        (void) FusionAltitudeRocketUpdate(&fast, 30.1f, FUSION_ALTITUDE_NO_BARO, 0.01f);
    }
    fast.phase = FusionAltitudeRocketPhaseCoast;
    failures += (SizedFusionAltitudeRocketUpdate(&fast, -9.7f, 1500.0f, 0.01f) != FusionAltitudeRocketStatusOk) ? 1 : 0;
    failures += (FusionAltitudeRocketGetBaro(&fast) == FusionAltitudeRocketBaroLockedOut) ? 0 : 1;
    for (int i = 0; i < 3000 && FusionAltitudeRocketGetPhase(&rocket) == FusionAltitudeRocketPhaseCoast; i++) {
        const float t = 0.01f * (float) i;
        (void) FusionAltitudeRocketUpdate(&rocket, -9.7f, 1498.0f + 80.0f * t - 4.9f * t * t, 0.01f);
    }
    failures += (FusionAltitudeRocketGetPhase(&rocket) == FusionAltitudeRocketPhaseDrogue) ? 0 : 1;
    const float height = FusionAltitudeRocketGetHeight(&rocket);
    failures += (SizedFusionAltitudeRocketUpdate(&rocket, 3.0f, 1400.0f + height - 0.2f, 0.01f) != FusionAltitudeRocketStatusOk) ? 1 : 0;
    failures += (FusionAltitudeRocketGetBaro(&rocket) == FusionAltitudeRocketBaroFused) ? 0 : 1;
    failures += (SizedFusionAltitudeRocketUpdate(&rocket, Infinity(), 1400.0f, 0.01f) != FusionAltitudeRocketStatusInvalidAccel) ? 1 : 0;
    return failures;
}
