/**
 * @file fuzz_kalman.c
 * @brief libFuzzer target for fusion_altitude_kalman.h, built with clang
 * under AddressSanitizer + UndefinedBehaviorSanitizer (csrc/firmware/Makefile,
 * target fuzz-run).
 *
 * The input is a loop period followed by a sequence of calls; floats are raw
 * bytes (any bit pattern: NaNs, infinities, subnormals, huge values):
 *   bytes 0-3   loop dt (float, s)
 *   then, per call, one opcode byte and its arguments:
 *   opcode & 7:
 *   0 initialise (defaults)
 *   1 initialise with the working settings
 *   2 set settings (the working settings)
 *   3 edit the working settings: field index byte (mod
 *     FUSION_ALTITUDE_KALMAN_SETTINGS_WORDS, 23 today: the struct's fields in
 *     order, gapPeriod 19, the three sensor timeouts 20-22; the decoder,
 *     FusionAltitudeKalmanSettingsSetWord, is generated from the header), 4 raw
 *     bytes (float bits; int32 for the minimum satellites; != 0 for the bool)
 *   4 update with every argument from the input: accel, dt, baro, range, GPS
 *     altitude, GPS accuracy (floats), satellites (int32), flags byte (bit 0:
 *     ground effect)
 *   5 update at the loop dt: accel, a presence byte (bit 0 baro, 1 range,
 *     2 GPS, 3 ground effect, 4 GPS accuracy, 5 satellites), then only the
 *     floats present (and the int32 satellites if flagged)
 *   6 update at the loop dt with NULL measurements: accel
 *   7 initialise with NULL settings, and reset the working settings to the defaults
 *   Step fuzzing: with bit 7 of the opcode set, 5 and 6 first read a step
 *   byte and update at a step from it instead of the loop dt (StepFromByte:
 *   0.1 ms to 10 s, 16 base steps times a jitter of up to 15/32; telemetry
 *   mixes of 0.1-4 s are sequences of them).
 *
 * Asserted after every call (abort, so libFuzzer reports a crash):
 *   - a rejected call leaves the filter bit-identical (memcmp, padding
 *     included);
 *   - InitialiseWith and SetSettings return what SettingsCheck returns on
 *     the same settings; an update returns the status that an independent
 *     classification of its inputs predicts (ExpectedStatus);
 *   - P is exactly symmetric (bitwise), always;
 *   - while the run is "sane" (IsSane below): x, P, the innovations,
 *     variances and NIS are finite (or the no-sample NaN) and the diagonal of
 *     P is >= 0.
 *
 * A run is sane while every accepted input and the settings in use are
 *   physically plausible:
 *   - every update at the loop dt, with 1e-3 s <= dt <= 0.1 s, or at a step
 *     from a step byte (1e-4 s <= dt <= 10 s), at most MAX_STEPS (20000)
 *     updates since the filter was initialised;
 *   - |accel| <= 1e3 m/s^2, |baro|, |GPS altitude| <= 1e5 m, GPS accuracy
 *     (when given) in [0.01, 100] m; range any (it is used only within the
 *     limits);
 *   - settings: accel noise in [1e-3, 10] m/s^2/sqrt(Hz), bias random walk
 *     <= 1 m/s^3/sqrt(Hz), initial bias sigma <= 10 m/s^2, baro and range
 *     noise in [0.01, 100] m, offset random walks <= 10 m/sqrt(s), range
 *     maximum <= 1e3 m, GPS base and satellite terms <= 100 m with a sum
 *     >= 0.1 m, gate <= 1e3, ground-effect scale <= 100 and dead zone
 *     <= 1e3 m, initial height and velocity sigmas <= 1e3 (m, m/s).
 * The bound stated for a sane run: |h|, |v|, the offsets and the bias within
 * MAX_STATE (1e14 m, m/s, m/s^2), every P entry within MAX_VARIANCE (1e30).
 * From the box: at most 20000 steps of at most 10 s (2e5 s), |accel| <=
 * 1e3 m/s^2: |v| <= 2e8 m/s and |h| <= 0.5 * 1e3 * (2e5)^2 = 2e13 m from the
 * prediction alone, samples within 1e5 m; P grows at most by the gap
 * inflation (10 m/s * 10 s)^2 and the prediction over 2e5 s.
 * Finite inputs alone are not enough: accel = 3e38 overflows h in one step,
 * and a noise of 1e-30 m next to a variance of 1e30 m^2 leaves nothing of
 * float32's 24 bits for the update.
 */

#include "fusion_altitude_kalman.h"
#include "fuzz_common.h"
#include "tests/vectors/kalman_settings_words.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MIN_DT (1e-3f)       /* s */
#define MAX_DT (0.1f)        /* s */
#define MAX_STEPS (20000)    /* updates since initialisation */
#define MAX_ACCEL (1e3f)     /* m/s^2 */
#define MAX_ALTITUDE (1e5f)  /* m */
#define MIN_STEP (1e-4f)     /* s, step fuzzing */
#define MAX_STEP (10.0f)     /* s, step fuzzing */
#define MAX_STATE (1e14f)    /* m, m/s, m/s^2: the bound of a sane run (file comment) */
#define MAX_VARIANCE (1e30f) /* m^2 and the like */

/* The settings a physically plausible system would have (see the file comment). */
static bool SaneSettings(const FusionAltitudeKalmanSettings *const s) {
    return InRange(s->accelNoise, 1e-3f, 10.0f) && InRange(s->accelBiasRandomWalk, 0.0f, 1.0f) &&
           InRange(s->accelBiasInitialSigma, 0.0f, 10.0f) && InRange(s->baroNoise, 0.01f, 100.0f) &&
           InRange(s->baroOffsetRandomWalk, 0.0f, 10.0f) && InRange(s->rangeNoise, 0.01f, 100.0f) &&
           InRange(s->rangeMaximum, 0.0f, 1e3f) && InRange(s->gpsNoiseBase, 0.0f, 100.0f) &&
           InRange(s->gpsNoiseSatellite, 0.0f, 100.0f) && (s->gpsNoiseBase + s->gpsNoiseSatellite >= 0.1f) &&
           InRange(s->gpsOffsetRandomWalk, 0.0f, 10.0f) && InRange(s->gate, 0.0f, 1e3f) &&
           InRange(s->groundEffectNoiseScale, 1.0f, 100.0f) && InRange(s->groundEffectDeadZone, 0.0f, 1e3f) &&
           InRange(s->initialHeightSigma, 0.0f, 1e3f) && InRange(s->initialVelocitySigma, 0.0f, 1e3f);
}

/* The status FusionAltitudeKalmanUpdate must return, classified independently of the header's code. */
static FusionAltitudeKalmanStatus ExpectedStatus(const float accel, const float dt, const FusionAltitudeKalmanMeasurements *const m) {
    if (!FusionAltitudeIsFinite(accel)) {
        return FusionAltitudeKalmanStatusInvalidAccel;
    }
    if (!FusionAltitudeIsFinite(dt) || (dt <= 0.0f)) {
        return FusionAltitudeKalmanStatusInvalidDt;
    }
    if ((m != NULL) && IsInfinite(m->baroAltitude)) {
        return FusionAltitudeKalmanStatusInvalidBaroAltitude;
    }
    if ((m != NULL) && IsInfinite(m->gpsAltitude)) {
        return FusionAltitudeKalmanStatusInvalidGpsAltitude;
    }
    if ((m != NULL) && !FusionAltitudeIsNaN(m->gpsAltitude) && !FusionAltitudeIsNaN(m->gpsVerticalAccuracy) &&
        !(FusionAltitudeIsFinite(m->gpsVerticalAccuracy) && (m->gpsVerticalAccuracy > 0.0f))) {
        return FusionAltitudeKalmanStatusInvalidGpsAccuracy;
    }
    return FusionAltitudeKalmanStatusOk;
}

/* Finite, or the no-sample NaN (0x7FC00000). */
static bool FiniteOrNoSample(const float value) {
    return FusionAltitudeIsFinite(value) || (FusionAltitudeFloatBits(value) == 0x7FC00000u);
}

static void CheckSymmetric(const FusionAltitudeKalman *const kalman) {
    for (int i = 0; i < FUSION_ALTITUDE_KALMAN_STATES; i++) {
        for (int j = 0; j < i; j++) {
            CHECK(FusionAltitudeFloatBits(kalman->P[i][j]) == FusionAltitudeFloatBits(kalman->P[j][i]));
        }
    }
}

static void CheckFinite(const FusionAltitudeKalman *const kalman) {
    for (int i = 0; i < FUSION_ALTITUDE_KALMAN_STATES; i++) {
        CHECK(InRange(kalman->x[i], -MAX_STATE, MAX_STATE));
        CHECK(kalman->P[i][i] >= 0.0f);
        for (int j = 0; j < FUSION_ALTITUDE_KALMAN_STATES; j++) {
            CHECK(InRange(kalman->P[i][j], -MAX_VARIANCE, MAX_VARIANCE));
        }
    }
    for (int i = 0; i < FUSION_ALTITUDE_KALMAN_SENSORS; i++) {
        const FusionAltitudeKalmanSensor sensor = FusionAltitudeKalmanGetSensor(kalman, (FusionAltitudeKalmanSensorIndex) i);
        CHECK(FiniteOrNoSample(sensor.innovation) && FiniteOrNoSample(sensor.innovationVariance) && FiniteOrNoSample(FusionAltitudeKalmanGetNis(kalman, (FusionAltitudeKalmanSensorIndex) i)));
        CHECK(FusionAltitudeIsFinite(sensor.rejectingFor));
    }
    CHECK(FusionAltitudeIsFinite(FusionAltitudeKalmanGetAltitude(kalman)));
    CHECK(FusionAltitudeIsFinite(FusionAltitudeKalmanGetAltitudeVariance(kalman)));
}

/* A step from a step byte: 16 base steps from 0.1 ms to 10 s (s), times 1 + (byte >> 4) / 32, at most MAX_STEP. */
static float StepFromByte(const uint8_t byte) {
    static const float steps[16] = {1e-4f, 5e-4f, 1e-3f, 2e-3f, 5e-3f, 0.01f, 0.02f, 0.05f,
                                    0.1f,  0.25f, 0.5f,  1.0f,  2.0f,  4.0f,  7.0f,  10.0f};
    const float dt = steps[byte & 15u] * (1.0f + (float) (byte >> 4) / 32.0f);
    return (dt < MAX_STEP) ? dt : MAX_STEP;
}

typedef struct {
    bool sane;    /* all accepted inputs and settings physically plausible so far */
    int steps;    /* updates since initialisation */
    float loopDt; /* s */
    bool loopDtSane;
} Run;

static void Initialised(Run *const run, const FusionAltitudeKalman *const kalman) {
    const FusionAltitudeKalmanSettings settings = FusionAltitudeKalmanGetSettings(kalman);
    run->sane = run->loopDtSane && SaneSettings(&settings);
    run->steps = 0;
}

static FusionAltitudeKalmanStatus Update(FusionAltitudeKalman *const kalman, Run *const run, const float accel, const float dt,
                                         const FusionAltitudeKalmanMeasurements *const m, const bool stepped) {
    const FusionAltitudeKalmanStatus status = FusionAltitudeKalmanUpdate(kalman, accel, dt, m);
    CHECK(status == ExpectedStatus(accel, dt, m));
    if (status != FusionAltitudeKalmanStatusOk) {
        return status;
    }
    run->steps++;
    const bool stepPlausible = stepped ? InRange(dt, MIN_STEP, MAX_STEP)
                                       : (FusionAltitudeFloatBits(dt) == FusionAltitudeFloatBits(run->loopDt));
    bool plausible = InRange(accel, -MAX_ACCEL, MAX_ACCEL) && stepPlausible && (run->steps <= MAX_STEPS);
    if (m != NULL) {
        plausible = plausible && (FusionAltitudeIsNaN(m->baroAltitude) || InRange(m->baroAltitude, -MAX_ALTITUDE, MAX_ALTITUDE));
        plausible = plausible && (FusionAltitudeIsNaN(m->gpsAltitude) || InRange(m->gpsAltitude, -MAX_ALTITUDE, MAX_ALTITUDE));
        plausible = plausible && (FusionAltitudeIsNaN(m->gpsAltitude) || FusionAltitudeIsNaN(m->gpsVerticalAccuracy) ||
                                  InRange(m->gpsVerticalAccuracy, 0.01f, 100.0f));
    }
    run->sane = run->sane && plausible;
    return status;
}

/* The step of opcodes 5 and 6: the loop dt, or with opcode bit 7 one byte through StepFromByte. False when the input ends. */
static bool ReadStep(Reader *const reader, const Run *const run, const uint8_t opcode, float *const dt) {
    *dt = run->loopDt;
    if ((opcode & 0x80u) == 0u) {
        return true;
    }
    uint8_t byte;
    if (!ReadByte(reader, &byte)) {
        return false;
    }
    *dt = StepFromByte(byte);
    return true;
}

/* Opcode 4: a, dt, every measurement and a ground-effect byte, all raw. False when the input ends. */
static bool CallUpdateRaw(FusionAltitudeKalman *const kalman, Run *const run, Reader *const reader, FusionAltitudeKalmanStatus *const status) {
    float accel = 0.0f;
    float dt = 0.0f;
    uint8_t byte = 0;
    FusionAltitudeKalmanMeasurements m = FusionAltitudeKalmanMeasurementsNone();
    if (!ReadFloat(reader, &accel) || !ReadFloat(reader, &dt) || !ReadFloat(reader, &m.baroAltitude) ||
        !ReadFloat(reader, &m.rangeDistance) || !ReadFloat(reader, &m.gpsAltitude) ||
        !ReadFloat(reader, &m.gpsVerticalAccuracy) || !ReadBytes(reader, &m.gpsSatellites, sizeof(m.gpsSatellites)) ||
        !ReadByte(reader, &byte)) {
        return false;
    }
    m.groundEffect = (byte & 1u) != 0u;
    *status = Update(kalman, run, accel, dt, &m, false);
    return true;
}

/* Opcode 5: a and a presence byte (bit 0 baro, 1 range, 2 GPS altitude, 3 ground effect, 4 GPS accuracy,
 * 5 satellites) followed by the present measurements; opcode 6: a alone (no measurement struct). */
static bool CallUpdate(FusionAltitudeKalman *const kalman, Run *const run, Reader *const reader, const uint8_t opcode,
                       FusionAltitudeKalmanStatus *const status) {
    float accel = 0.0f;
    float dt = 0.0f;
    uint8_t byte = 0;
    FusionAltitudeKalmanMeasurements m = FusionAltitudeKalmanMeasurementsNone();
    if (!ReadStep(reader, run, opcode, &dt) || !ReadFloat(reader, &accel)) {
        return false;
    }
    if ((opcode & 7u) == 6u) {
        *status = Update(kalman, run, accel, dt, NULL, (opcode & 0x80u) != 0u);
        return true;
    }
    if (!ReadByte(reader, &byte) || (((byte & 1u) != 0u) && !ReadFloat(reader, &m.baroAltitude)) ||
        (((byte & 2u) != 0u) && !ReadFloat(reader, &m.rangeDistance)) ||
        (((byte & 4u) != 0u) && !ReadFloat(reader, &m.gpsAltitude)) ||
        (((byte & 16u) != 0u) && !ReadFloat(reader, &m.gpsVerticalAccuracy)) ||
        (((byte & 32u) != 0u) && !ReadBytes(reader, &m.gpsSatellites, sizeof(m.gpsSatellites)))) {
        return false;
    }
    m.groundEffect = (byte & 8u) != 0u;
    *status = Update(kalman, run, accel, dt, &m, (opcode & 0x80u) != 0u);
    return true;
}

/* Opcodes 0-3 and 7: initialise, initialise with / set the working settings, edit one settings word (index byte,
 * 4-byte word), initialise with NULL (the defaults, also for the working settings). False when the input ends. */
static bool CallSettings(FusionAltitudeKalman *const kalman, Run *const run, Reader *const reader, const uint8_t opcode,
                         FusionAltitudeKalmanSettings *const working, FusionAltitudeKalmanStatus *const status) {
    uint8_t byte = 0;
    uint32_t bits = 0u;
    switch (opcode & 7u) {
        case 0:
            FusionAltitudeKalmanInitialise(kalman);
            Initialised(run, kalman);
            return true;
        case 1:
            *status = FusionAltitudeKalmanInitialiseWith(kalman, working);
            CHECK(*status == FusionAltitudeKalmanSettingsCheck(working));
            if (*status == FusionAltitudeKalmanStatusOk) {
                Initialised(run, kalman);
            }
            return true;
        case 2:
            *status = FusionAltitudeKalmanSetSettings(kalman, working);
            CHECK(*status == FusionAltitudeKalmanSettingsCheck(working));
            if (*status == FusionAltitudeKalmanStatusOk) {
                run->sane = run->sane && SaneSettings(working);
            }
            return true;
        case 3:
            if (!ReadByte(reader, &byte) || !ReadBytes(reader, &bits, sizeof(bits))) {
                return false;
            }
            FusionAltitudeKalmanSettingsSetWord(working, byte % FUSION_ALTITUDE_KALMAN_SETTINGS_WORDS, bits);
            return true;
        default:
            *status = FusionAltitudeKalmanInitialiseWith(kalman, NULL);
            CHECK(*status == FusionAltitudeKalmanStatusOk);
            *working = FusionAltitudeKalmanSettingsDefault();
            Initialised(run, kalman);
            return true;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    Reader reader = {data, size};
    Run run = {true, 0, 0.0f, false};
    if (!ReadFloat(&reader, &run.loopDt)) {
        return 0;
    }
    run.loopDtSane = InRange(run.loopDt, MIN_DT, MAX_DT);
    static FusionAltitudeKalman kalman;
    memset(&kalman, 0, sizeof(kalman)); /* defined padding bytes for memcmp */
    FusionAltitudeKalmanInitialise(&kalman);
    Initialised(&run, &kalman);
    FusionAltitudeKalmanSettings working;
    memset(&working, 0, sizeof(working));
    working = FusionAltitudeKalmanSettingsDefault();
    uint8_t opcode;
    while (ReadByte(&reader, &opcode)) {
        static FusionAltitudeKalman before;
        memcpy(&before, &kalman, sizeof(before));
        FusionAltitudeKalmanStatus status = FusionAltitudeKalmanStatusOk;
        const unsigned call = opcode & 7u;
        bool read;
        if (call == 4u) {
            read = CallUpdateRaw(&kalman, &run, &reader, &status);
        } else if ((call == 5u) || (call == 6u)) {
            read = CallUpdate(&kalman, &run, &reader, opcode, &status);
        } else {
            read = CallSettings(&kalman, &run, &reader, opcode, &working, &status);
        }
        if (!read) {
            return 0;
        }
        if (status != FusionAltitudeKalmanStatusOk) {
            CHECK(memcmp(&before, &kalman, sizeof(before)) == 0);
        }
        (void) FusionAltitudeKalmanStatusMessage(status);
        CheckSymmetric(&kalman);
        if (run.sane) {
            CheckFinite(&kalman);
        }
    }
    return 0;
}
