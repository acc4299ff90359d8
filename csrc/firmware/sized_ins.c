/**
 * @file sized_ins.c
 * @brief An out-of-line copy of FusionAltitudeInsUpdate (fusion_altitude_ins.h)
 * for measuring its code size, stack and cycles on a Cortex-M4F. The header
 * compiles its functions with fp-contract off under gcc, so helpers it calls
 * may stay out of line; ins_cycles.py therefore prices every instruction
 * executed between the call and the return, wherever it lies.
 */

#include "fusion_altitude_ins.h"

FusionAltitudeInsStatus SizedFusionAltitudeInsUpdate(FusionAltitudeIns *const ins, const FusionAltitudeInsVector gyro,
                                                     const FusionAltitudeInsVector accel, const FusionAltitudeInsVector mag,
                                                     const float baroAltitude, const float dt);

FusionAltitudeInsStatus SizedFusionAltitudeInsUpdate(FusionAltitudeIns *const ins, const FusionAltitudeInsVector gyro,
                                                     const FusionAltitudeInsVector accel, const FusionAltitudeInsVector mag,
                                                     const float baroAltitude, const float dt) {
    return FusionAltitudeInsUpdate(ins, gyro, accel, mag, baroAltitude, dt);
}
