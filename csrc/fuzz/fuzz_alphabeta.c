/**
 * @file fuzz_alphabeta.c
 * @brief libFuzzer target for fusion_altitude_alphabeta.h, built with clang
 * under AddressSanitizer + UndefinedBehaviorSanitizer (csrc/firmware/Makefile,
 * FUZZERS; seeds in csrc/fuzz/corpus_alphabeta/, written by
 * make_seeds_alphabeta.py).
 *
 * The input is a loop period followed by a sequence of calls; floats are raw
 * bytes (any bit pattern: NaNs, infinities, subnormals, huge values):
 *   bytes 0-3   loop dt (float, s)
 *   then, per call, one opcode byte and its arguments:
 *   opcode & 7:
 *   0 initialise (defaults)
 *   1 initialise with the working settings
 *   2 set settings (the working settings)
 *   3 edit the working settings: an index byte (mod
 *     FUSION_ALTITUDE_ALPHABETA_SETTINGS_WORDS: the flattened settings of
 *     alphabeta_settings_words.h, each sensor's fields then the gap period),
 *     4 raw bytes (the word: float bits, int32 for the qualities)
 *   4 update with every argument from the input: accel, dt, baro, lidar,
 *     sonar, GPS (floats)
 *   5 update at a step from a step byte (StepFromByte: 0.1 ms to 10 s, 16
 *     base steps times a jitter of up to 15/32; telemetry mixes of 0.1-4 s are
 *     sequences of them): step byte, accel, a presence byte (bit 0 accel,
 *     1 baro, 2 lidar, 3 sonar, 4 GPS; absent: NaN), then the floats present
 *   6 update at the loop dt: accel, presence byte, the floats present
 *   7 initialise with the defaults, and reset the working settings to them
 *
 * Asserted after every call (abort, so libFuzzer reports a crash):
 *   - a rejected call leaves the fusion bit-identical (memcmp, padding
 *     included);
 *   - InitialiseWith and SetSettings return what SettingsCheck returns on
 *     the same settings; an update returns the status that an independent
 *     classification of its inputs predicts (ExpectedStatus);
 *   - every weight is finite and >= 0, and 0 for a filter not started;
 *   - while the run is sane (below): the fused altitude and velocity and
 *     every started filter's altitude and velocity are finite and within
 *     MAX_STATE (1e9 m, m/s).
 *
 * A run is sane while every accepted input and the settings in use are
 * physically plausible:
 *   - every update at the loop dt (1e-3 s <= dt <= 0.1 s) or at a step from
 *     a step byte (1e-4 s <= dt <= 10 s), at most MAX_STEPS (20000) updates
 *     since the fusion was initialised;
 *   - |accel| <= 1e3 m/s^2 (or NaN), every sample within 1e5 m (or NaN);
 *   - settings: thresholds in [1e-3, 1e3] m, confidences <= 1e3, altitude
 *     bands and gap maxima any, timeouts and the gap period <= 1e3 s.
 * The bound: a started filter's altitude is its last sample plus v * T (T up
 * to a timeout, 1e3 s) and its velocity a sum of beta * r / T terms that the
 * interval rule keeps from compounding (FUSION_ALTITUDE_ALPHABETA_MAX_INTERVAL_RATIO);
 * dead reckoning lasts at most a gap period (0.5 * 1e3 m/s^2 * (1e3 s)^2 =
 * 5e8 m). 1e9 m is the round bound above both.
 */

#include "fusion_altitude_alphabeta.h"
#include "fuzz_common.h"
#include "tests/vectors/alphabeta_settings_words.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MIN_DT (1e-3f)       /* s, loop dt */
#define MAX_DT (0.1f)        /* s, loop dt */
#define MIN_STEP (1e-4f)     /* s, step fuzzing */
#define MAX_STEP (10.0f)     /* s, step fuzzing */
#define MAX_STEPS (20000)    /* updates since initialisation */
#define MAX_ACCEL (1e3f)     /* m/s^2 */
#define MAX_ALTITUDE (1e5f)  /* m */
#define MAX_STATE (1e9f)     /* m, m/s: the bound of a sane run (file comment) */

static bool SampleSane(const float value, const float limit) {
    return FusionAltitudeIsNaN(value) || InRange(value, -limit, limit);
}

/* A step from a step byte: 16 base steps from 0.1 ms to 10 s (s), times 1 + (byte >> 4) / 32, at most MAX_STEP. */
static float StepFromByte(const uint8_t byte) {
    static const float steps[16] = {1e-4f, 5e-4f, 1e-3f, 2e-3f, 5e-3f, 0.01f, 0.02f, 0.05f,
                                    0.1f,  0.25f, 0.5f,  1.0f,  2.0f,  4.0f,  7.0f,  10.0f};
    const float dt = steps[byte & 15u] * (1.0f + (float) (byte >> 4) / 32.0f);
    return (dt < MAX_STEP) ? dt : MAX_STEP;
}

/* The settings a physically plausible system would have (see the file comment). */
static bool SaneSettings(const FusionAltitudeAlphaBetaSettings *const s) {
    for (int i = 0; i < FUSION_ALTITUDE_ALPHABETA_SENSORS; i++) {
        const FusionAltitudeAlphaBetaSensorSettings *const sensor = &s->sensors[i];
        if (!InRange(sensor->threshold, 1e-3f, 1e3f) || !InRange(sensor->confidence, 0.0f, 1e3f) ||
            !InRange(sensor->timeout, 0.0f, 1e3f)) {
            return false;
        }
    }
    return InRange(s->gapPeriod, 0.0f, 1e3f);
}

/* The status FusionAltitudeAlphaBetaUpdate must return, classified independently of the header's code. */
static FusionAltitudeAlphaBetaStatus ExpectedStatus(const float accel, const float dt, const FusionAltitudeAlphaBetaMeasurements *const m) {
    if (IsInfinite(accel)) {
        return FusionAltitudeAlphaBetaStatusInvalidAccel;
    }
    if (!FusionAltitudeIsFinite(dt) || (dt <= 0.0f)) {
        return FusionAltitudeAlphaBetaStatusInvalidDt;
    }
    if (IsInfinite(m->baroAltitude)) {
        return FusionAltitudeAlphaBetaStatusInvalidBaroAltitude;
    }
    if (IsInfinite(m->lidarAltitude)) {
        return FusionAltitudeAlphaBetaStatusInvalidLidarAltitude;
    }
    if (IsInfinite(m->sonarAltitude)) {
        return FusionAltitudeAlphaBetaStatusInvalidSonarAltitude;
    }
    if (IsInfinite(m->gpsAltitude)) {
        return FusionAltitudeAlphaBetaStatusInvalidGpsAltitude;
    }
    return FusionAltitudeAlphaBetaStatusOk;
}

static void CheckState(const FusionAltitudeAlphaBeta *const fusion, const bool sane) {
    for (int i = 0; i < FUSION_ALTITUDE_ALPHABETA_SENSORS; i++) {
        const FusionAltitudeAlphaBetaFilter *const f = &fusion->filters[i];
        CHECK(FusionAltitudeIsFinite(f->weight) && (f->weight >= 0.0f));
        CHECK(f->started || (f->weight == 0.0f));
        if (sane && f->started) {
            CHECK(InRange(f->altitude, -MAX_STATE, MAX_STATE) && InRange(f->velocity, -MAX_STATE, MAX_STATE));
        }
    }
    if (sane) {
        CHECK(InRange(FusionAltitudeAlphaBetaGetAltitude(fusion), -MAX_STATE, MAX_STATE));
        CHECK(InRange(FusionAltitudeAlphaBetaGetVerticalVelocity(fusion), -MAX_STATE, MAX_STATE));
    }
}

/* Reads a presence byte and the samples it flags (absent: NaN). */
static bool ReadPresent(Reader *const reader, float *const accel, FusionAltitudeAlphaBetaMeasurements *const m) {
    uint8_t presence;
    if (!ReadByte(reader, &presence)) {
        return false;
    }
    float *const fields[5] = {accel, &m->baroAltitude, &m->lidarAltitude, &m->sonarAltitude, &m->gpsAltitude};
    for (int i = 0; i < 5; i++) {
        *fields[i] = FusionAltitudeNaN();
        if (((presence >> i) & 1u) != 0u) {
            if (!ReadFloat(reader, fields[i])) {
                return false;
            }
        }
    }
    return true;
}

typedef struct {
    bool sane;       /* all accepted inputs and the settings in use physically plausible so far */
    int steps;       /* accepted updates since the fusion was initialised */
    float loopDt;    /* s */
    bool loopDtSane; /* the loop dt is plausible */
} Run;

/* Opcodes 0-3 and 7: initialise, initialise with / set the working settings, edit one word of the working settings
 * (an index byte and 4 raw bytes), initialise with the defaults and reset the working settings. False when the input ends. */
static bool CallSettings(FusionAltitudeAlphaBeta *const fusion, Run *const run, Reader *const reader, const uint8_t opcode,
                         FusionAltitudeAlphaBetaSettings *const working, FusionAltitudeAlphaBetaStatus *const status) {
    uint8_t index = 0;
    uint32_t bits = 0u;
    switch (opcode & 7u) {
        case 0:
            FusionAltitudeAlphaBetaInitialise(fusion);
            run->sane = SaneSettings(&fusion->settings);
            run->steps = 0;
            return true;
        case 1:
            *status = FusionAltitudeAlphaBetaInitialiseWith(fusion, working);
            CHECK(*status == FusionAltitudeAlphaBetaSettingsCheck(working));
            if (*status == FusionAltitudeAlphaBetaStatusOk) {
                run->sane = SaneSettings(working);
                run->steps = 0;
            }
            return true;
        case 2:
            *status = FusionAltitudeAlphaBetaSetSettings(fusion, working);
            CHECK(*status == FusionAltitudeAlphaBetaSettingsCheck(working));
            if (*status == FusionAltitudeAlphaBetaStatusOk) {
                run->sane = run->sane && SaneSettings(working);
            }
            return true;
        case 3:
            if (!ReadByte(reader, &index) || !ReadBytes(reader, &bits, sizeof(bits))) {
                return false;
            }
            FusionAltitudeAlphaBetaSettingsSetWord(working, index % FUSION_ALTITUDE_ALPHABETA_SETTINGS_WORDS, bits);
            return true;
        default:
            FusionAltitudeAlphaBetaInitialise(fusion);
            *working = FusionAltitudeAlphaBetaSettingsDefault();
            run->sane = true;
            run->steps = 0;
            return true;
    }
}

/* Opcodes 4 (every argument raw: accel, dt, baro, lidar, sonar, GPS), 5 (a step byte, then ReadPresent) and 6
 * (ReadPresent at the loop dt): the update, its status against ExpectedStatus and the run's sanity. */
static bool CallUpdate(FusionAltitudeAlphaBeta *const fusion, Run *const run, Reader *const reader, const uint8_t opcode,
                       FusionAltitudeAlphaBetaStatus *const status) {
    FusionAltitudeAlphaBetaMeasurements m = FusionAltitudeAlphaBetaMeasurementsNone();
    float accel = FusionAltitudeNaN();
    float dt = run->loopDt;
    uint8_t stepByte = 0;
    const bool stepped = (opcode & 7u) == 5u;
    if ((opcode & 7u) == 4u) {
        if (!ReadFloat(reader, &accel) || !ReadFloat(reader, &dt) || !ReadFloat(reader, &m.baroAltitude) ||
            !ReadFloat(reader, &m.lidarAltitude) || !ReadFloat(reader, &m.sonarAltitude) || !ReadFloat(reader, &m.gpsAltitude)) {
            return false;
        }
    } else if ((stepped && !ReadByte(reader, &stepByte)) || !ReadPresent(reader, &accel, &m)) {
        return false;
    }
    dt = stepped ? StepFromByte(stepByte) : dt;
    *status = FusionAltitudeAlphaBetaUpdate(fusion, accel, dt, &m);
    CHECK(*status == ExpectedStatus(accel, dt, &m));
    if (*status == FusionAltitudeAlphaBetaStatusOk) {
        run->steps++;
        const bool stepSane = stepped ? InRange(dt, MIN_STEP, MAX_STEP)
                                      : (run->loopDtSane && (FusionAltitudeFloatBits(dt) == FusionAltitudeFloatBits(run->loopDt)));
        run->sane = run->sane && stepSane && (run->steps <= MAX_STEPS) && SampleSane(accel, MAX_ACCEL) &&
                    SampleSane(m.baroAltitude, MAX_ALTITUDE) && SampleSane(m.lidarAltitude, MAX_ALTITUDE) &&
                    SampleSane(m.sonarAltitude, MAX_ALTITUDE) && SampleSane(m.gpsAltitude, MAX_ALTITUDE);
    }
    return true;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    Reader reader = {data, size};
    Run run = {true, 0, 0.0f, false};
    if (!ReadFloat(&reader, &run.loopDt)) {
        return 0;
    }
    run.loopDtSane = InRange(run.loopDt, MIN_DT, MAX_DT);
    static FusionAltitudeAlphaBeta fusion;
    memset(&fusion, 0, sizeof(fusion)); /* defined padding bytes for memcmp */
    FusionAltitudeAlphaBetaInitialise(&fusion);
    FusionAltitudeAlphaBetaSettings working;
    memset(&working, 0, sizeof(working));
    working = FusionAltitudeAlphaBetaSettingsDefault();
    uint8_t opcode;
    while (ReadByte(&reader, &opcode)) {
        static FusionAltitudeAlphaBeta before;
        memcpy(&before, &fusion, sizeof(before));
        FusionAltitudeAlphaBetaStatus status = FusionAltitudeAlphaBetaStatusOk;
        const unsigned call = opcode & 7u;
        const bool read = ((call >= 4u) && (call <= 6u)) ? CallUpdate(&fusion, &run, &reader, opcode, &status)
                                                         : CallSettings(&fusion, &run, &reader, opcode, &working, &status);
        if (!read) {
            return 0;
        }
        if (status != FusionAltitudeAlphaBetaStatusOk) {
            CHECK(memcmp(&before, &fusion, sizeof(before)) == 0);
        }
        (void) FusionAltitudeAlphaBetaStatusMessage(status);
        CheckState(&fusion, run.sane);
    }
    return 0;
}
