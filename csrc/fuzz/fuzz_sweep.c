/**
 * @file fuzz_sweep.c
 * @brief libFuzzer target for fusion_altitude_sweep.h, built with clang under
 * AddressSanitizer + UndefinedBehaviorSanitizer (csrc/firmware/Makefile,
 * target fuzz-run).
 *
 * The input: one byte K (1-8 settings, K = byte % 8 + 1), one byte for the
 * time split, K gain triples (Kh, Kv, Kb; floats, raw bytes), then samples of
 * one control byte and floats: accel, then (unless bit 0: no baro) the baro
 * altitude, then (with bit 1) an explicit dt, else the step of the control
 * byte's upper 6 bits from a table of 64 steps from 0.1 ms to 10 s
 * (log-spaced). Settings that FusionAltitudeSettingsCheck rejects are
 * replaced by the defaults. The seeds (make_seeds_sweep.py) hold telemetry-like
 * 0.1-4 s mixes, 0.1 ms-10 s sequences and baro outages.
 *
 * Asserted (abort, so libFuzzer reports a crash):
 *   - inputs FusionAltitudeCheckInputs rejects are reported at their index
 *     and touch nothing (state, outputs);
 *   - one call over all samples equals two calls split at any index (the
 *     shared timeline, the stability rule's tiles) bit for bit;
 *   - the K settings run as two parts with ruleBefore/ruleAfter (how a sweep
 *     is split across threads) equal the one sweep bit for bit;
 *   - with K = 1 the column equals FusionAltitudeUpdate alone bit for bit;
 *   - while the inputs are plausible (|accel| <= 1e3 m/s^2, |baro| <= 1e5 m,
 *     1e-4 s <= dt <= 10 s, Kh <= 100 1/s, Kv, Kb <= 1e3) the outputs stay
 *     finite and within MAX_STATE (1e9: m, m/s, m/s^2).
 */

#include "fusion_altitude_sweep.h"
#include "fuzz_common.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_SETTINGS (8)
#define MAX_SAMPLES (512)
#define MAX_STATE (1e9f) /* m, m/s, m/s^2 */

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static float kh[MAX_SETTINGS], kv[MAX_SETTINGS], kb[MAX_SETTINGS];
static float accel[MAX_SAMPLES], baro[MAX_SAMPLES], dt[MAX_SAMPLES];

typedef struct {
    float state[4][MAX_SETTINGS];
    float out[4][MAX_SAMPLES * MAX_SETTINGS];
} Run;

static Run runs[4];

/* A sweep over settings [first, first + count) of the gain arrays (the stability rule over all K). */
static FusionAltitudeSweep NewSweep(Run *const run, const size_t first, const size_t count, const size_t total) {
    FusionAltitudeSweep sweep;
    memset(&sweep, 0, sizeof(sweep));
    sweep.count = count;
    sweep.positionGain = &kh[first];
    sweep.velocityGain = &kv[first];
    sweep.biasGain = &kb[first];
    sweep.altitude = &run->state[0][first];
    sweep.verticalVelocity = &run->state[1][first];
    sweep.accelBias = &run->state[2][first];
    sweep.baroResidual = &run->state[3][first];
    FusionAltitudeSweepInitialise(&sweep);
    sweep.ruleBefore = first;
    sweep.ruleAfter = total - first - count;
    return sweep;
}

static FusionAltitudeStatus Sweep(FusionAltitudeSweep *const sweep, Run *const run, const size_t first, const size_t total,
                                  const size_t start, const size_t samples, size_t *const bad) {
    const FusionAltitudeSweepOutputs outputs = {&run->out[0][start * total + first], &run->out[1][start * total + first],
                                                &run->out[2][start * total + first], &run->out[3][start * total + first], total};
    return FusionAltitudeSweepUpdate(sweep, &accel[start], &baro[start], &dt[start], 1, samples, &outputs, NULL, bad);
}

static bool SameBits(const float *const a, const float *const b, const size_t count) {
    return memcmp(a, b, count * sizeof(float)) == 0;
}

/* Reads count gain triples into kh, kv, kb (a rejected triple: the defaults); false when the input ends.
 * *sane: every gain plausible (Kh <= 100 1/s, Kv <= 1e3 1/s^2, Kb <= 1e3 1/s^3). */
static bool ReadGains(Reader *const reader, const size_t count, bool *const sane) {
    for (size_t k = 0; k < count; k++) {
        FusionAltitudeSettings settings = FusionAltitudeSettingsDefault();
        if (!ReadFloat(reader, &settings.positionGain) || !ReadFloat(reader, &settings.velocityGain) ||
            !ReadFloat(reader, &settings.biasGain)) {
            return false;
        }
        if (FusionAltitudeSettingsCheck(&settings) != FusionAltitudeStatusOk) {
            settings = FusionAltitudeSettingsDefault();
        }
        kh[k] = settings.positionGain;
        kv[k] = settings.velocityGain;
        kb[k] = settings.biasGain;
        *sane = *sane && Within(kh[k], 100.0f) && Within(kv[k], 1e3f) && Within(kb[k], 1e3f);
    }
    return true;
}

/* Reads up to MAX_SAMPLES samples into accel, baro, dt; returns how many. Per sample: a control byte (bit 0: no baro;
 * bit 1: dt as a float, else 1e-4 s * 1.2005^(control >> 2)), a (m/s^2), z (m) unless bit 0, dt (s) if bit 1.
 * *sane: every input plausible (|a| <= 1e3 m/s^2, |z| <= 1e5 m, 1e-4 s <= dt <= 10 s). */
static size_t ReadSamples(Reader *const reader, bool *const sane) {
    size_t samples = 0;
    uint8_t control;
    while ((samples < MAX_SAMPLES) && ReadByte(reader, &control)) {
        float a;
        float z = FusionAltitudeNaN();
        float step = 1e-4f;
        if (!ReadFloat(reader, &a) || (((control & 1u) == 0u) && !ReadFloat(reader, &z))) {
            break;
        }
        if ((control & 2u) != 0u) {
            if (!ReadFloat(reader, &step)) {
                break;
            }
        } else {
            for (unsigned i = 0; i < (unsigned) (control >> 2); i++) {
                step *= 1.2005f; /* 64 log-spaced steps, 1e-4 s to 10 s */
            }
        }
        accel[samples] = a;
        baro[samples] = z;
        dt[samples] = step;
        *sane = *sane && Within(a, 1e3f) && (FusionAltitudeIsNaN(z) || Within(z, 1e5f)) && (step >= 1e-4f) && (step <= 10.0f);
        samples++;
    }
    return samples;
}

/* The index of the first sample FusionAltitudeCheckInputs rejects, samples if none. */
static size_t FirstBadSample(const size_t samples) {
    for (size_t t = 0; t < samples; t++) {
        if (FusionAltitudeCheckInputs(accel[t], baro[t], dt[t]) != FusionAltitudeStatusOk) {
            return t;
        }
    }
    return samples;
}

/* Run 1 (two calls split in time at split) and run 2 (the settings in two parts, one stability rule, as across
 * threads) give the bits of run 0 (whole). */
static void CheckSplits(const FusionAltitudeSweep *const whole, const size_t count, const size_t samples, const size_t split) {
    size_t bad = 0;
    FusionAltitudeSweep halves = NewSweep(&runs[1], 0, count, count);
    CHECK(Sweep(&halves, &runs[1], 0, count, 0, split, &bad) == FusionAltitudeStatusOk);
    CHECK(Sweep(&halves, &runs[1], 0, count, split, samples - split, &bad) == FusionAltitudeStatusOk);
    for (int field = 0; field < 4; field++) {
        CHECK(SameBits(runs[0].out[field], runs[1].out[field], samples * count));
    }
    CHECK((halves.gapCount == whole->gapCount) && (halves.baroTimeouts == whole->baroTimeouts));
    const size_t part = count / 2u;
    if (part > 0u) {
        FusionAltitudeSweep lower = NewSweep(&runs[2], 0, part, count);
        FusionAltitudeSweep upper = NewSweep(&runs[2], part, count - part, count);
        CHECK(Sweep(&lower, &runs[2], 0, count, 0, samples, &bad) == FusionAltitudeStatusOk);
        CHECK(Sweep(&upper, &runs[2], part, count, 0, samples, &bad) == FusionAltitudeStatusOk);
        for (int field = 0; field < 4; field++) {
            CHECK(SameBits(runs[0].out[field], runs[2].out[field], samples * count));
        }
    }
}

/* Run 3: the first setting alone gives the bits of FusionAltitudeUpdate. */
static void CheckSingle(const size_t samples) {
    size_t bad = 0;
    FusionAltitudeSweep single = NewSweep(&runs[3], 0, 1, 1);
    CHECK(Sweep(&single, &runs[3], 0, 1, 0, samples, &bad) == FusionAltitudeStatusOk);
    FusionAltitude altitude;
    FusionAltitudeInitialise(&altitude);
    FusionAltitudeSettings settings = FusionAltitudeSettingsDefault();
    settings.positionGain = kh[0];
    settings.velocityGain = kv[0];
    settings.biasGain = kb[0];
    CHECK(FusionAltitudeSetSettings(&altitude, &settings) == FusionAltitudeStatusOk);
    for (size_t t = 0; t < samples; t++) {
        CHECK(FusionAltitudeUpdate(&altitude, accel[t], baro[t], dt[t]) == FusionAltitudeStatusOk);
        CHECK(SameBits(&runs[3].out[0][t], &altitude.altitude, 1u) && SameBits(&runs[3].out[1][t], &altitude.verticalVelocity, 1u) &&
              SameBits(&runs[3].out[2][t], &altitude.accelBias, 1u) && SameBits(&runs[3].out[3][t], &altitude.baroResidual, 1u));
    }
    CHECK((single.gapCount == altitude.gapCount) && (single.baroTimeouts == altitude.baroTimeouts));
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    Reader reader = {data, size};
    uint8_t countByte;
    uint8_t splitByte;
    if (!ReadByte(&reader, &countByte) || !ReadByte(&reader, &splitByte)) {
        return 0;
    }
    const size_t count = (size_t) (countByte % MAX_SETTINGS) + 1u;
    bool sane = true;
    if (!ReadGains(&reader, count, &sane)) {
        return 0;
    }
    const size_t samples = ReadSamples(&reader, &sane);
    if (samples == 0u) {
        return 0;
    }
    memset(runs, 0, sizeof(runs));
    size_t bad = 0;
    /* 0: one call over everything */
    FusionAltitudeSweep whole = NewSweep(&runs[0], 0, count, count);
    const FusionAltitudeStatus status = Sweep(&whole, &runs[0], 0, count, 0, samples, &bad);
    const size_t firstBad = FirstBadSample(samples);
    if (status != FusionAltitudeStatusOk) {
        CHECK(bad == firstBad);
        CHECK(status == FusionAltitudeCheckInputs(accel[bad], baro[bad], dt[bad]));
        for (size_t i = 0; i < samples * count; i++) {
            CHECK(runs[0].out[0][i] == 0.0f); /* nothing written */
        }
        return 0;
    }
    CHECK(firstBad == samples);
    CheckSplits(&whole, count, samples, (size_t) splitByte % (samples + 1u));
    CheckSingle(samples);
    if (sane) {
        for (size_t i = 0; i < samples * count; i++) {
            CHECK(Within(runs[0].out[0][i], MAX_STATE) && Within(runs[0].out[1][i], MAX_STATE) && Within(runs[0].out[2][i], MAX_STATE));
        }
    }
    return 0;
}
