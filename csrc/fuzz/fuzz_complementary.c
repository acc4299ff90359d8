/**
 * @file fuzz_complementary.c
 * @brief libFuzzer target for fusion_altitude_complementary.h, built with clang
 * under AddressSanitizer + UndefinedBehaviorSanitizer (csrc/firmware/Makefile,
 * target fuzz-run).
 *
 * The input is a loop period followed by a sequence of calls; floats are raw
 * bytes (any bit pattern: NaNs, infinities, subnormals, huge values):
 *   bytes 0-3   loop dt (float, s)
 *   then, per call, one opcode byte and its float arguments (4 bytes each):
 *   opcode & 7: 0 initialise, 1 set settings (tauA, tauB, cV, cH, TV, TH, gap
 *   period, baro timeout; opcode bit 4: per-sample coefficients), 2 reset (z),
 *   3 update (a, z, dt), 4-7 update at the loop dt (a, z);
 *   opcode bit 3 replaces z of an update with a NaN (no baro sample).
 * The seeds (make_seeds_complementary.py) hold step sequences of 0.1 ms to
 * 10 s, telemetry-like 0.1-4 s mixes and baro outages past the timeout.
 *
 * Asserted after every call (abort, so libFuzzer reports a crash):
 *   - a rejected call leaves the filter bit-identical (memcmp);
 *   - FusionAltitudeComplementaryCheckInputs returns what the update returned,
 *     FusionAltitudeComplementarySettingsCheck what SetSettings returned;
 *   - an accepted update: the gap count goes up by one exactly on a gap
 *     (dt > gapPeriod once the reference is set), the timeout count by at
 *     most one, a baro sample ends a timeout, and while timed out a step
 *     without baro decays the velocity by T/(T + dt) and keeps aLp;
 *   - the state stays finite and within MAX_STATE (1e9: m, m/s, m/s^2) while
 *     the run is "sane": every accepted input plausible (|accel| <= 1e3 m/s^2,
 *     |baro| and |reset altitude| <= 1e5 m, 1e-4 s <= dt <= 10 s, any step
 *     sequence) and every accepted setting too (time constants <= 100 s,
 *     per-sample coefficients <= 0.999, the baro timeout <= 10 s). The blend
 *     is stable at every step (eigenvalues in [0, 1]); the velocity error
 *     is then at most about 1e3 m/s^2 * (TV + the 10 s timeout) and the
 *     altitude's that times TH, far below MAX_STATE.
 */

#include "fusion_altitude_complementary.h"
#include "fuzz_common.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_ACCEL (1e3f)     /* m/s^2 */
#define MAX_ALTITUDE (1e5f)  /* m */
#define MIN_DT (1e-4f)       /* s */
#define MAX_DT (10.0f)       /* s */
#define MAX_STATE (1e9f)     /* m, m/s, m/s^2 */

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static bool SameBits(const float a, const float b) {
    return FusionAltitudeFloatBits(a) == FusionAltitudeFloatBits(b);
}

static bool PlausibleSettings(const FusionAltitudeComplementarySettings *const s) {
    const bool blend = s->perSampleCoefficients ? ((s->velocityCoefficient <= 0.999f) && (s->altitudeCoefficient <= 0.999f))
                                                : ((s->velocityTimeConstant <= 100.0f) && (s->altitudeTimeConstant <= 100.0f));
    return blend && (s->accelTimeConstant <= 100.0f) && (s->baroTimeConstant <= 100.0f) && (s->baroTimeout <= 10.0f);
}

static bool StateBounded(const FusionAltitudeComplementary *const f) {
    return Within(f->altitude, MAX_STATE) && Within(f->verticalVelocity, MAX_STATE) && Within(f->accelFiltered, MAX_STATE) &&
           Within(f->baroFiltered, MAX_STATE);
}

static void Update(FusionAltitudeComplementary *const filter, bool *const sane, const float accel, const float baro, const float dt) {
    FusionAltitudeComplementary before;
    memcpy(&before, filter, sizeof(before)); /* with its padding bytes */
    const FusionAltitudeComplementaryStatus status = FusionAltitudeComplementaryUpdate(filter, accel, baro, dt);
    CHECK(FusionAltitudeComplementaryCheckInputs(accel, baro, dt) == status);
    if (status != FusionAltitudeComplementaryStatusOk) {
        CHECK(memcmp(&before, filter, sizeof(before)) == 0);
        return;
    }
    const bool baroSample = FusionAltitudeIsFinite(baro);
    const bool gap = before.referenceSet && (dt > before.settings.gapPeriod);
    CHECK(FusionAltitudeComplementaryGetGapCount(filter) == before.gapCount + (gap ? 1u : 0u));
    CHECK((FusionAltitudeComplementaryGetBaroTimeouts(filter) - before.baroTimeouts) <= 1u);
    CHECK(!FusionAltitudeComplementaryIsBaroTimedOut(filter) || !baroSample);
    if (!gap && before.referenceSet && before.baroTimedOut && !baroSample) { /* no dead reckoning: v decays */
        const float timeout = before.settings.baroTimeout;
        CHECK(SameBits(filter->verticalVelocity, before.verticalVelocity * (timeout / (timeout + dt))));
        CHECK(SameBits(filter->accelFiltered, before.accelFiltered));
    }
    if (baroSample && (before.referenceSet || (before.gapTime > 0.0f) || gap)) {
        CHECK(FusionAltitudeComplementaryIsReferenceSet(filter));
    }
    *sane = *sane && Within(accel, MAX_ACCEL) && (!baroSample || Within(baro, MAX_ALTITUDE)) && (dt >= MIN_DT) && (dt <= MAX_DT);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    Reader reader = {data, size};
    float loopDt;
    if (!ReadFloat(&reader, &loopDt)) {
        return 0;
    }
    FusionAltitudeComplementary filter;
    memset(&filter, 0, sizeof(filter)); /* defined padding bytes for memcmp */
    FusionAltitudeComplementaryInitialise(&filter);
    bool sane = true;
    uint8_t opcode;
    while (ReadByte(&reader, &opcode)) {
        float a = 0.0f;
        float z = 0.0f;
        float t = 0.0f;
        FusionAltitudeComplementary before;
        memcpy(&before, &filter, sizeof(before));
        FusionAltitudeComplementaryStatus status = FusionAltitudeComplementaryStatusOk;
        switch (opcode & 7u) {
            case 0:
                FusionAltitudeComplementaryInitialise(&filter);
                sane = true;
                break;
            case 1: {
                FusionAltitudeComplementarySettings settings;
                memset(&settings, 0, sizeof(settings));
                float *const fields[8] = {&settings.accelTimeConstant, &settings.baroTimeConstant, &settings.velocityCoefficient,
                                          &settings.altitudeCoefficient, &settings.velocityTimeConstant,
                                          &settings.altitudeTimeConstant, &settings.gapPeriod, &settings.baroTimeout};
                for (int i = 0; i < 8; i++) {
                    if (!ReadFloat(&reader, fields[i])) {
                        return 0;
                    }
                }
                settings.perSampleCoefficients = (opcode & 16u) != 0u;
                status = FusionAltitudeComplementarySetSettings(&filter, &settings);
                CHECK(status == FusionAltitudeComplementarySettingsCheck(&settings));
                if (status == FusionAltitudeComplementaryStatusOk) {
                    sane = sane && PlausibleSettings(&settings);
                }
                break;
            }
            case 2:
                if (!ReadFloat(&reader, &z)) {
                    return 0;
                }
                status = FusionAltitudeComplementaryReset(&filter, z);
                if (status == FusionAltitudeComplementaryStatusOk) {
                    CHECK(SameBits(filter.altitude, z) && !filter.baroTimedOut);
                    sane = sane && Within(z, MAX_ALTITUDE);
                }
                break;
            case 3:
                if (!ReadFloat(&reader, &a) || !ReadFloat(&reader, &z) || !ReadFloat(&reader, &t)) {
                    return 0;
                }
                Update(&filter, &sane, a, ((opcode & 8u) != 0u) ? FusionAltitudeNaN() : z, t);
                break;
            default:
                if (!ReadFloat(&reader, &a) || !ReadFloat(&reader, &z)) {
                    return 0;
                }
                Update(&filter, &sane, a, ((opcode & 8u) != 0u) ? FusionAltitudeNaN() : z, loopDt);
                break;
        }
        if (status != FusionAltitudeComplementaryStatusOk) {
            CHECK(memcmp(&before, &filter, sizeof(before)) == 0);
        }
        (void) FusionAltitudeComplementaryStatusMessage(status);
        if (sane) {
            CHECK(StateBounded(&filter));
        }
    }
    return 0;
}
