/**
 * @file main.c
 * @brief Integration example: fusion_altitude.h in a 100 Hz firmware loop
 * with a 25 Hz barometer.
 *
 *  1. Tune: the VTOL preset, validated at the loop period.
 *  2. Calibrate on the ground for 2 s (stationary: the mean vertical
 *     acceleration is the accelerometer bias, the mean baro the reference)
 *     and warm-start with FusionAltitudeResetWithBias, so the bias estimate
 *     does not have to converge in flight.
 *  3. Each tick: update with the baro sample when one arrived, with
 *     FUSION_ALTITUDE_NO_BARO on the three ticks in between.
 *  4. Watch the baro residual (z - h before the correction, NaN on ticks
 *     without baro): a residual beyond 8 m on 5 baro samples in a row (0.2 s)
 *     flags a baro fault. The faulty samples have already pulled the estimate
 *     (and the bias) towards them, so the estimator is rolled back to a copy
 *     taken at the last trusted baro sample, the accelerations since then are
 *     replayed without baro, and from then on the baro is ignored and the
 *     estimate coasts on the bias-corrected accelerometer.
 *
 * Built for Cortex-M4F and run on QEMU by csrc/firmware/Makefile (target
 * example-run) with the simulated board of sensors_sim.c. Output goes through
 * printf (semihosting on QEMU); values are printed as integers in cm, so no
 * double is involved.
 */

#include "fusion_altitude.h"
#include "sensors.h"

#include <inttypes.h>
#include <stdint.h>
#include <stdio.h>

#define DT (1.0f / (float) SENSORS_RATE)        /* s */
#define CALIBRATION_TICKS (2 * SENSORS_RATE)    /* 2 s on the ground */
#define RESIDUAL_LIMIT (8.0f)                   /* m */
#define RESIDUAL_SAMPLES (5)                    /* consecutive baro samples beyond the limit */
#define LOG_PERIOD_MS (5000u)                   /* ms */
#define TICKS_PER_BARO (SENSORS_RATE / SENSORS_BARO_RATE)
#define HISTORY_LENGTH ((RESIDUAL_SAMPLES + 1) * TICKS_PER_BARO)

/* value * 100, rounded toward zero: m to cm, m/s to cm/s. */
static int32_t Centi(const float value) {
    return (int32_t) (value * 100.0f);
}

int main(void) {
    /* 1. Tuning */
    FusionAltitude altitude;
    FusionAltitudeInitialise(&altitude);
    FusionAltitudeSettings settings;
    FusionAltitudeStatus status = FusionAltitudeSettingsFromPreset(&settings, FusionAltitudePresetVtol);
    if (status == FusionAltitudeStatusOk) {
        status = FusionAltitudeSettingsValidate(&settings, DT);
    }
    if (status == FusionAltitudeStatusOk) {
        status = FusionAltitudeSetSettings(&altitude, &settings);
    }
    if (status != FusionAltitudeStatusOk) {
        printf("tuning rejected: %s\n", FusionAltitudeStatusMessage(status));
        return 1;
    }

    /* 2. Ground calibration and warm start */
    float accelSum = 0.0f; /* m/s^2 */
    float baroSum = 0.0f;  /* m */
    uint32_t baroCount = 0;
    for (uint32_t tick = 0; tick < CALIBRATION_TICKS; tick++) {
        (void) SensorsWaitForTick();
        accelSum += SensorsReadAccel();
        float baro;
        if (SensorsReadBaro(&baro)) {
            baroSum += baro;
            baroCount++;
        }
    }
    const float groundAccelBias = accelSum / (float) CALIBRATION_TICKS; /* m/s^2 */
    const float groundAltitude = (baroCount > 0u) ? (baroSum / (float) baroCount) : FUSION_ALTITUDE_NO_BARO; /* m */
    status = FusionAltitudeResetWithBias(&altitude, groundAltitude, groundAccelBias);
    if (status != FusionAltitudeStatusOk) {
        printf("ground calibration rejected: %s\n", FusionAltitudeStatusMessage(status));
        return 1;
    }
    printf("calibrated: ground %" PRId32 " cm, accel bias %" PRId32 " cm/s^2\n", Centi(groundAltitude), Centi(groundAccelBias));

    /* 3. Flight loop and 4. residual monitor */
    uint32_t suspicious = 0;
    bool baroFault = false;
    uint32_t rejected = 0;
    FusionAltitude trusted = altitude;   /* copy at the last trusted baro sample */
    float history[HISTORY_LENGTH];       /* m/s^2, accelerations since that copy */
    uint32_t historyLength = 0;
    while (SensorsWaitForTick()) {
        const float accel = SensorsReadAccel();
        if (historyLength < HISTORY_LENGTH) {
            history[historyLength++] = accel;
        }
        float baro = FUSION_ALTITUDE_NO_BARO;
        float sample;
        if (SensorsReadBaro(&sample) && !baroFault) {
            baro = sample;
        }
        status = FusionAltitudeUpdate(&altitude, accel, baro, DT);
        if (status != FusionAltitudeStatusOk) { /* state unchanged: skip this sample */
            rejected++;
            continue;
        }
        const float residual = FusionAltitudeGetBaroResidual(&altitude); /* m, NaN without baro */
        if (!FusionAltitudeIsNaN(residual)) {
            suspicious = ((residual > RESIDUAL_LIMIT) || (residual < -RESIDUAL_LIMIT)) ? (suspicious + 1u) : 0u;
            if (suspicious == 0u) {
                trusted = altitude;
                historyLength = 0;
            } else if (suspicious >= RESIDUAL_SAMPLES) {
                baroFault = true;
                printf("baro fault at %" PRIu32 " ms: residual %" PRId32 " cm, baro ignored from now on\n", SensorsTimeMs(),
                       Centi(residual));
                altitude = trusted;
                for (uint32_t index = 0; index < historyLength; index++) {
                    (void) FusionAltitudeUpdate(&altitude, history[index], FUSION_ALTITUDE_NO_BARO, DT);
                }
            }
        }
        if ((SensorsTimeMs() % LOG_PERIOD_MS) == 0u) {
            printf("t %" PRIu32 " ms: height %" PRId32 " cm, climb %" PRId32 " cm/s, accel bias %" PRId32 " cm/s^2%s\n",
                   SensorsTimeMs(), Centi(FusionAltitudeGetAltitude(&altitude) - groundAltitude),
                   Centi(FusionAltitudeGetVerticalVelocity(&altitude)), Centi(FusionAltitudeGetAccelBias(&altitude)),
                   baroFault ? " (baro fault)" : "");
        }
    }
    printf("done: %" PRIu32 " rejected updates, baro fault %s\n", rejected, baroFault ? "detected" : "not detected");
    return 0;
}
