/**
 * @file cycles_ins.c
 * @brief Calls SizedFusionAltitudeInsUpdate (sized_ins.c) once on each path,
 * on bare-metal Cortex-M4F under QEMU with every executed instruction logged
 * (-singlestep -d exec,nochain), as cycles_observer.c does for the observer;
 * size_table.py (and ins_cycles.py) price each executed instruction with the
 * Cortex-M4 cycle counts (the Makefile builds it with -fno-math-errno, so
 * sqrtf is one vsqrt.f32 inside the wrapper). Traced calls (the names are
 * INS_CALLS of size_table.py):
 *   1. predict + accel correction (no baro, no mag): the common IMU step
 *   2. predict + accel + baro
 *   3. predict + accel + magnetometer
 *   4. stationary: predict + accel + zero-rate + zero-velocity + baro-bias learning
 *   5. predict only: accel rejected by its norm (no correction at all)
 *   6. rejected: gyro not finite
 * Exits non-zero if a call does not take its path.
 */

#include "fusion_altitude_ins.h"

FusionAltitudeInsStatus SizedFusionAltitudeInsUpdate(FusionAltitudeIns *const ins, const FusionAltitudeInsVector gyro,
                                                     const FusionAltitudeInsVector accel, const FusionAltitudeInsVector mag,
                                                     const float baroAltitude, const float dt);

static FusionAltitudeInsVector Vector(const float x, const float y, const float z) {
    FusionAltitudeInsVector v;
    v.x = x;
    v.y = y;
    v.z = z;
    return v;
}

int main(void) {
    static FusionAltitudeIns ins;
    FusionAltitudeInsInitialise(&ins);
    const FusionAltitudeInsVector none = FusionAltitudeInsNoMag();
    const FusionAltitudeInsVector moving = Vector(0.3f, -0.2f, 0.1f);
    const FusionAltitudeInsVector accel = Vector(0.2f, -0.1f, 9.9f);
    for (int i = 0; i < 20; i++) { /* warm-up in motion, inline calls (not traced) */
        (void) FusionAltitudeInsUpdate(&ins, moving, accel, Vector(0.4f, 0.0f, -0.3f), 100.0f, 0.002f);
    }
    int bad = 0;
    bad += SizedFusionAltitudeInsUpdate(&ins, moving, accel, none, FUSION_ALTITUDE_NO_BARO, 0.002f) != FusionAltitudeInsStatusOk;
    bad += SizedFusionAltitudeInsUpdate(&ins, moving, accel, none, 100.1f, 0.002f) != FusionAltitudeInsStatusOk;
    bad += SizedFusionAltitudeInsUpdate(&ins, moving, accel, Vector(0.4f, 0.0f, -0.3f), FUSION_ALTITUDE_NO_BARO, 0.002f) !=
           FusionAltitudeInsStatusOk;
    bad += ins.accelRejected ? 1 : 0;
    for (int i = 0; i < 600; i++) { /* come to rest (inline calls) */
        (void) FusionAltitudeInsUpdate(&ins, Vector(0.001f, 0.0f, 0.0f), Vector(0.0f, 0.0f, 9.8f), none, 100.0f, 0.002f);
    }
    bad += SizedFusionAltitudeInsUpdate(&ins, Vector(0.001f, 0.0f, 0.0f), Vector(0.0f, 0.0f, 9.8f), none, 100.0f, 0.002f) !=
           FusionAltitudeInsStatusOk;
    bad += ins.stationary ? 0 : 1;
    bad += SizedFusionAltitudeInsUpdate(&ins, moving, Vector(0.2f, -0.1f, 14.0f), none, FUSION_ALTITUDE_NO_BARO, 0.002f) !=
           FusionAltitudeInsStatusOk;
    bad += ins.accelRejected ? 0 : 1;
    bad += SizedFusionAltitudeInsUpdate(&ins, Vector(FusionAltitudeNaN(), 0.0f, 0.0f), accel, none, 100.0f, 0.002f) !=
           FusionAltitudeInsStatusInvalidGyro;
    return bad;
}
