/**
 * @file cycles_observer.c
 * @brief Calls SizedFusionAltitudeUpdate (sized_observer.c) once on each path, on
 * bare-metal Cortex-M4F under QEMU with every executed instruction logged
 * (-singlestep -d exec,nochain). size_table.py walks the log and prices each
 * executed instruction with the Cortex-M4 cycle counts to estimate the cycles
 * of one update. The calls, in order:
 *   1. baro sample, reference set (the full correction)
 *   2. no baro sample (FUSION_ALTITUDE_NO_BARO), reference set (integration only)
 *   3. rejected: accel not finite
 */

#include "fusion_altitude.h"

#include <stdint.h>
#include <string.h>

FusionAltitudeStatus SizedFusionAltitudeUpdate(FusionAltitude *const altitude, const float accel, const float baroAltitude, const float dt);

static float Infinity(void) {
    const uint32_t bits = 0x7F800000u;
    float value;
    memcpy(&value, &bits, sizeof(value));
    return value;
}

int main(void) {
    static FusionAltitude altitude;
    FusionAltitudeInitialise(&altitude);
    if (FusionAltitudeResetWithBias(&altitude, 100.0f, 0.1f) != FusionAltitudeStatusOk) {
        return 1;
    }
    int failures = 0;
    failures += (SizedFusionAltitudeUpdate(&altitude, 0.2f, 100.5f, 0.01f) != FusionAltitudeStatusOk) ? 1 : 0;
    failures += (SizedFusionAltitudeUpdate(&altitude, 0.2f, FUSION_ALTITUDE_NO_BARO, 0.01f) != FusionAltitudeStatusOk) ? 1 : 0;
    failures += (SizedFusionAltitudeUpdate(&altitude, Infinity(), 100.5f, 0.01f) != FusionAltitudeStatusInvalidAccel) ? 1 : 0;
    return failures;
}
