/**
 * @file test_kalman.c
 * @brief Unit tests of fusion_altitude_kalman.h, built by
 * tests/test_kalman_c.py with gcc and clang (C99 and as C++), strict warnings,
 * and under ASan + UBSan. Prints "N passed, M failed" and exits non-zero on
 * any failure.
 *
 * With the argument "long" it runs only the covariance robustness test:
 * 10^7 steps at 1 kHz in each of three configurations, checking every 1000
 * steps that P is exactly symmetric, finite, with non-negative diagonal, and
 * positive semi-definite (Cholesky in double of the correlation matrix).
 */

#include "fusion_altitude_kalman.h"
#include "test_harness.h"

#include <math.h> /* the test only; the header uses no libm */
#include <string.h>

/* A firmware budget: the whole filter in under 320 bytes. */
typedef char kalmanFitsIn320Bytes[(sizeof(FusionAltitudeKalman) <= 320u) ? 1 : -1];

static float Infinity(void) {
    const uint32_t bits = 0x7F800000u;
    float value;
    memcpy(&value, &bits, sizeof(value));
    return value;
}

static float Absolute(const float value) {
    return value < 0.0f ? -value : value;
}

static bool SameBits(const FusionAltitudeKalman *const a, const FusionAltitudeKalman *const b) {
    return memcmp(a, b, sizeof(*a)) == 0;
}

static FusionAltitudeKalmanMeasurements Baro(const float z) {
    FusionAltitudeKalmanMeasurements m = FusionAltitudeKalmanMeasurementsNone();
    m.baroAltitude = z;
    return m;
}

/* Deterministic noise without libm: LCG, sum of 12 uniforms - 6 ~ N(0, 1). */
static uint32_t rngState = 12345u;

static float Uniform(void) {
    rngState = rngState * 1664525u + 1013904223u;
    return (float) (rngState >> 8) * (1.0f / 16777216.0f);
}

static float Gaussian(void) {
    float sum = 0.0f;
    for (int i = 0; i < 12; i++) {
        sum += Uniform();
    }
    return sum - 6.0f;
}

/* A filter in the middle of a run with all three sensors, for the rejection tests. */
static FusionAltitudeKalman RunningFilter(void) {
    FusionAltitudeKalman kalman;
    FusionAltitudeKalmanInitialise(&kalman);
    for (int i = 0; i < 500; i++) {
        FusionAltitudeKalmanMeasurements m = FusionAltitudeKalmanMeasurementsNone();
        const float h = 0.002f * (float) i;
        m.baroAltitude = 120.0f + h + 0.1f * Gaussian();
        m.rangeDistance = h + 0.2f + 0.02f * Gaussian();
        if (i % 20 == 0) {
            m.gpsAltitude = 160.0f + h + Gaussian();
            m.gpsSatellites = 9;
        }
        (void) FusionAltitudeKalmanUpdate(&kalman, 0.1f * Gaussian(), 0.01f, &m);
    }
    return kalman;
}

static void InitialiseIsOnTheGroundAtRestWithUnknownOffsets(void) {
    FusionAltitudeKalman kalman;
    FusionAltitudeKalmanInitialise(&kalman);
    const FusionAltitudeKalmanSettings s = FusionAltitudeKalmanGetSettings(&kalman);
    CHECK(s.gate == 5.0f && s.rejectionTimeout == 1.0f && s.gpsMinimumSatellites == 4);
    for (int i = 0; i < FUSION_ALTITUDE_KALMAN_STATES; i++) {
        CHECK(kalman.x[i] == 0.0f);
    }
    CHECK(kalman.P[0][0] == 0.1f * 0.1f);
    CHECK(kalman.P[1][1] == 1.0f);
    CHECK(kalman.P[4][4] == 0.2f * 0.2f);
    CHECK(kalman.P[2][2] == 0.0f && kalman.P[3][3] == 0.0f);
    CHECK(!kalman.baroInitialised && !kalman.gpsInitialised);
    CHECK(FusionAltitudeIsNaN(FusionAltitudeKalmanGetNis(&kalman, FusionAltitudeKalmanSensorBaro)));
}

static void PredictFollowsTheDocumentedEquations(void) {
    FusionAltitudeKalman kalman;
    FusionAltitudeKalmanInitialise(&kalman);
    kalman.x[1] = 0.5f;
    kalman.x[4] = 0.1f;
    const float a = 0.7f, dt = 0.02f;
    const float u = a - 0.1f;
    const float halfDt2 = 0.5f * dt * dt;
    const float h = 0.0f + 0.5f * dt + u * halfDt2;
    const float v = 0.5f + u * dt;
    CHECK(FusionAltitudeKalmanUpdate(&kalman, a, dt, NULL) == FusionAltitudeKalmanStatusOk);
    CHECK(FusionAltitudeKalmanGetHeightAboveGround(&kalman) == h);
    CHECK(FusionAltitudeKalmanGetVerticalVelocity(&kalman) == v);
    /* P = F P0 F^T + Q with P0 = diag(0.01, 1, 0, 0, 0.04), Q = N_a^2 (dt^3/4, dt^2/2; dt^2/2, dt) */
    const float q = 0.035f * 0.035f;
    const float phh = 0.01f + dt * dt * 1.0f + halfDt2 * halfDt2 * 0.04f + q * dt * dt * dt / 4.0f;
    const float pvv = 1.0f + dt * dt * 0.04f + q * dt;
    CHECK(Absolute(kalman.P[0][1] - (dt * 1.0f + halfDt2 * dt * 0.04f + q * dt * dt / 2.0f)) < 1e-9f);
    CHECK(Absolute(kalman.P[0][0] - phh) < 1e-9f);
    CHECK(Absolute(kalman.P[1][1] - pvv) < 1e-9f);
    CHECK(Absolute(kalman.P[0][4] + halfDt2 * 0.04f) < 1e-10f);
    CHECK(Absolute(kalman.P[1][4] + dt * 0.04f) < 1e-10f);
    CHECK(kalman.P[0][1] == kalman.P[1][0]);
}

static void FirstBaroSampleSetsTheOffsetNotTheHeight(void) {
    FusionAltitudeKalman kalman;
    FusionAltitudeKalmanInitialise(&kalman);
    const FusionAltitudeKalmanMeasurements m = Baro(1234.5f);
    CHECK(FusionAltitudeKalmanUpdate(&kalman, 0.0f, 0.01f, &m) == FusionAltitudeKalmanStatusOk);
    CHECK(kalman.baroInitialised);
    CHECK(FusionAltitudeKalmanGetHeightAboveGround(&kalman) == 0.0f);
    CHECK(FusionAltitudeKalmanGetBaroOffset(&kalman) == 1234.5f);
    CHECK(FusionAltitudeKalmanGetAltitude(&kalman) == 1234.5f);
    CHECK(kalman.P[2][2] == kalman.P[0][0] + 0.25f);
    CHECK(kalman.P[0][2] == -kalman.P[0][0]);
    CHECK(FusionAltitudeKalmanGetSensor(&kalman, FusionAltitudeKalmanSensorBaro).result == FusionAltitudeKalmanResultInitialised);
}

static void StationaryBaroAndRangeConverge(void) {
    FusionAltitudeKalman kalman;
    FusionAltitudeKalmanInitialise(&kalman);
    for (int i = 0; i < 3000; i++) {
        FusionAltitudeKalmanMeasurements m = Baro(250.0f);
        m.rangeDistance = 2.0f;
        (void) FusionAltitudeKalmanUpdate(&kalman, 0.05f, 0.01f, &m);
    }
    CHECK(Absolute(FusionAltitudeKalmanGetHeightAboveGround(&kalman) - 2.0f) < 1e-3f);
    CHECK(Absolute(FusionAltitudeKalmanGetAltitude(&kalman) - 250.0f) < 1e-2f);
    CHECK(Absolute(FusionAltitudeKalmanGetAccelBias(&kalman) - 0.05f) < 1e-3f);
    CHECK(Absolute(FusionAltitudeKalmanGetVerticalVelocity(&kalman)) < 1e-3f);
}

static void RejectedInputsLeaveTheStateBitIdentical(void) {
    const FusionAltitudeKalman before = RunningFilter();
    FusionAltitudeKalman kalman = before;
    FusionAltitudeKalmanMeasurements m = Baro(10.0f);
    const float nan = FusionAltitudeNaN();
    CHECK(FusionAltitudeKalmanUpdate(&kalman, nan, 0.01f, &m) == FusionAltitudeKalmanStatusInvalidAccel);
    CHECK(FusionAltitudeKalmanUpdate(&kalman, Infinity(), 0.01f, &m) == FusionAltitudeKalmanStatusInvalidAccel);
    CHECK(FusionAltitudeKalmanUpdate(&kalman, 0.0f, 0.0f, &m) == FusionAltitudeKalmanStatusInvalidDt);
    CHECK(FusionAltitudeKalmanUpdate(&kalman, 0.0f, -0.01f, &m) == FusionAltitudeKalmanStatusInvalidDt);
    CHECK(FusionAltitudeKalmanUpdate(&kalman, 0.0f, nan, &m) == FusionAltitudeKalmanStatusInvalidDt);
    m.baroAltitude = -Infinity();
    CHECK(FusionAltitudeKalmanUpdate(&kalman, 0.0f, 0.01f, &m) == FusionAltitudeKalmanStatusInvalidBaroAltitude);
    m = FusionAltitudeKalmanMeasurementsNone();
    m.gpsAltitude = Infinity();
    CHECK(FusionAltitudeKalmanUpdate(&kalman, 0.0f, 0.01f, &m) == FusionAltitudeKalmanStatusInvalidGpsAltitude);
    m.gpsAltitude = 100.0f;
    m.gpsVerticalAccuracy = 0.0f;
    CHECK(FusionAltitudeKalmanUpdate(&kalman, 0.0f, 0.01f, &m) == FusionAltitudeKalmanStatusInvalidGpsAccuracy);
    m.gpsVerticalAccuracy = Infinity();
    CHECK(FusionAltitudeKalmanUpdate(&kalman, 0.0f, 0.01f, &m) == FusionAltitudeKalmanStatusInvalidGpsAccuracy);
    CHECK(SameBits(&kalman, &before));
}

static void InvalidSettingsAreRejected(void) {
    FusionAltitudeKalman kalman = RunningFilter();
    const FusionAltitudeKalman before = kalman;
    FusionAltitudeKalmanSettings s = FusionAltitudeKalmanSettingsDefault();
    s.baroNoise = 0.0f;
    CHECK(FusionAltitudeKalmanSetSettings(&kalman, &s) == FusionAltitudeKalmanStatusInvalidNoise);
    s = FusionAltitudeKalmanSettingsDefault();
    s.accelNoise = -1.0f;
    CHECK(FusionAltitudeKalmanSettingsCheck(&s) == FusionAltitudeKalmanStatusInvalidNoise);
    s = FusionAltitudeKalmanSettingsDefault();
    s.rangeMaximum = s.rangeMinimum;
    CHECK(FusionAltitudeKalmanSettingsCheck(&s) == FusionAltitudeKalmanStatusInvalidRange);
    s = FusionAltitudeKalmanSettingsDefault();
    s.gpsNoiseBase = 0.0f;
    s.gpsNoiseSatellite = 0.0f;
    CHECK(FusionAltitudeKalmanSettingsCheck(&s) == FusionAltitudeKalmanStatusInvalidGps);
    s = FusionAltitudeKalmanSettingsDefault();
    s.gate = FusionAltitudeNaN();
    CHECK(FusionAltitudeKalmanSettingsCheck(&s) == FusionAltitudeKalmanStatusInvalidGate);
    s = FusionAltitudeKalmanSettingsDefault();
    s.groundEffectNoiseScale = 0.5f;
    CHECK(FusionAltitudeKalmanSetSettings(&kalman, &s) == FusionAltitudeKalmanStatusInvalidGroundEffect);
    CHECK(FusionAltitudeKalmanInitialiseWith(&kalman, &s) == FusionAltitudeKalmanStatusInvalidGroundEffect);
    CHECK(SameBits(&kalman, &before));
    for (int status = 0; status <= (int) FusionAltitudeKalmanStatusInvalidGroundEffect; status++) {
        CHECK(strcmp(FusionAltitudeKalmanStatusMessage((FusionAltitudeKalmanStatus) status), "unknown status") != 0);
    }
}

static void GpsJumpIsRejectedThenResetsItsOffsetWithoutMovingHeight(void) {
    FusionAltitudeKalman kalman = RunningFilter();
    const float h0 = FusionAltitudeKalmanGetHeightAboveGround(&kalman);
    const float og0 = FusionAltitudeKalmanGetGpsOffset(&kalman);
    int resets = 0;
    float worst = 0.0f;
    for (int i = 0; i < 300; i++) {
        FusionAltitudeKalmanMeasurements m = FusionAltitudeKalmanMeasurementsNone();
        m.baroAltitude = 120.0f + 1.0f;
        m.rangeDistance = 1.0f + 0.2f;
        if (i % 20 == 0) {
            m.gpsAltitude = 160.0f + 1.0f + 10.0f; /* 10 m jump */
            m.gpsSatellites = 9;
        }
        (void) FusionAltitudeKalmanUpdate(&kalman, 0.0f, 0.01f, &m);
        if (kalman.sensors[FusionAltitudeKalmanSensorGps].result == FusionAltitudeKalmanResultReset) {
            resets++;
        }
        const float error = Absolute(FusionAltitudeKalmanGetHeightAboveGround(&kalman) - 1.2f);
        worst = (i > 100 && error > worst) ? error : worst;
    }
    (void) h0;
    CHECK(resets == 1);
    CHECK(kalman.sensors[FusionAltitudeKalmanSensorGps].rejections >= 5);
    CHECK(worst < 0.05f);
    CHECK(Absolute(FusionAltitudeKalmanGetGpsOffset(&kalman) - og0 - 10.0f) < 1.0f);
}

static void TerrainStepMovesTheOffsetsNotTheAltitude(void) {
    FusionAltitudeKalman kalman;
    FusionAltitudeKalmanInitialise(&kalman);
    for (int i = 0; i < 2000; i++) {
        FusionAltitudeKalmanMeasurements m = Baro(100.0f + 3.0f);
        m.rangeDistance = 3.0f;
        (void) FusionAltitudeKalmanUpdate(&kalman, 0.0f, 0.01f, &m);
    }
    const float altitude = FusionAltitudeKalmanGetAltitude(&kalman);
    const float ob = FusionAltitudeKalmanGetBaroOffset(&kalman);
    bool reset = false;
    for (int i = 0; i < 300; i++) {
        FusionAltitudeKalmanMeasurements m = Baro(100.0f + 3.0f);
        m.rangeDistance = 2.0f; /* 1 m step up under the vehicle */
        (void) FusionAltitudeKalmanUpdate(&kalman, 0.0f, 0.01f, &m);
        if (kalman.sensors[FusionAltitudeKalmanSensorRange].result == FusionAltitudeKalmanResultReset) {
            reset = true;
            CHECK(FusionAltitudeKalmanGetHeightAboveGround(&kalman) == 2.0f);
        }
        CHECK(Absolute(FusionAltitudeKalmanGetAltitude(&kalman) - altitude) < 0.02f);
    }
    CHECK(reset);
    CHECK(Absolute(FusionAltitudeKalmanGetBaroOffset(&kalman) - ob - 1.0f) < 0.02f);
}

static void GroundEffectIgnoresSmallNegativeBaroInnovations(void) {
    FusionAltitudeKalman kalman;
    FusionAltitudeKalmanInitialise(&kalman);
    for (int i = 0; i < 1000; i++) {
        const FusionAltitudeKalmanMeasurements m = Baro(50.0f);
        (void) FusionAltitudeKalmanUpdate(&kalman, 0.0f, 0.01f, &m);
    }
    FusionAltitudeKalmanMeasurements m = Baro(50.0f - 0.4f); /* prop-wash: baro reads low */
    m.groundEffect = true;
    FusionAltitudeKalman plain = kalman;
    (void) FusionAltitudeKalmanUpdate(&kalman, 0.0f, 0.01f, &m);
    CHECK(FusionAltitudeKalmanGetSensor(&kalman, FusionAltitudeKalmanSensorBaro).innovation == 0.0f);
    m.groundEffect = false;
    (void) FusionAltitudeKalmanUpdate(&plain, 0.0f, 0.01f, &m);
    CHECK(FusionAltitudeKalmanGetSensor(&plain, FusionAltitudeKalmanSensorBaro).innovation < -0.39f);
    CHECK(FusionAltitudeKalmanGetAltitude(&plain) < FusionAltitudeKalmanGetAltitude(&kalman));
}

static void RangeOutsideLimitsAndTooFewSatellitesAreNotFused(void) {
    FusionAltitudeKalman kalman = RunningFilter();
    FusionAltitudeKalmanMeasurements m = FusionAltitudeKalmanMeasurementsNone();
    m.rangeDistance = 9.0f;
    m.gpsAltitude = 170.0f;
    m.gpsSatellites = 3;
    (void) FusionAltitudeKalmanUpdate(&kalman, 0.0f, 0.01f, &m);
    CHECK(kalman.sensors[FusionAltitudeKalmanSensorRange].result == FusionAltitudeKalmanResultUnusable);
    CHECK(kalman.sensors[FusionAltitudeKalmanSensorGps].result == FusionAltitudeKalmanResultUnusable);
    m.rangeDistance = Infinity();
    m.gpsSatellites = 4;
    m.gpsAltitude = 160.0f + 1.0f;
    (void) FusionAltitudeKalmanUpdate(&kalman, 0.0f, 0.01f, &m);
    CHECK(kalman.sensors[FusionAltitudeKalmanSensorRange].result == FusionAltitudeKalmanResultUnusable);
    CHECK(kalman.sensors[FusionAltitudeKalmanSensorGps].result == FusionAltitudeKalmanResultFused);
    CHECK(kalman.sensors[FusionAltitudeKalmanSensorGps].innovationVariance > 1.5f * 1.5f);
}

static void GpsSigmaFollowsSatellitesOrReportedAccuracy(void) {
    const FusionAltitudeKalmanSettings s = FusionAltitudeKalmanSettingsDefault();
    CHECK(FusionAltitudeKalmanGpsSigma(&s, FusionAltitudeNaN(), 4) == 1.5f);
    CHECK(FusionAltitudeKalmanGpsSigma(&s, FusionAltitudeNaN(), 16) == 1.25f);
    CHECK(FusionAltitudeKalmanGpsSigma(&s, FusionAltitudeNaN(), -1) == 1.5f);
    CHECK(FusionAltitudeKalmanGpsSigma(&s, FusionAltitudeNaN(), 1000) == 1.125f);
    CHECK(FusionAltitudeKalmanGpsSigma(&s, 2.5f, 16) == 2.5f);
}

static void DisabledBiasStaysExactlyZero(void) {
    FusionAltitudeKalmanSettings s = FusionAltitudeKalmanSettingsDefault();
    s.estimateAccelBias = false;
    FusionAltitudeKalman kalman;
    CHECK(FusionAltitudeKalmanInitialiseWith(&kalman, &s) == FusionAltitudeKalmanStatusOk);
    for (int i = 0; i < 2000; i++) {
        FusionAltitudeKalmanMeasurements m = Baro(10.0f);
        m.rangeDistance = 1.0f;
        (void) FusionAltitudeKalmanUpdate(&kalman, 0.2f, 0.01f, &m);
    }
    CHECK(FusionAltitudeKalmanGetAccelBias(&kalman) == 0.0f);
    for (int i = 0; i < FUSION_ALTITUDE_KALMAN_STATES; i++) {
        CHECK(kalman.P[4][i] == 0.0f && kalman.P[i][4] == 0.0f);
    }
    s.estimateAccelBias = true;
    CHECK(FusionAltitudeKalmanSetSettings(&kalman, &s) == FusionAltitudeKalmanStatusOk);
    CHECK(kalman.P[4][4] == 0.2f * 0.2f);
}

//------------------------------------------------------------------------------
// Long run: covariance stays symmetric positive semi-definite

/* Worst (most negative) Cholesky pivot of the correlation matrix of P, in
 * double; >= 0 means positive semi-definite. States with zero variance (an
 * offset not yet set, a disabled bias) are left out. */
static double CorrelationPivot(const FusionAltitudeKalman *const k) {
    int index[FUSION_ALTITUDE_KALMAN_STATES];
    int n = 0;
    for (int i = 0; i < FUSION_ALTITUDE_KALMAN_STATES; i++) {
        if (k->P[i][i] > 0.0f) {
            index[n++] = i;
        }
    }
    double L[FUSION_ALTITUDE_KALMAN_STATES][FUSION_ALTITUDE_KALMAN_STATES];
    double worst = 1.0;
    for (int i = 0; i < n; i++) {
        for (int j = 0; j <= i; j++) {
            const double pij = (double) k->P[index[i]][index[j]];
            double sum = pij / sqrt((double) k->P[index[i]][index[i]] * (double) k->P[index[j]][index[j]]);
            for (int m = 0; m < j; m++) {
                sum -= L[i][m] * L[j][m];
            }
            if (i == j) {
                worst = sum < worst ? sum : worst;
                L[i][i] = sqrt(sum > 1e-300 ? sum : 1e-300);
            } else {
                L[i][j] = sum / L[j][j];
            }
        }
    }
    return worst;
}

typedef struct {
    const char *name;
    bool rangefinder;
    bool gps;
    bool bias;
} LongConfiguration;

static bool LongRun(const LongConfiguration configuration) {
    FusionAltitudeKalmanSettings s = FusionAltitudeKalmanSettingsDefault();
    s.estimateAccelBias = configuration.bias;
    FusionAltitudeKalman kalman;
    (void) FusionAltitudeKalmanInitialiseWith(&kalman, &s);
    const float dt = 0.001f;
    const long steps = 10000000L;
    double h = 0.0, v = 0.0;
    double worstPivot = 1.0;
    float maxVariance = 0.0f;
    bool ok = true;
    for (long i = 0; i < steps; i++) {
        /* Truth: slow climbs and descents between 0 and ~14 m with a 200 s period. */
        const long phase = i % 200000L;
        const double a = (phase < 50000L) ? 0.004 : ((phase < 150000L) ? -0.004 : 0.004);
        v += a * 0.001;
        h += v * 0.001;
        FusionAltitudeKalmanMeasurements m = FusionAltitudeKalmanMeasurementsNone();
        if (i % 10 == 0) {
            m.baroAltitude = (float) (300.0 + h) + 0.3f * Gaussian() + 1e-6f * (float) (i / 1000);
            m.groundEffect = h < 0.5;
        }
        if (configuration.rangefinder && (i % 50 == 0)) {
            m.rangeDistance = (float) h + 0.03f * Gaussian();
        }
        if (configuration.gps && (i % 200 == 0) && ((i / 1000000L) % 4 != 3)) { /* outages */
            m.gpsAltitude = (float) (340.0 + h) + 1.2f * Gaussian() + (((i / 3000000L) % 2 == 1) ? 10.0f : 0.0f);
            m.gpsSatellites = 6 + (int32_t) ((i / 100000L) % 12);
        }
        const float accel = (float) a + 0.3f * Gaussian() + 0.05f;
        if (FusionAltitudeKalmanUpdate(&kalman, accel, dt, &m) != FusionAltitudeKalmanStatusOk) {
            printf("  %s: update rejected at step %ld\n", configuration.name, i);
            return false;
        }
        if (i % 1000 == 999) {
            for (int r = 0; r < FUSION_ALTITUDE_KALMAN_STATES; r++) {
                for (int c = 0; c < FUSION_ALTITUDE_KALMAN_STATES; c++) {
                    if (!FusionAltitudeIsFinite(kalman.P[r][c]) || (memcmp(&kalman.P[r][c], &kalman.P[c][r], sizeof(float)) != 0)) {
                        ok = false;
                    }
                }
                if (kalman.P[r][r] < 0.0f) {
                    ok = false;
                }
                maxVariance = kalman.P[r][r] > maxVariance ? kalman.P[r][r] : maxVariance;
            }
            const double pivot = CorrelationPivot(&kalman);
            worstPivot = pivot < worstPivot ? pivot : worstPivot;
            if (!ok || pivot < 0.0) {
                printf("  %s: covariance check failed at step %ld (pivot %g)\n", configuration.name, i, pivot);
                return false;
            }
        }
    }
    printf("  %s: %ld steps, worst correlation Cholesky pivot %.3g, largest variance %.3g, h %.3f (truth %.3f)\n",
           configuration.name, steps, worstPivot, (double) maxVariance, (double) FusionAltitudeKalmanGetHeightAboveGround(&kalman), h);
    return true;
}

static int RunLong(void) {
    const LongConfiguration configurations[] = {
        {"all sensors", true, true, true},
        {"baro only", false, false, true},
        {"baro + GPS, bias off", false, true, false},
    };
    int bad = 0;
    for (size_t i = 0; i < sizeof(configurations) / sizeof(configurations[0]); i++) {
        if (!LongRun(configurations[i])) {
            bad++;
        }
    }
    printf("long: %d of %d configurations kept P symmetric PSD\n", 3 - bad, 3);
    return bad == 0 ? 0 : 1;
}

static void GapIsCountedNotPredictedAndInflatesHeightAndVelocity(void) {
    FusionAltitudeKalman kalman = RunningFilter();
    const FusionAltitudeKalman before = kalman;
    CHECK(FusionAltitudeKalmanUpdate(&kalman, 50.0f, 2.0f, NULL) == FusionAltitudeKalmanStatusOk);
    CHECK(FusionAltitudeKalmanGetGapCount(&kalman) == 1u);
    CHECK(memcmp(kalman.x, before.x, sizeof(kalman.x)) == 0);
    const float heightSigma = FUSION_ALTITUDE_KALMAN_RESTART_VELOCITY_SIGMA * 2.0f;
    CHECK(kalman.P[0][0] == before.P[0][0] + heightSigma * heightSigma);
    CHECK(kalman.P[1][1] == before.P[1][1] + FUSION_ALTITUDE_KALMAN_RESTART_VELOCITY_SIGMA * FUSION_ALTITUDE_KALMAN_RESTART_VELOCITY_SIGMA);
    CHECK(kalman.P[0][1] == before.P[0][1] && kalman.P[1][0] == before.P[1][0]);
    CHECK(kalman.P[4][4] > before.P[4][4]); /* bias random walk over the gap */
    FusionAltitudeKalman atPeriod = before;
    CHECK(FusionAltitudeKalmanUpdate(&atPeriod, 0.0f, 0.5f, NULL) == FusionAltitudeKalmanStatusOk);
    CHECK(FusionAltitudeKalmanGetGapCount(&atPeriod) == 0u);
}

/* A vehicle climbing at 3 m/s, baro only at 100 Hz; 2 s of data lost while
 * it keeps climbing: the first samples after the gap pass the gate and the
 * altitude is back within 0.5 m of the truth within 2 s, bias untouched. */
static void GapInAClimbIsRecoveredWithinTwoSeconds(void) {
    FusionAltitudeKalman kalman;
    FusionAltitudeKalmanInitialise(&kalman);
    float t = 0.0f;
    for (int i = 0; i < 1000; i++) {
        const float truth = 50.0f + 3.0f * (t > 2.0f ? t - 2.0f : 0.0f);
        const FusionAltitudeKalmanMeasurements m = Baro(truth + 0.1f * Gaussian());
        (void) FusionAltitudeKalmanUpdate(&kalman, (i == 200) ? 300.0f : 0.0f, 0.01f, &m);
        t += 0.01f;
    }
    const float bias = FusionAltitudeKalmanGetAccelBias(&kalman);
    t += 2.0f;
    float worstAfter = 0.0f;
    int rejected = 0;
    for (int i = 0; i < 400; i++) {
        const float truth = 50.0f + 3.0f * (t - 2.0f);
        const FusionAltitudeKalmanMeasurements m = Baro(truth + 0.1f * Gaussian());
        (void) FusionAltitudeKalmanUpdate(&kalman, 0.0f, (i == 0) ? 2.01f : 0.01f, &m);
        rejected += (kalman.sensors[FusionAltitudeKalmanSensorBaro].result == FusionAltitudeKalmanResultRejected) ? 1 : 0;
        const float error = Absolute(FusionAltitudeKalmanGetAltitude(&kalman) - truth);
        worstAfter = (i >= 200 && error > worstAfter) ? error : worstAfter;
        t += 0.01f;
    }
    CHECK(FusionAltitudeKalmanGetGapCount(&kalman) == 1u);
    CHECK(rejected == 0);
    CHECK(worstAfter < 0.5f);
    CHECK(Absolute(FusionAltitudeKalmanGetAccelBias(&kalman) - bias) < 0.05f);
}

/* An accelerometer glitch burst (+20 m/s^2 for 0.5 s) throws the velocity
 * 9 m/s off (and the bias 0.3 m/s^2) while the vehicle hovers: the baro is
 * rejected until the timeout, then h, v and b are inflated with the reset,
 * and the filter is back (altitude within 0.5 m from 2 s after the burst,
 * velocity within 0.3 m/s from 3.5 s after) instead of re-basing the offset
 * around a wrong velocity. */
static void GlitchBurstIsRecoveredAfterTheRejectionTimeout(void) {
    FusionAltitudeKalman kalman;
    FusionAltitudeKalmanInitialise(&kalman);
    float worstLate = 0.0f;
    float worstVelocity = 0.0f;
    for (int i = 0; i < 1500; i++) {
        const float accel = (i >= 500 && i < 550) ? 20.0f : 0.05f * Gaussian();
        const FusionAltitudeKalmanMeasurements m = Baro(80.0f + 0.1f * Gaussian());
        (void) FusionAltitudeKalmanUpdate(&kalman, accel, 0.01f, &m);
        const float error = Absolute(FusionAltitudeKalmanGetAltitude(&kalman) - 80.0f);
        const float velocity = Absolute(FusionAltitudeKalmanGetVerticalVelocity(&kalman));
        worstLate = (i >= 750 && error > worstLate) ? error : worstLate;
        worstVelocity = (i >= 900 && velocity > worstVelocity) ? velocity : worstVelocity;
    }
    CHECK(kalman.sensors[FusionAltitudeKalmanSensorBaro].resets >= 1u);
    CHECK(worstLate < 0.5f);
    CHECK(worstVelocity < 0.3f);
}

int main(int argc, char **argv) {
    if ((argc > 1) && (strcmp(argv[1], "long") == 0)) {
        return RunLong();
    }
    RUN(InitialiseIsOnTheGroundAtRestWithUnknownOffsets);
    RUN(PredictFollowsTheDocumentedEquations);
    RUN(FirstBaroSampleSetsTheOffsetNotTheHeight);
    RUN(StationaryBaroAndRangeConverge);
    RUN(RejectedInputsLeaveTheStateBitIdentical);
    RUN(InvalidSettingsAreRejected);
    RUN(GpsJumpIsRejectedThenResetsItsOffsetWithoutMovingHeight);
    RUN(TerrainStepMovesTheOffsetsNotTheAltitude);
    RUN(GroundEffectIgnoresSmallNegativeBaroInnovations);
    RUN(RangeOutsideLimitsAndTooFewSatellitesAreNotFused);
    RUN(GpsSigmaFollowsSatellitesOrReportedAccuracy);
    RUN(DisabledBiasStaysExactlyZero);
    RUN(GapIsCountedNotPredictedAndInflatesHeightAndVelocity);
    RUN(GapInAClimbIsRecoveredWithinTwoSeconds);
    RUN(GlitchBurstIsRecoveredAfterTheRejectionTimeout);
    return TestSummary();
}
