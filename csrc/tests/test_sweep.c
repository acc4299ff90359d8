/**
 * @file test_sweep.c
 * @brief Unit tests of fusion_altitude_sweep.h: every column equals
 * FusionAltitudeUpdate run alone, bit for bit; rejected inputs touch nothing.
 * Prints "N passed, M failed"; exits non-zero on any failure.
 */

#include "fusion_altitude_sweep.h"
#include "test_harness.h"

#include <string.h>

#define SAMPLES 3000
#define SETTINGS 41 /* one full 32-lane chunk and a partial one */

static float accel[SAMPLES], baro[SAMPLES], dt[SAMPLES], reference[SAMPLES];
static float kh[SETTINGS], kv[SETTINGS], kb[SETTINGS];
static float state[4][SETTINGS];
static float outputs[4][SAMPLES * SETTINGS];

/* A deterministic pseudo-random sequence in [-1, 1) (no libm, no rand()). */
static float Noise(uint32_t *const seed) {
    *seed = *seed * 1664525u + 1013904223u;
    return (float) (*seed >> 8) / 8388608.0f - 1.0f;
}

static void MakeInputs(void) {
    uint32_t seed = 12345u;
    float altitude = 30.0f;
    for (int t = 0; t < SAMPLES; t++) {
        accel[t] = 2.0f * Noise(&seed);
        altitude += 0.05f * Noise(&seed);
        baro[t] = (t % 3 == 0) ? altitude : FusionAltitudeNaN();
        dt[t] = 0.01f + 0.004f * Noise(&seed);
        reference[t] = (t % 50 == 7) ? FusionAltitudeNaN() : altitude;
    }
    for (int k = 0; k < SETTINGS; k++) {
        FusionAltitudeSettings settings = FusionAltitudeSettingsDefault();
        (void) FusionAltitudeSettingsFromBandwidth(&settings, 0.2f + 0.2f * (float) k, 0.7f, 0.04f + 0.04f * (float) k);
        kh[k] = settings.positionGain;
        kv[k] = settings.velocityGain;
        kb[k] = settings.biasGain;
    }
}

static FusionAltitudeSweep NewSweep(void) {
    FusionAltitudeSweep sweep = {SETTINGS, kh, kv, kb, state[0], state[1], state[2], state[3], 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0u, 0u,
                                 false, false, 0u, 0u};
    FusionAltitudeSweepInitialise(&sweep);
    return sweep;
}

static bool SameBits(const float a, const float b) {
    return FusionAltitudeFloatBits(a) == FusionAltitudeFloatBits(b);
}

static void EveryColumnEqualsTheSingleFilter(void) {
    FusionAltitudeSweep sweep = NewSweep();
    CHECK(sweep.gapPeriod == FUSION_ALTITUDE_DEFAULT_GAP_PERIOD);
    const FusionAltitudeSweepOutputs out = {outputs[0], outputs[1], outputs[2], outputs[3], SETTINGS};
    size_t bad = 0;
    CHECK(FusionAltitudeSweepUpdate(&sweep, accel, baro, dt, 1, SAMPLES, &out, NULL, &bad) == FusionAltitudeStatusOk);
    for (int k = 0; k < SETTINGS; k++) {
        FusionAltitude single;
        FusionAltitudeInitialise(&single);
        const FusionAltitudeSettings settings = {kh[k], kv[k], kb[k], FUSION_ALTITUDE_DEFAULT_GAP_PERIOD, FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT};
        (void) FusionAltitudeSetSettings(&single, &settings);
        bool same = true;
        for (int t = 0; t < SAMPLES; t++) {
            (void) FusionAltitudeUpdate(&single, accel[t], baro[t], dt[t]);
            const size_t i = (size_t) t * SETTINGS + (size_t) k;
            same = same && SameBits(outputs[0][i], single.altitude) && SameBits(outputs[1][i], single.verticalVelocity) &&
                   SameBits(outputs[2][i], single.accelBias) && SameBits(outputs[3][i], single.baroResidual);
        }
        CHECK(same);
        CHECK(SameBits(state[0][k], single.altitude) && SameBits(state[2][k], single.accelBias));
    }
    CHECK(sweep.referenceSet);
}

static void MetricsMatchTheOutputs(void) {
    float sums[5][SETTINGS];
    memset(sums, 0, sizeof(sums));
    FusionAltitudeSweep sweep = NewSweep();
    FusionAltitudeSweepMetrics metrics = {reference, NULL, sums[0], sums[1], sums[2], sums[3], sums[4], 0, 0};
    size_t bad = 0;
    CHECK(FusionAltitudeSweepUpdate(&sweep, accel, baro, dt, 1, SAMPLES, NULL, &metrics, &bad) == FusionAltitudeStatusOk);
    FusionAltitudeSweepFlushMetrics(&sweep, &metrics);
    CHECK(metrics.metricSamples == SAMPLES - SAMPLES / 50);
    for (int k = 0; k < SETTINGS; k++) {
        float largest = 0.0f;
        for (int t = 0; t < SAMPLES; t++) {
            if (FusionAltitudeIsFinite(reference[t])) {
                const float error = outputs[0][(size_t) t * SETTINGS + (size_t) k] - reference[t];
                const float absolute = error < 0.0f ? -error : error;
                largest = absolute > largest ? absolute : largest;
            }
        }
        CHECK(SameBits(sums[2][k], largest));
        CHECK(sums[1][k] >= 0.0f);
    }
}

static void RejectedSampleTouchesNothing(void) {
    FusionAltitudeSweep sweep = NewSweep();
    float before[4][SETTINGS];
    memcpy(before, state, sizeof(before));
    const float saved = accel[1234];
    accel[1234] = FusionAltitudeNaN();
    size_t bad = 0;
    CHECK(FusionAltitudeSweepUpdate(&sweep, accel, baro, dt, 1, SAMPLES, NULL, NULL, &bad) == FusionAltitudeStatusInvalidAccel);
    CHECK(bad == 1234u);
    CHECK(memcmp(before, state, sizeof(before)) == 0);
    CHECK(!sweep.referenceSet);
    accel[1234] = saved;
}

static void ScalarDtUsesStrideZero(void) {
    FusionAltitudeSweep sweep = NewSweep();
    const float step = 0.01f;
    size_t bad = 0;
    CHECK(FusionAltitudeSweepUpdate(&sweep, accel, baro, &step, 0, SAMPLES, NULL, NULL, &bad) == FusionAltitudeStatusOk);
    FusionAltitude single;
    FusionAltitudeInitialise(&single);
    const FusionAltitudeSettings settings = {kh[5], kv[5], kb[5], FUSION_ALTITUDE_DEFAULT_GAP_PERIOD, FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT};
    (void) FusionAltitudeSetSettings(&single, &settings);
    for (int t = 0; t < SAMPLES; t++) {
        (void) FusionAltitudeUpdate(&single, accel[t], baro[t], step);
    }
    CHECK(SameBits(state[0][5], single.altitude));
}

/* Gaps (dt above the gap period, with and without a baro sample on the gap
 * step) restart every column exactly as FusionAltitudeUpdate does, split
 * over two calls so the shared gap state also carries across calls. */
static void EveryColumnRestartsAfterAGapAsTheSingleFilter(void) {
    static float gapDt[SAMPLES];
    for (int t = 0; t < SAMPLES; t++) {
        gapDt[t] = dt[t];
    }
    gapDt[700] = 2.0f;  /* no baro on this step (700 % 3 != 0) */
    gapDt[1500] = 0.9f; /* a baro sample on this step */
    gapDt[1501] = 0.6f; /* a gap right after the restart */
    gapDt[2200] = 0.4f; /* below the gap period: integrated */
    FusionAltitudeSweep sweep = NewSweep();
    sweep.gapPeriod = 0.5f;
    const FusionAltitudeSweepOutputs out = {outputs[0], outputs[1], outputs[2], outputs[3], SETTINGS};
    const FusionAltitudeSweepOutputs rest = {&outputs[0][1000 * SETTINGS], &outputs[1][1000 * SETTINGS], &outputs[2][1000 * SETTINGS],
                                             &outputs[3][1000 * SETTINGS], SETTINGS};
    size_t bad = 0;
    CHECK(FusionAltitudeSweepUpdate(&sweep, accel, baro, gapDt, 1, 1000, &out, NULL, &bad) == FusionAltitudeStatusOk);
    CHECK(FusionAltitudeSweepUpdate(&sweep, &accel[1000], &baro[1000], &gapDt[1000], 1, SAMPLES - 1000, &rest, NULL, &bad) ==
          FusionAltitudeStatusOk);
    for (int k = 0; k < SETTINGS; k++) {
        FusionAltitude single;
        FusionAltitudeInitialise(&single);
        const FusionAltitudeSettings settings = {kh[k], kv[k], kb[k], 0.5f, FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT};
        (void) FusionAltitudeSetSettings(&single, &settings);
        bool same = true;
        for (int t = 0; t < SAMPLES; t++) {
            (void) FusionAltitudeUpdate(&single, accel[t], baro[t], gapDt[t]);
            const size_t i = (size_t) t * SETTINGS + (size_t) k;
            same = same && SameBits(outputs[0][i], single.altitude) && SameBits(outputs[1][i], single.verticalVelocity) &&
                   SameBits(outputs[2][i], single.accelBias) && SameBits(outputs[3][i], single.baroResidual);
        }
        CHECK(same);
        CHECK(FusionAltitudeGetGapCount(&single) == 3u);
    }
    CHECK(sweep.gapCount == 3u);
    CHECK(sweep.referenceSet);
}

int main(void) {
    MakeInputs();
    RUN(EveryColumnEqualsTheSingleFilter);
    RUN(MetricsMatchTheOutputs);
    RUN(RejectedSampleTouchesNothing);
    RUN(ScalarDtUsesStrideZero);
    RUN(EveryColumnRestartsAfterAGapAsTheSingleFilter);
    return TestSummary();
}
