/**
 * @file test_alphabeta.c
 * @brief Unit tests of fusion_altitude_alphabeta.h, built by
 * tests/test_c_core.py with gcc and clang (C99 and as C++), strict warnings,
 * and under ASan + UBSan. Prints "N passed, M failed".
 */

#include "fusion_altitude_alphabeta.h"
#include "test_harness.h"

#include <math.h>
#include <string.h>

static FusionAltitudeAlphaBetaMeasurements Baro(const float baro) {
    FusionAltitudeAlphaBetaMeasurements m = FusionAltitudeAlphaBetaMeasurementsNone();
    m.baroAltitude = baro;
    return m;
}

static FusionAltitudeAlphaBeta Running(void) {
    FusionAltitudeAlphaBeta fusion;
    memset(&fusion, 0, sizeof(fusion));
    FusionAltitudeAlphaBetaInitialise(&fusion);
    for (int i = 0; i < 200; i++) {
        FusionAltitudeAlphaBetaMeasurements m = Baro(10.0f + 0.01f * (float) i);
        m.lidarAltitude = 10.0f + 0.01f * (float) i;
        m.gpsAltitude = (i % 20 == 0) ? 11.0f : FusionAltitudeNaN();
        (void) FusionAltitudeAlphaBetaUpdate(&fusion, 0.0f, 0.01f, &m);
    }
    return fusion;
}

static void GainsAreTheLeastSquaresLineFit(void) {
    float alpha, beta;
    FusionAltitudeAlphaBetaGains(2, &alpha, &beta);
    CHECK(alpha == 1.0f && beta == 1.0f);
    FusionAltitudeAlphaBetaGains(10, &alpha, &beta);
    CHECK(fabsf(alpha - 38.0f / 110.0f) < 1e-7f && fabsf(beta - 6.0f / 110.0f) < 1e-7f);
    /* Least-squares line through the Q points (k, y_k), k = 1..Q, predicted at k = Q, for y = k^2 (not a line) */
    for (int32_t q = 2; q <= 30; q++) {
        /* A filter of depth Q started from an exact line tracks a line exactly: residual 0 keeps it. */
        FusionAltitudeAlphaBetaGains(q, &alpha, &beta);
        CHECK(alpha > 0.0f && alpha <= 1.0f && beta > 0.0f && beta < 4.0f - 2.0f * alpha);
        CHECK(beta <= alpha * alpha / (2.0f - alpha) * 1.0001f + 1e-6f || q == 2); /* not underdamped */
    }
}

static void DefaultsAreTheWriteUpsTables(void) {
    const FusionAltitudeAlphaBetaSettings s = FusionAltitudeAlphaBetaSettingsDefault();
    CHECK(FusionAltitudeAlphaBetaSettingsCheck(&s) == FusionAltitudeAlphaBetaStatusOk);
    CHECK(s.sensors[FusionAltitudeAlphaBetaSensorImu].qualityMax == 4);
    CHECK(s.sensors[FusionAltitudeAlphaBetaSensorBaro].qualityMin == 10 && s.sensors[FusionAltitudeAlphaBetaSensorBaro].qualityMax == 60);
    CHECK(s.sensors[FusionAltitudeAlphaBetaSensorLidar].threshold == 0.5f && s.sensors[FusionAltitudeAlphaBetaSensorLidar].confidence == 10.0f);
    CHECK(s.sensors[FusionAltitudeAlphaBetaSensorGps].gapMax == 20.0f && s.sensors[FusionAltitudeAlphaBetaSensorGps].qualityMax == 120);
    CHECK(s.sensors[FusionAltitudeAlphaBetaSensorBaro].altitudeMin == -4.0f);
}

static void StartsOnTheFirstNonImuSample(void) {
    FusionAltitudeAlphaBeta fusion;
    FusionAltitudeAlphaBetaInitialise(&fusion);
    FusionAltitudeAlphaBetaMeasurements m = FusionAltitudeAlphaBetaMeasurementsNone();
    CHECK(FusionAltitudeAlphaBetaUpdate(&fusion, 1.0f, 0.01f, &m) == FusionAltitudeAlphaBetaStatusOk);
    CHECK(!FusionAltitudeAlphaBetaIsStarted(&fusion));
    m.baroAltitude = 10.0f;
    m.gpsAltitude = 20.0f;
    CHECK(FusionAltitudeAlphaBetaUpdate(&fusion, 1.0f, 0.01f, &m) == FusionAltitudeAlphaBetaStatusOk);
    CHECK(FusionAltitudeAlphaBetaIsStarted(&fusion));
    /* weights Qmin*confidence: baro 10*2 = 20, GPS 10*1 = 10 */
    CHECK(fabsf(FusionAltitudeAlphaBetaGetAltitude(&fusion) - (20.0f * 10.0f + 10.0f * 20.0f) / 30.0f) < 1e-5f);
    CHECK(FusionAltitudeAlphaBetaGetVerticalVelocity(&fusion) == 0.0f);
}

static void QualityRisesWhileAgreeingAndFallsOtherwise(void) {
    FusionAltitudeAlphaBeta fusion;
    FusionAltitudeAlphaBetaInitialise(&fusion);
    FusionAltitudeAlphaBetaMeasurements m = Baro(0.0f);
    for (int i = 0; i < 100; i++) {
        (void) FusionAltitudeAlphaBetaUpdate(&fusion, 0.0f, 0.01f, &m);
    }
    CHECK(FusionAltitudeAlphaBetaGetQuality(&fusion, FusionAltitudeAlphaBetaSensorBaro) == 60);
    CHECK(FusionAltitudeAlphaBetaGetQuality(&fusion, FusionAltitudeAlphaBetaSensorImu) == 4);
    CHECK(FusionAltitudeAlphaBetaGetWeight(&fusion, FusionAltitudeAlphaBetaSensorBaro) == 120.0f);
    m.baroAltitude = 3.0f; /* disagrees by more than the 1 m threshold */
    for (int i = 0; i < 5; i++) {
        (void) FusionAltitudeAlphaBetaUpdate(&fusion, 0.0f, 0.01f, &m);
    }
    CHECK(FusionAltitudeAlphaBetaGetQuality(&fusion, FusionAltitudeAlphaBetaSensorBaro) == 55);
}

static void SensorBeyondItsGapMaximumIsDroppedAndRecovered(void) {
    FusionAltitudeAlphaBeta fusion;
    FusionAltitudeAlphaBetaInitialise(&fusion);
    FusionAltitudeAlphaBetaMeasurements m = Baro(5.0f);
    m.lidarAltitude = 5.0f;
    for (int i = 0; i < 300; i++) {
        (void) FusionAltitudeAlphaBetaUpdate(&fusion, 0.0f, 0.01f, &m);
    }
    CHECK(FusionAltitudeAlphaBetaGetWeight(&fusion, FusionAltitudeAlphaBetaSensorLidar) == 80.0f);
    m.lidarAltitude = 15.0f; /* 10 m glitch: beyond the lidar's 6 m gap maximum */
    float worst = 0.0f;
    for (int i = 0; i < 100; i++) {
        (void) FusionAltitudeAlphaBetaUpdate(&fusion, 0.0f, 0.01f, &m);
        const float error = fabsf(FusionAltitudeAlphaBetaGetAltitude(&fusion) - 5.0f);
        worst = error > worst ? error : worst;
    }
    CHECK(FusionAltitudeAlphaBetaGetWeight(&fusion, FusionAltitudeAlphaBetaSensorLidar) == 0.0f);
    CHECK(FusionAltitudeAlphaBetaGetQuality(&fusion, FusionAltitudeAlphaBetaSensorLidar) == 2);
    CHECK(fabsf(FusionAltitudeAlphaBetaGetAltitude(&fusion) - 5.0f) < 0.1f);
    CHECK(worst < 3.0f);
    m.lidarAltitude = 5.0f;
    for (int i = 0; i < 100; i++) {
        (void) FusionAltitudeAlphaBetaUpdate(&fusion, 0.0f, 0.01f, &m);
    }
    CHECK(FusionAltitudeAlphaBetaGetWeight(&fusion, FusionAltitudeAlphaBetaSensorLidar) == 80.0f);
    CHECK(fabsf(FusionAltitudeAlphaBetaGetAltitude(&fusion) - 5.0f) < 0.05f);
}

static void SensorOutsideItsBandOrSilentHasNoWeight(void) {
    FusionAltitudeAlphaBeta fusion;
    FusionAltitudeAlphaBetaInitialise(&fusion);
    FusionAltitudeAlphaBetaMeasurements m = Baro(8.0f);
    m.sonarAltitude = 8.0f; /* above the sonar's 5 m band */
    m.lidarAltitude = 8.0f;
    for (int i = 0; i < 50; i++) {
        (void) FusionAltitudeAlphaBetaUpdate(&fusion, 0.0f, 0.01f, &m);
    }
    CHECK(FusionAltitudeAlphaBetaGetWeight(&fusion, FusionAltitudeAlphaBetaSensorSonar) == 0.0f);
    CHECK(FusionAltitudeAlphaBetaGetWeight(&fusion, FusionAltitudeAlphaBetaSensorLidar) > 0.0f);
    m.lidarAltitude = FusionAltitudeNaN();
    for (int i = 0; i < 160; i++) {
        (void) FusionAltitudeAlphaBetaUpdate(&fusion, 0.0f, 0.01f, &m);
    }
    CHECK(FusionAltitudeAlphaBetaGetWeight(&fusion, FusionAltitudeAlphaBetaSensorLidar) == 0.0f); /* silent > 1.5 s */
}

static void EverySensorDroppedMeansDeadReckoning(void) {
    FusionAltitudeAlphaBeta fusion = Running();
    FusionAltitudeAlphaBetaSettings s = FusionAltitudeAlphaBetaSettingsDefault();
    s.sensors[FusionAltitudeAlphaBetaSensorImu].confidence = 0.0f; /* the IMU channel gets no weight */
    CHECK(FusionAltitudeAlphaBetaSetSettings(&fusion, &s) == FusionAltitudeAlphaBetaStatusOk);
    FusionAltitudeAlphaBetaMeasurements none = FusionAltitudeAlphaBetaMeasurementsNone();
    for (int i = 0; i < 200; i++) {
        (void) FusionAltitudeAlphaBetaUpdate(&fusion, 0.0f, 0.01f, &none);
    }
    CHECK(fusion.totalWeight == 0.0f);
    const float h = fusion.altitude, v = fusion.verticalVelocity;
    (void) FusionAltitudeAlphaBetaUpdate(&fusion, 1.0f, 0.01f, &none);
    CHECK(fusion.verticalVelocity == v + 1.0f * 0.01f);
    CHECK(fusion.altitude == h + v * 0.01f + 0.5f * 1.0f * 0.01f * 0.01f);
}

static void BadInputsLeaveTheStateUnchanged(void) {
    const float inf = FusionAltitudeAlphaBetaInfinity();
    for (int k = 0; k < 7; k++) {
        FusionAltitudeAlphaBeta fusion = Running();
        const FusionAltitudeAlphaBeta before = fusion;
        FusionAltitudeAlphaBetaMeasurements m = Baro(1.0f);
        float accel = 0.0f, dt = 0.01f;
        FusionAltitudeAlphaBetaStatus expected = FusionAltitudeAlphaBetaStatusOk;
        switch (k) {
            case 0: accel = -inf; expected = FusionAltitudeAlphaBetaStatusInvalidAccel; break;
            case 1: dt = 0.0f; expected = FusionAltitudeAlphaBetaStatusInvalidDt; break;
            case 2: dt = FusionAltitudeNaN(); expected = FusionAltitudeAlphaBetaStatusInvalidDt; break;
            case 3: m.baroAltitude = inf; expected = FusionAltitudeAlphaBetaStatusInvalidBaroAltitude; break;
            case 4: m.lidarAltitude = -inf; expected = FusionAltitudeAlphaBetaStatusInvalidLidarAltitude; break;
            case 5: m.sonarAltitude = inf; expected = FusionAltitudeAlphaBetaStatusInvalidSonarAltitude; break;
            default: m.gpsAltitude = inf; expected = FusionAltitudeAlphaBetaStatusInvalidGpsAltitude; break;
        }
        CHECK(FusionAltitudeAlphaBetaUpdate(&fusion, accel, dt, &m) == expected);
        CHECK(memcmp(&fusion, &before, sizeof(fusion)) == 0);
    }
}

static void BadSettingsAreRejected(void) {
    FusionAltitudeAlphaBeta fusion = Running();
    const FusionAltitudeAlphaBeta before = fusion;
    FusionAltitudeAlphaBetaSettings s = FusionAltitudeAlphaBetaSettingsDefault();
    s.sensors[FusionAltitudeAlphaBetaSensorGps].threshold = 0.0f;
    CHECK(FusionAltitudeAlphaBetaSetSettings(&fusion, &s) == FusionAltitudeAlphaBetaStatusInvalidThreshold);
    s = FusionAltitudeAlphaBetaSettingsDefault();
    s.sensors[FusionAltitudeAlphaBetaSensorBaro].qualityMin = 1;
    CHECK(FusionAltitudeAlphaBetaSetSettings(&fusion, &s) == FusionAltitudeAlphaBetaStatusInvalidQuality);
    s = FusionAltitudeAlphaBetaSettingsDefault();
    s.sensors[FusionAltitudeAlphaBetaSensorBaro].qualityMax = 9;
    CHECK(FusionAltitudeAlphaBetaSetSettings(&fusion, &s) == FusionAltitudeAlphaBetaStatusInvalidQuality);
    s = FusionAltitudeAlphaBetaSettingsDefault();
    s.sensors[FusionAltitudeAlphaBetaSensorImu].confidence = -1.0f;
    CHECK(FusionAltitudeAlphaBetaSetSettings(&fusion, &s) == FusionAltitudeAlphaBetaStatusInvalidConfidence);
    s = FusionAltitudeAlphaBetaSettingsDefault();
    s.sensors[FusionAltitudeAlphaBetaSensorSonar].altitudeMax = -1.0f;
    CHECK(FusionAltitudeAlphaBetaSetSettings(&fusion, &s) == FusionAltitudeAlphaBetaStatusInvalidAltitudeBand);
    s = FusionAltitudeAlphaBetaSettingsDefault();
    s.sensors[FusionAltitudeAlphaBetaSensorSonar].gapMax = FusionAltitudeNaN();
    CHECK(FusionAltitudeAlphaBetaSetSettings(&fusion, &s) == FusionAltitudeAlphaBetaStatusInvalidGapMax);
    s = FusionAltitudeAlphaBetaSettingsDefault();
    s.sensors[FusionAltitudeAlphaBetaSensorLidar].timeout = FusionAltitudeAlphaBetaInfinity();
    CHECK(FusionAltitudeAlphaBetaSetSettings(&fusion, &s) == FusionAltitudeAlphaBetaStatusInvalidTimeout);
    CHECK(FusionAltitudeAlphaBetaInitialiseWith(&fusion, &s) == FusionAltitudeAlphaBetaStatusInvalidTimeout);
    CHECK(memcmp(&fusion, &before, sizeof(fusion)) == 0);
    s = FusionAltitudeAlphaBetaSettingsDefault();
    s.sensors[FusionAltitudeAlphaBetaSensorBaro].qualityMax = 20; /* narrower: quality clamped */
    CHECK(FusionAltitudeAlphaBetaSetSettings(&fusion, &s) == FusionAltitudeAlphaBetaStatusOk);
    CHECK(FusionAltitudeAlphaBetaGetQuality(&fusion, FusionAltitudeAlphaBetaSensorBaro) == 20);
}

static void GapIsCountedAndRestartsFromThatStepsSamplesWithTheMeanVelocity(void) {
    FusionAltitudeAlphaBeta fusion = Running();
    const float h = FusionAltitudeAlphaBetaGetAltitude(&fusion);
    FusionAltitudeAlphaBetaMeasurements m = Baro(h + 8.0f);
    CHECK(FusionAltitudeAlphaBetaUpdate(&fusion, 30.0f, 2.0f, &m) == FusionAltitudeAlphaBetaStatusOk);
    CHECK(FusionAltitudeAlphaBetaGetGapCount(&fusion) == 1u);
    CHECK(FusionAltitudeAlphaBetaIsStarted(&fusion));
    CHECK(FusionAltitudeAlphaBetaGetAltitude(&fusion) == h + 8.0f);
    CHECK(FusionAltitudeAlphaBetaGetVerticalVelocity(&fusion) == ((h + 8.0f) - h) / 2.0f);
    CHECK(FusionAltitudeAlphaBetaGetQuality(&fusion, FusionAltitudeAlphaBetaSensorBaro) == 10);
}

static void GapWithoutSamplesHoldsUntilTheNextSample(void) {
    FusionAltitudeAlphaBeta fusion = Running();
    const float h = FusionAltitudeAlphaBetaGetAltitude(&fusion);
    const FusionAltitudeAlphaBetaMeasurements none = FusionAltitudeAlphaBetaMeasurementsNone();
    CHECK(FusionAltitudeAlphaBetaUpdate(&fusion, 30.0f, 3.0f, &none) == FusionAltitudeAlphaBetaStatusOk);
    CHECK(FusionAltitudeAlphaBetaUpdate(&fusion, 30.0f, 0.5f, &none) == FusionAltitudeAlphaBetaStatusOk);
    CHECK(!FusionAltitudeAlphaBetaIsStarted(&fusion));
    CHECK(FusionAltitudeAlphaBetaGetAltitude(&fusion) == h);
    const FusionAltitudeAlphaBetaMeasurements m = Baro(h - 7.0f);
    CHECK(FusionAltitudeAlphaBetaUpdate(&fusion, 0.0f, 0.5f, &m) == FusionAltitudeAlphaBetaStatusOk);
    CHECK(FusionAltitudeAlphaBetaGetAltitude(&fusion) == h - 7.0f);
    CHECK(FusionAltitudeAlphaBetaGetVerticalVelocity(&fusion) == ((h - 7.0f) - h) / 4.0f);
    CHECK(FusionAltitudeAlphaBetaGetGapCount(&fusion) == 1u);
}

/* The baro drops out for 10 s and the IMU is the only channel left (weight
 * 0 once its gap exceeds its maximum): dead reckoning with a 1 m/s^2 accel
 * error stops after the gap period instead of running away, and the baro
 * re-acquires the altitude on its first sample back. */
static void DeadReckoningIsBoundedAndTheSensorReacquires(void) {
    FusionAltitudeAlphaBeta fusion;
    FusionAltitudeAlphaBetaInitialise(&fusion);
    for (int i = 0; i < 500; i++) {
        const FusionAltitudeAlphaBetaMeasurements m = Baro(20.0f);
        (void) FusionAltitudeAlphaBetaUpdate(&fusion, 0.0f, 0.01f, &m);
    }
    float worst = 0.0f;
    const FusionAltitudeAlphaBetaMeasurements none = FusionAltitudeAlphaBetaMeasurementsNone();
    for (int i = 0; i < 1000; i++) {
        (void) FusionAltitudeAlphaBetaUpdate(&fusion, 1.0f, 0.01f, &none);
        const float error = fabsf(FusionAltitudeAlphaBetaGetAltitude(&fusion) - 20.0f);
        worst = error > worst ? error : worst;
    }
    CHECK(!FusionAltitudeAlphaBetaIsStarted(&fusion));
    CHECK(worst < 0.5f * 1.0f * 3.1f * 3.1f); /* at most the 1.5 s timeout plus the 1.5 s gap period of coasting */
    const FusionAltitudeAlphaBetaMeasurements back = Baro(20.0f);
    (void) FusionAltitudeAlphaBetaUpdate(&fusion, 1.0f, 0.01f, &back);
    CHECK(FusionAltitudeAlphaBetaIsStarted(&fusion));
    CHECK(FusionAltitudeAlphaBetaGetAltitude(&fusion) == 20.0f);
    CHECK(FusionAltitudeAlphaBetaGetGapCount(&fusion) == 0u);
}

static void GapPeriodMustBePositive(void) {
    FusionAltitudeAlphaBetaSettings s = FusionAltitudeAlphaBetaSettingsDefault();
    CHECK(s.gapPeriod == 1.5f);
    s.gapPeriod = 0.0f;
    CHECK(FusionAltitudeAlphaBetaSettingsCheck(&s) == FusionAltitudeAlphaBetaStatusInvalidGapPeriod);
    s.gapPeriod = FusionAltitudeNaN();
    CHECK(FusionAltitudeAlphaBetaSettingsCheck(&s) == FusionAltitudeAlphaBetaStatusInvalidGapPeriod);
    s.gapPeriod = FusionAltitudeAlphaBetaInfinity();
    CHECK(FusionAltitudeAlphaBetaSettingsCheck(&s) == FusionAltitudeAlphaBetaStatusOk);
}

int main(void) {
    RUN(GainsAreTheLeastSquaresLineFit);
    RUN(DefaultsAreTheWriteUpsTables);
    RUN(StartsOnTheFirstNonImuSample);
    RUN(QualityRisesWhileAgreeingAndFallsOtherwise);
    RUN(SensorBeyondItsGapMaximumIsDroppedAndRecovered);
    RUN(SensorOutsideItsBandOrSilentHasNoWeight);
    RUN(EverySensorDroppedMeansDeadReckoning);
    RUN(BadInputsLeaveTheStateUnchanged);
    RUN(BadSettingsAreRejected);
    RUN(GapIsCountedAndRestartsFromThatStepsSamplesWithTheMeanVelocity);
    RUN(GapWithoutSamplesHoldsUntilTheNextSample);
    RUN(DeadReckoningIsBoundedAndTheSensorReacquires);
    RUN(GapPeriodMustBePositive);
    return TestSummary();
}
