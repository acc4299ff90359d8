/**
 * @file fuzz_ins.c
 * @brief libFuzzer target for fusion_altitude_ins.h, built with clang under
 * AddressSanitizer + UndefinedBehaviorSanitizer: by csrc/firmware/Makefile
 * (FUZZERS, timed fuzz-run from the seeds in csrc/fuzz/corpus_ins/, written
 * by make_seeds_ins.py) and by tests/test_ins_c.py (a fixed number of inputs).
 *
 * The input is a sequence of calls; floats are raw bytes (any bit pattern):
 *   opcode & 3:
 *   0 initialise with the working settings
 *   1 edit the working settings: field index byte (mod 23: the first 23
 *     fields; baroTimeout and deadReckoningHorizon, added later, keep their
 *     defaults so that the findings decode as they were found), 4 raw bytes,
 *     then SetSettings
 *   2 update with every argument raw: gyro, accel, mag (3 floats each), baro, dt
 *   3 update with bytes scaled into a plausible range (sane): gyro, accel, mag,
 *     a baro presence byte, baro, dt
 *
 * Asserted after every call (abort, so libFuzzer reports a crash):
 *   - a rejected call leaves the INS bit-identical (memcmp, padding included),
 *     and the status equals an independent classification of the inputs;
 *   - SetSettings / InitialiseWith return what SettingsCheck returns;
 *   - P is exactly symmetric (bitwise), always;
 *   - while the run is sane (every accepted update had |gyro| <= 10 rad/s,
 *     |accel| <= 160 m/s^2 (16 g), |mag| <= 1e3, |baro| <= 1e5 m,
 *     1e-4 <= dt <= 10 s (step fuzzing: raw updates, opcode 2, draw any
 *     step; the seeds have 0.1 ms to 10 s and telemetry-like 0.1-4 s mixes)
 *     with |gyro| dt <= 0.2 rad on every integrated step (dt <= gapPeriod:
 *     the first-order attitude integration and the EKF's linearisation
 *     hold; a longer dt is a gap, not integrated),
 *     at most 20000 updates since initialisation, and the settings in use are
 *     plausible: noises in [1e-6, 10], random walks <= 1, sigmas <= 10,
 *     thresholds and windows <= 1e3): q, biases, d, v and P are finite, P's
 *     diagonal >= 0, |q| within 1e-3 of 1, and the bound: |v| <= 1e9 m/s,
 *     |d| <= 1e14 m (from the box: 20000 steps of at most 10 s, |accel| <=
 *     160 m/s^2, give |v| <= 3.2e7 m/s and |d| <= 0.5 * 160 * (2e5)^2 =
 *     3.2e12 m from the prediction; the baro is within 1e5 m).
 */

#include "fusion_altitude_ins.h"
#include "fuzz_common.h"
#include "tests/vectors/ins_settings_words.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FIELDS (23) /* the settings words an edit reaches (file comment); at most FUSION_ALTITUDE_INS_SETTINGS_WORDS */

typedef char fieldsWithinSettings[(FIELDS <= FUSION_ALTITUDE_INS_SETTINGS_WORDS) ? 1 : -1];

#define MAX_STEPS (20000)
#define MAX_VELOCITY (1e9f) /* m/s: the bound of a sane run (file comment) */
#define MAX_DISTANCE (1e14f) /* m */

static bool ReadVector(Reader *const reader, FusionAltitudeInsVector *const v) {
    return ReadFloat(reader, &v->x) && ReadFloat(reader, &v->y) && ReadFloat(reader, &v->z);
}

/* A byte pair scaled to [-limit, limit]. */
static bool ReadScaled(Reader *const reader, const float limit, float *const value) {
    uint16_t raw;
    if (!ReadBytes(reader, &raw, sizeof(raw))) {
        return false;
    }
    *value = ((float) raw / 32767.5f - 1.0f) * limit;
    return true;
}

static bool Bounded(const float value, const float limit) {
    return InRange(value, -limit, limit);
}

static bool BoundedVector(const FusionAltitudeInsVector v, const float limit) {
    return Bounded(v.x, limit) && Bounded(v.y, limit) && Bounded(v.z, limit);
}

static bool SaneSettings(const FusionAltitudeInsSettings *const s) {
    return InRange(s->gyroNoise, 1e-6f, 10.0f) && InRange(s->gyroBiasRandomWalk, 0.0f, 1.0f) && InRange(s->accelNoise, 1e-6f, 10.0f) &&
           InRange(s->accelAttitudeNoise, 1e-3f, 10.0f) && InRange(s->baroNoise, 1e-2f, 100.0f) && InRange(s->zeroRateNoise, 1e-4f, 10.0f) &&
           InRange(s->zeroVelocityNoise, 1e-3f, 10.0f) && InRange(s->initialAttitudeSigma, 0.0f, 10.0f) &&
           InRange(s->initialGyroBiasSigma, 0.0f, 10.0f) && InRange(s->initialVelocitySigma, 0.0f, 10.0f) &&
           InRange(s->accelNormRejection, 0.0f, 1e3f) && InRange(s->accelRejection, 0.0f, 1e3f) && InRange(s->recoveryTriggerPeriod, 0.0f, 1e3f) &&
           InRange(s->stationaryGyroThreshold, 0.0f, 1e3f) && InRange(s->stationaryAccelThreshold, 0.0f, 1e3f) &&
           InRange(s->stationaryWindow, 0.0f, 1e3f) && InRange(s->baroBiasTimeConstant, 1e-3f, 1e3f) &&
           InRange(s->accelBiasTimeConstant, 1e-3f, 1e3f) && InRange(s->magTimeConstant, 1e-3f, 1e3f) && InRange(s->gapPeriod, 1e-3f, 1e3f) &&
           InRange(s->stationaryBaroRate, 0.0f, 1e3f) && InRange(s->baroGate, 1e-3f, 1e6f) && InRange(s->baroRejectionTimeout, 0.0f, 1e3f) &&
           InRange(s->baroTimeout, 1e-3f, 1e3f) && InRange(s->deadReckoningHorizon, 1e-3f, 1e3f);
}

/* A plausible step (s): 0.1 ms to 10 s, and |gyro| dt <= 0.2 rad on a step that is integrated (dt <= gapPeriod). */
static bool SaneStep(const FusionAltitudeInsVector gyro, const float dt, const float gapPeriod) {
    const float limit = (dt > gapPeriod) ? 10.0f : (0.2f / dt);
    return InRange(dt, 1e-4f, 10.0f) && BoundedVector(gyro, (limit < 10.0f) ? limit : 10.0f);
}

static FusionAltitudeInsStatus Expected(const FusionAltitudeInsVector gyro, const FusionAltitudeInsVector accel, const FusionAltitudeInsVector mag,
                                        const float baro, const float dt) {
    if (!BoundedVector(gyro, 1e6f)) {
        return FusionAltitudeInsStatusInvalidGyro;
    }
    if (!BoundedVector(accel, 1e6f)) {
        return FusionAltitudeInsStatusInvalidAccel;
    }
    const bool noMag = FusionAltitudeIsNaN(mag.x) && FusionAltitudeIsNaN(mag.y) && FusionAltitudeIsNaN(mag.z);
    if (!noMag && !BoundedVector(mag, 1e6f)) {
        return FusionAltitudeInsStatusInvalidMag;
    }
    if (!FusionAltitudeIsNaN(baro) && !Bounded(baro, 1e6f)) {
        return FusionAltitudeInsStatusInvalidBaroAltitude;
    }
    if (!FusionAltitudeIsFinite(dt) || !(dt > 0.0f)) {
        return FusionAltitudeInsStatusInvalidDt;
    }
    return FusionAltitudeInsStatusOk;
}

static void CheckState(const FusionAltitudeIns *const ins, const bool sane) {
    for (int i = 0; i < FUSION_ALTITUDE_INS_STATES; i++) {
        for (int j = 0; j < FUSION_ALTITUDE_INS_STATES; j++) {
            CHECK(memcmp(&ins->P[i][j], &ins->P[j][i], sizeof(float)) == 0);
        }
    }
    if (!sane) {
        return;
    }
    for (int i = 0; i < FUSION_ALTITUDE_INS_STATES; i++) {
        for (int j = 0; j < FUSION_ALTITUDE_INS_STATES; j++) {
            CHECK(FusionAltitudeIsFinite(ins->P[i][j]));
        }
        CHECK(ins->P[i][i] >= 0.0f);
    }
    const float norm = ins->q[0] * ins->q[0] + ins->q[1] * ins->q[1] + ins->q[2] * ins->q[2] + ins->q[3] * ins->q[3];
    CHECK(norm > 0.998f && norm < 1.002f);
    CHECK(Bounded(ins->distance, MAX_DISTANCE) && Bounded(ins->velocity, MAX_VELOCITY));
    CHECK(FusionAltitudeIsFinite(ins->gyroBias[0]) && FusionAltitudeIsFinite(ins->gyroBias[1]) && FusionAltitudeIsFinite(ins->gyroBias[2]));
    CHECK(FusionAltitudeIsFinite(ins->accelZBias) && FusionAltitudeIsFinite(ins->baroBias));
}

/* The arguments of an update: opcode & 3 == 2, all raw (gyro, accel, mag vectors, baro, dt); else scaled into
 * plausible ranges (gyro 10 rad/s, accel 160 m/s^2, mag 1e3, a presence byte: bit 0 baro (1e5 m), bit 1 mag;
 * dt in [1e-3, 0.02] s). False when the input ends. */
static bool ReadUpdate(Reader *const reader, const uint8_t opcode, FusionAltitudeInsVector *const gyro, FusionAltitudeInsVector *const accel,
                       FusionAltitudeInsVector *const mag, float *const baro, float *const dt) {
    if ((opcode & 3) == 2) {
        return ReadVector(reader, gyro) && ReadVector(reader, accel) && ReadVector(reader, mag) && ReadFloat(reader, baro) &&
               ReadFloat(reader, dt);
    }
    uint8_t presence;
    if (!ReadScaled(reader, 10.0f, &gyro->x) || !ReadScaled(reader, 10.0f, &gyro->y) || !ReadScaled(reader, 10.0f, &gyro->z) ||
        !ReadScaled(reader, 160.0f, &accel->x) || !ReadScaled(reader, 160.0f, &accel->y) || !ReadScaled(reader, 160.0f, &accel->z) ||
        !ReadScaled(reader, 1e3f, &mag->x) || !ReadScaled(reader, 1e3f, &mag->y) || !ReadScaled(reader, 1e3f, &mag->z) ||
        !ReadBytes(reader, &presence, 1) || !ReadScaled(reader, 1e5f, baro) || !ReadScaled(reader, 0.01f, dt)) {
        return false;
    }
    *dt = 0.0105f + *dt; /* [5e-4, 0.0205] */
    *dt = *dt < 1e-3f ? 1e-3f : (*dt > 0.02f ? 0.02f : *dt);
    if (!(presence & 1)) {
        *baro = FusionAltitudeNaN();
    }
    if (!(presence & 2)) {
        *mag = FusionAltitudeInsNoMag();
    }
    return true;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    Reader reader = {data, size};
    FusionAltitudeIns ins;
    FusionAltitudeInsInitialise(&ins);
    FusionAltitudeInsSettings working = FusionAltitudeInsSettingsDefault();
    bool sane = true;
    int steps = 0;
    uint8_t opcode;
    while (ReadBytes(&reader, &opcode, 1)) {
        const FusionAltitudeIns before = ins;
        switch (opcode & 3) {
            case 0: {
                const FusionAltitudeInsStatus status = FusionAltitudeInsInitialiseWith(&ins, &working);
                CHECK(status == FusionAltitudeInsSettingsCheck(&working));
                if (status == FusionAltitudeInsStatusOk) {
                    sane = SaneSettings(&working);
                    steps = 0;
                } else {
                    CHECK(memcmp(&ins, &before, sizeof(ins)) == 0);
                }
                break;
            }
            case 1: {
                uint8_t field;
                float value;
                if (!ReadBytes(&reader, &field, 1) || !ReadFloat(&reader, &value)) {
                    return 0;
                }
                uint32_t bits;
                memcpy(&bits, &value, sizeof(bits));
                FusionAltitudeInsSettingsSetWord(&working, field % FIELDS, bits);
                const FusionAltitudeInsStatus status = FusionAltitudeInsSetSettings(&ins, &working);
                CHECK(status == FusionAltitudeInsSettingsCheck(&working));
                if (status == FusionAltitudeInsStatusOk) {
                    sane = sane && SaneSettings(&working);
                } else {
                    CHECK(memcmp(&ins, &before, sizeof(ins)) == 0);
                }
                break;
            }
            default: {
                FusionAltitudeInsVector gyro, accel, mag;
                float baro, dt;
                if (!ReadUpdate(&reader, opcode, &gyro, &accel, &mag, &baro, &dt)) {
                    return 0;
                }
                const FusionAltitudeInsStatus status = FusionAltitudeInsUpdate(&ins, gyro, accel, mag, baro, dt);
                CHECK(status == Expected(gyro, accel, mag, baro, dt));
                if (status != FusionAltitudeInsStatusOk) {
                    CHECK(memcmp(&ins, &before, sizeof(ins)) == 0);
                } else {
                    const bool noMag = FusionAltitudeIsNaN(mag.x) && FusionAltitudeIsNaN(mag.y) && FusionAltitudeIsNaN(mag.z);
                    sane = sane && BoundedVector(gyro, 10.0f) && BoundedVector(accel, 160.0f) && (noMag || BoundedVector(mag, 1e3f)) &&
                           (FusionAltitudeIsNaN(baro) || Bounded(baro, 1e5f)) && SaneStep(gyro, dt, ins.settings.gapPeriod) &&
                           (++steps <= MAX_STEPS);
                }
                break;
            }
        }
        CheckState(&ins, sane);
    }
    return 0;
}
