/**
 * @file test_complementary.c
 * @brief Unit tests of fusion_altitude_complementary.h, built by
 * tests/test_c_core.py with gcc and clang (C99 and as C++), strict warnings,
 * and under ASan + UBSan. Prints "N passed, M failed".
 */

#include "fusion_altitude_complementary.h"
#include "test_harness.h"

#include <math.h>
#include <string.h>

static float Infinity(void) {
    const uint32_t bits = 0x7F800000u;
    float value;
    memcpy(&value, &bits, sizeof(value));
    return value;
}

static FusionAltitudeComplementary Running(void) {
    FusionAltitudeComplementary filter;
    memset(&filter, 0, sizeof(filter));
    FusionAltitudeComplementaryInitialise(&filter);
    for (int i = 0; i < 100; i++) {
        (void) FusionAltitudeComplementaryUpdate(&filter, 0.3f, 10.0f + 0.01f * (float) i, 0.01f);
    }
    return filter;
}

static void DefaultsAreTheWriteUpsCoefficientsAt100Hz(void) {
    const FusionAltitudeComplementarySettings s = FusionAltitudeComplementarySettingsDefault();
    CHECK(!s.perSampleCoefficients);
    CHECK(s.velocityCoefficient == 0.999f);
    CHECK(s.altitudeCoefficient == 0.998f);
    CHECK(fabsf(s.velocityTimeConstant / (s.velocityTimeConstant + 0.01f) - 0.999f) < 1e-6f);
    CHECK(fabsf(s.altitudeTimeConstant / (s.altitudeTimeConstant + 0.01f) - 0.998f) < 1e-6f);
    CHECK(FusionAltitudeComplementarySettingsCheck(&s) == FusionAltitudeComplementaryStatusOk);
}

static void FirstBaroSampleSetsTheReference(void) {
    FusionAltitudeComplementary filter;
    FusionAltitudeComplementaryInitialise(&filter);
    CHECK(FusionAltitudeComplementaryUpdate(&filter, 1.0f, FUSION_ALTITUDE_NO_BARO, 0.01f) == FusionAltitudeComplementaryStatusOk);
    CHECK(!FusionAltitudeComplementaryIsReferenceSet(&filter));
    CHECK(FusionAltitudeIsNaN(FusionAltitudeComplementaryGetBaroVelocity(&filter)));
    CHECK(FusionAltitudeComplementaryUpdate(&filter, 1.0f, 42.0f, 0.01f) == FusionAltitudeComplementaryStatusOk);
    CHECK(FusionAltitudeComplementaryIsReferenceSet(&filter));
    CHECK(FusionAltitudeComplementaryGetAltitude(&filter) == 42.0f);
    CHECK(FusionAltitudeComplementaryGetBaroFiltered(&filter) == 42.0f);
    CHECK(FusionAltitudeComplementaryGetVerticalVelocity(&filter) == 0.0f);
}

static void PerSampleStepFollowsTheWriteUp(void) {
    FusionAltitudeComplementary filter;
    FusionAltitudeComplementaryInitialise(&filter);
    FusionAltitudeComplementarySettings s = FusionAltitudeComplementarySettingsDefault();
    s.perSampleCoefficients = true;
    s.accelTimeConstant = 0.0f;
    s.baroTimeConstant = 0.0f;
    CHECK(FusionAltitudeComplementarySetSettings(&filter, &s) == FusionAltitudeComplementaryStatusOk);
    (void) FusionAltitudeComplementaryReset(&filter, 10.0f);
    filter.verticalVelocity = 0.5f;
    const float dt = 0.01f, a = 2.0f, z = 10.2f;
    CHECK(FusionAltitudeComplementaryUpdate(&filter, a, z, dt) == FusionAltitudeComplementaryStatusOk);
    const float vTemp = 0.5f + a * dt;
    const float vBaro = (z - 10.0f) / dt;
    const float v = 0.999f * vTemp + (1.0f - 0.999f) * vBaro;
    const float hTemp = 10.0f + vTemp * dt + 0.5f * a * dt * dt;
    const float h = 0.998f * hTemp + (1.0f - 0.998f) * z;
    CHECK(fabsf(FusionAltitudeComplementaryGetVerticalVelocity(&filter) - v) < 1e-6f);
    CHECK(fabsf(FusionAltitudeComplementaryGetAltitude(&filter) - h) < 1e-5f);
    CHECK(fabsf(FusionAltitudeComplementaryGetBaroVelocity(&filter) - vBaro) < 1e-3f);
}

static void StepWithoutBaroIntegratesOnly(void) {
    FusionAltitudeComplementary filter = Running();
    const float h = filter.altitude, v = filter.verticalVelocity;
    CHECK(FusionAltitudeComplementaryUpdate(&filter, 0.0f, FUSION_ALTITUDE_NO_BARO, 0.01f) == FusionAltitudeComplementaryStatusOk);
    const float aLp = filter.accelFiltered;
    CHECK(filter.verticalVelocity == v + aLp * 0.01f);
    CHECK(FusionAltitudeIsNaN(filter.baroVelocity));
    CHECK(h != filter.altitude);
    CHECK(filter.sinceBaro == 0.01f);
}

static void BaroStepSettlesWithTheDocumentedResponse(void) {
    /* h(t) = 1 - (p e^-pt - q e^-qt)/(p - q): 50 % near 2.1 s, overshoot ~12.5 % near 13.9 s */
    FusionAltitudeComplementary filter;
    FusionAltitudeComplementaryInitialise(&filter);
    (void) FusionAltitudeComplementaryUpdate(&filter, 0.0f, 0.0f, 0.01f);
    float peak = 0.0f;
    float half = -1.0f;
    for (int i = 1; i <= 6000; i++) {
        (void) FusionAltitudeComplementaryUpdate(&filter, 0.0f, 1.0f, 0.01f);
        const float h = FusionAltitudeComplementaryGetAltitude(&filter);
        if ((half < 0.0f) && (h >= 0.5f)) {
            half = 0.01f * (float) i;
        }
        peak = h > peak ? h : peak;
    }
    CHECK(half > 1.9f && half < 2.4f);
    CHECK(peak > 1.10f && peak < 1.15f);
    CHECK(fabsf(FusionAltitudeComplementaryGetAltitude(&filter) - 1.0f) < 0.02f);
}

static void BiasGivesTheDocumentedOffset(void) {
    FusionAltitudeComplementary filter;
    FusionAltitudeComplementaryInitialise(&filter);
    const float bias = 0.012f * FUSION_ALTITUDE_GRAVITY;
    for (int i = 0; i < 30000; i++) {
        (void) FusionAltitudeComplementaryUpdate(&filter, bias, 0.0f, 0.01f);
    }
    const float expected = bias * 9.99f * 4.99f;
    CHECK(fabsf(FusionAltitudeComplementaryGetAltitude(&filter) - expected) < 0.05f * expected);
}

static void SlowBaroUsesTheIntervalSinceTheLastSample(void) {
    FusionAltitudeComplementary a, b;
    FusionAltitudeComplementaryInitialise(&a);
    FusionAltitudeComplementaryInitialise(&b);
    (void) FusionAltitudeComplementaryUpdate(&a, 0.0f, 0.0f, 0.01f);
    (void) FusionAltitudeComplementaryUpdate(&b, 0.0f, 0.0f, 0.04f);
    for (int i = 0; i < 3; i++) {
        (void) FusionAltitudeComplementaryUpdate(&a, 0.0f, FUSION_ALTITUDE_NO_BARO, 0.01f);
    }
    (void) FusionAltitudeComplementaryUpdate(&a, 0.0f, 1.0f, 0.01f);
    (void) FusionAltitudeComplementaryUpdate(&b, 0.0f, 1.0f, 0.04f);
    CHECK(fabsf(a.baroFiltered - b.baroFiltered) < 1e-6f);
    CHECK(fabsf(a.baroVelocity - b.baroVelocity) < 1e-4f);
    CHECK(fabsf(a.altitude - b.altitude) < 1e-5f);
}

static void BadInputsLeaveTheStateUnchanged(void) {
    const float bad[][3] = {{FusionAltitudeNaN(), 1.0f, 0.01f}, {Infinity(), 1.0f, 0.01f}, {0.0f, Infinity(), 0.01f},
                            {0.0f, -Infinity(), 0.01f}, {0.0f, 1.0f, 0.0f}, {0.0f, 1.0f, -0.01f},
                            {0.0f, 1.0f, FusionAltitudeNaN()}, {0.0f, 1.0f, Infinity()}};
    const FusionAltitudeComplementaryStatus expected[] = {
        FusionAltitudeComplementaryStatusInvalidAccel, FusionAltitudeComplementaryStatusInvalidAccel,
        FusionAltitudeComplementaryStatusInvalidBaroAltitude, FusionAltitudeComplementaryStatusInvalidBaroAltitude,
        FusionAltitudeComplementaryStatusInvalidDt, FusionAltitudeComplementaryStatusInvalidDt,
        FusionAltitudeComplementaryStatusInvalidDt, FusionAltitudeComplementaryStatusInvalidDt};
    for (unsigned i = 0; i < sizeof(expected) / sizeof(expected[0]); i++) {
        FusionAltitudeComplementary filter = Running();
        const FusionAltitudeComplementary before = filter;
        CHECK(FusionAltitudeComplementaryUpdate(&filter, bad[i][0], bad[i][1], bad[i][2]) == expected[i]);
        CHECK(memcmp(&filter, &before, sizeof(filter)) == 0);
    }
    FusionAltitudeComplementary filter = Running();
    CHECK(FusionAltitudeComplementaryReset(&filter, FusionAltitudeNaN()) == FusionAltitudeComplementaryStatusInvalidBaroAltitude);
}

static void BadSettingsAreRejected(void) {
    FusionAltitudeComplementary filter = Running();
    const FusionAltitudeComplementary before = filter;
    FusionAltitudeComplementarySettings s = FusionAltitudeComplementarySettingsDefault();
    s.baroTimeConstant = -1.0f;
    CHECK(FusionAltitudeComplementarySetSettings(&filter, &s) == FusionAltitudeComplementaryStatusInvalidTimeConstant);
    s = FusionAltitudeComplementarySettingsDefault();
    s.velocityTimeConstant = Infinity();
    CHECK(FusionAltitudeComplementarySetSettings(&filter, &s) == FusionAltitudeComplementaryStatusInvalidTimeConstant);
    s = FusionAltitudeComplementarySettingsDefault();
    s.altitudeCoefficient = 1.5f;
    CHECK(FusionAltitudeComplementarySetSettings(&filter, &s) == FusionAltitudeComplementaryStatusInvalidCoefficient);
    s.altitudeCoefficient = FusionAltitudeNaN();
    CHECK(FusionAltitudeComplementarySetSettings(&filter, &s) == FusionAltitudeComplementaryStatusInvalidCoefficient);
    CHECK(memcmp(&filter, &before, sizeof(filter)) == 0);
    CHECK(strcmp(FusionAltitudeComplementaryStatusMessage(FusionAltitudeComplementaryStatusInvalidDt), "dt must be finite and > 0") == 0);
}

static void GapIsCountedAndNotIntegrated(void) {
    FusionAltitudeComplementary filter = Running();
    const FusionAltitudeComplementary before = filter;
    CHECK(FusionAltitudeComplementaryUpdate(&filter, 40.0f, FusionAltitudeNaN(), 2.0f) == FusionAltitudeComplementaryStatusOk);
    CHECK(FusionAltitudeComplementaryGetGapCount(&filter) == 1u);
    CHECK(!FusionAltitudeComplementaryIsReferenceSet(&filter));
    CHECK(filter.altitude == before.altitude && filter.verticalVelocity == before.verticalVelocity);
    CHECK(filter.accelFiltered == before.accelFiltered);
}

static void NextBaroAfterAGapRestartsWithTheMeanVelocity(void) {
    FusionAltitudeComplementary filter = Running();
    const float h = filter.altitude;
    CHECK(FusionAltitudeComplementaryUpdate(&filter, 0.0f, FusionAltitudeNaN(), 1.0f) == FusionAltitudeComplementaryStatusOk);
    CHECK(FusionAltitudeComplementaryUpdate(&filter, 0.0f, h + 6.0f, 0.5f) == FusionAltitudeComplementaryStatusOk);
    CHECK(FusionAltitudeComplementaryIsReferenceSet(&filter));
    CHECK(FusionAltitudeComplementaryGetAltitude(&filter) == h + 6.0f);
    CHECK(FusionAltitudeComplementaryGetBaroFiltered(&filter) == h + 6.0f);
    CHECK(FusionAltitudeComplementaryGetVerticalVelocity(&filter) == ((h + 6.0f) - h) / 1.5f);
    CHECK(FusionAltitudeComplementaryGetBaroVelocity(&filter) == ((h + 6.0f) - h) / 1.5f);
    CHECK(filter.sinceBaro == 0.0f);
}

static void DtAtTheGapPeriodIsIntegrated(void) {
    FusionAltitudeComplementary filter = Running();
    CHECK(FusionAltitudeComplementaryUpdate(&filter, 0.0f, FusionAltitudeNaN(), 0.5f) == FusionAltitudeComplementaryStatusOk);
    CHECK(FusionAltitudeComplementaryGetGapCount(&filter) == 0u);
    CHECK(FusionAltitudeComplementaryIsReferenceSet(&filter));
}

static void GapPeriodMustBePositive(void) {
    FusionAltitudeComplementarySettings s = FusionAltitudeComplementarySettingsDefault();
    CHECK(s.gapPeriod == 0.5f);
    s.gapPeriod = 0.0f;
    CHECK(FusionAltitudeComplementarySettingsCheck(&s) == FusionAltitudeComplementaryStatusInvalidGapPeriod);
    s.gapPeriod = FusionAltitudeNaN();
    CHECK(FusionAltitudeComplementarySettingsCheck(&s) == FusionAltitudeComplementaryStatusInvalidGapPeriod);
    s.gapPeriod = Infinity();
    CHECK(FusionAltitudeComplementarySettingsCheck(&s) == FusionAltitudeComplementaryStatusOk);
}

static void BaroTimeoutFlagsCountsAndDecaysTheVelocity(void) {
    FusionAltitudeComplementary filter = Running();
    int steps = 0;
    while (!FusionAltitudeComplementaryIsBaroTimedOut(&filter) && (steps < 1000)) {
        CHECK(FusionAltitudeComplementaryUpdate(&filter, 1.0f, FusionAltitudeNaN(), 0.01f) == FusionAltitudeComplementaryStatusOk);
        steps++;
    }
    CHECK(steps >= 195 && steps <= 201); /* 2 s since the latest baro sample, in 0.01 s float32 steps */
    CHECK(FusionAltitudeComplementaryGetBaroTimeouts(&filter) == 1u);
    const float v = filter.verticalVelocity;
    const float h = filter.altitude;
    const float aLp = filter.accelFiltered;
    CHECK(FusionAltitudeComplementaryUpdate(&filter, 50.0f, FusionAltitudeNaN(), 0.01f) == FusionAltitudeComplementaryStatusOk);
    CHECK(filter.verticalVelocity == v * (2.0f / (2.0f + 0.01f)));
    CHECK(filter.altitude == h + filter.verticalVelocity * 0.01f);
    CHECK(filter.accelFiltered == aLp); /* the accel is not integrated any more */
    for (int i = 0; i < 100000; i++) {
        CHECK(FusionAltitudeComplementaryUpdate(&filter, 50.0f, FusionAltitudeNaN(), 0.01f) == FusionAltitudeComplementaryStatusOk);
    }
    const float moved = (filter.altitude - h) * ((v < 0.0f) ? -1.0f : 1.0f);
    CHECK((moved >= 0.0f) && (moved <= ((v < 0.0f) ? -v : v) * 2.0f + 0.01f)); /* at most |v| * T further */
}

static void FirstBaroAfterATimeoutRestartsAtIt(void) {
    FusionAltitudeComplementary filter = Running();
    for (int i = 0; i < 300; i++) {
        CHECK(FusionAltitudeComplementaryUpdate(&filter, 1.0f, FusionAltitudeNaN(), 0.01f) == FusionAltitudeComplementaryStatusOk);
    }
    const float v = filter.verticalVelocity;
    CHECK(FusionAltitudeComplementaryUpdate(&filter, 1.0f, 42.0f, 0.01f) == FusionAltitudeComplementaryStatusOk);
    CHECK(!FusionAltitudeComplementaryIsBaroTimedOut(&filter));
    CHECK(FusionAltitudeComplementaryGetAltitude(&filter) == 42.0f && FusionAltitudeComplementaryGetBaroFiltered(&filter) == 42.0f);
    CHECK(FusionAltitudeComplementaryGetVerticalVelocity(&filter) == v);
    CHECK(FusionAltitudeComplementaryGetGapCount(&filter) == 0u);
}

static void BaroTimeoutMustBePositive(void) {
    FusionAltitudeComplementarySettings settings = FusionAltitudeComplementarySettingsDefault();
    CHECK(settings.baroTimeout == 2.0f);
    settings.baroTimeout = 0.0f;
    CHECK(FusionAltitudeComplementarySettingsCheck(&settings) == FusionAltitudeComplementaryStatusInvalidBaroTimeout);
    settings.baroTimeout = FusionAltitudeNaN();
    CHECK(FusionAltitudeComplementarySettingsCheck(&settings) == FusionAltitudeComplementaryStatusInvalidBaroTimeout);
    settings.baroTimeout = FusionAltitudeInfinity();
    CHECK(FusionAltitudeComplementarySettingsCheck(&settings) == FusionAltitudeComplementaryStatusOk);
}

/* A pseudo-random float in [0, 1) from a 32-bit LCG (no libm). */
static float Random(uint32_t *const seed) {
    *seed = *seed * 1664525u + 1013904223u;
    return (float) (*seed >> 8) / 16777216.0f;
}

static void TelemetryLikeStepsStayFiniteAndBounded(void) {
    /* steps 0.1-4 s (most 0.1 s), baro on 90 % of them within 1 m of a true altitude moving at most 3 m/s, accel
     * +-2 m/s^2 noise, a 1 s gap period: |h - truth| stays below 100 m (measured 32 m; the blend is stable at every
     * dt, but with +-20 m/s^2 the 10 s velocity blend lets the integrated noise reach 240 m) */
    FusionAltitudeComplementary filter = Running();
    filter.settings.gapPeriod = 1.0f;
    uint32_t seed = 777u;
    float truth = filter.altitude;
    float worst = 0.0f;
    for (int k = 0; k < 20000; k++) {
        const float u = Random(&seed);
        const float dt = (u < 0.6f) ? 0.1f : ((u < 0.85f) ? (0.1f + 0.9f * Random(&seed)) : (0.5f + 3.5f * Random(&seed)));
        truth += (6.0f * Random(&seed) - 3.0f) * dt;
        const float baro = (Random(&seed) < 0.9f) ? (truth + 2.0f * Random(&seed) - 1.0f) : FusionAltitudeNaN();
        CHECK(FusionAltitudeComplementaryUpdate(&filter, 4.0f * Random(&seed) - 2.0f, baro, dt) == FusionAltitudeComplementaryStatusOk);
        const float error = filter.altitude - truth;
        worst = (error > worst) ? error : ((-error > worst) ? -error : worst);
    }
    CHECK(worst < 100.0f);
}

int main(void) {
    RUN(DefaultsAreTheWriteUpsCoefficientsAt100Hz);
    RUN(FirstBaroSampleSetsTheReference);
    RUN(PerSampleStepFollowsTheWriteUp);
    RUN(StepWithoutBaroIntegratesOnly);
    RUN(BaroStepSettlesWithTheDocumentedResponse);
    RUN(BiasGivesTheDocumentedOffset);
    RUN(SlowBaroUsesTheIntervalSinceTheLastSample);
    RUN(BadInputsLeaveTheStateUnchanged);
    RUN(BadSettingsAreRejected);
    RUN(GapIsCountedAndNotIntegrated);
    RUN(NextBaroAfterAGapRestartsWithTheMeanVelocity);
    RUN(DtAtTheGapPeriodIsIntegrated);
    RUN(GapPeriodMustBePositive);
    RUN(BaroTimeoutFlagsCountsAndDecaysTheVelocity);
    RUN(FirstBaroAfterATimeoutRestartsAtIt);
    RUN(BaroTimeoutMustBePositive);
    RUN(TelemetryLikeStepsStayFiniteAndBounded);
    return TestSummary();
}
