/**
 * @file cycles_complementary.c
 * @brief Calls SizedFusionAltitudeComplementaryUpdate (sized_complementary.c)
 * once on each path, on bare-metal Cortex-M4F under QEMU with every executed
 * instruction logged, as cycles_observer.c does for the observer. The traced calls:
 *   1. baro sample, time-constant blend (the default: two divisions more)
 *   2. baro sample, per-sample coefficients
 *   3. no baro sample (prediction only)
 *   4. rejected: accel not finite
 * Exits non-zero if a call does not take its path.
 */

#include "fusion_altitude_complementary.h"

#include <stdint.h>
#include <string.h>

FusionAltitudeComplementaryStatus SizedFusionAltitudeComplementaryUpdate(FusionAltitudeComplementary *const filter, const float accel,
                                                                         const float baroAltitude, const float dt);

static float Infinity(void) {
    const uint32_t bits = 0x7F800000u;
    float value;
    memcpy(&value, &bits, sizeof(value));
    return value;
}

int main(void) {
    static FusionAltitudeComplementary filter;
    FusionAltitudeComplementaryInitialise(&filter);
    if (FusionAltitudeComplementaryReset(&filter, 100.0f) != FusionAltitudeComplementaryStatusOk) {
        return 1;
    }
    int failures = 0;
    failures += (SizedFusionAltitudeComplementaryUpdate(&filter, 0.2f, 100.5f, 0.01f) != FusionAltitudeComplementaryStatusOk) ? 1 : 0;
    FusionAltitudeComplementarySettings settings = FusionAltitudeComplementarySettingsDefault();
    settings.perSampleCoefficients = true;
    failures += (FusionAltitudeComplementarySetSettings(&filter, &settings) != FusionAltitudeComplementaryStatusOk) ? 1 : 0;
    failures += (SizedFusionAltitudeComplementaryUpdate(&filter, 0.2f, 100.5f, 0.01f) != FusionAltitudeComplementaryStatusOk) ? 1 : 0;
    failures += (SizedFusionAltitudeComplementaryUpdate(&filter, 0.2f, FusionAltitudeNaN(), 0.01f) != FusionAltitudeComplementaryStatusOk) ? 1 : 0;
    failures += FusionAltitudeIsNaN(FusionAltitudeComplementaryGetBaroVelocity(&filter)) ? 0 : 1;
    failures += (SizedFusionAltitudeComplementaryUpdate(&filter, Infinity(), 100.5f, 0.01f) != FusionAltitudeComplementaryStatusInvalidAccel) ? 1 : 0;
    return failures;
}
