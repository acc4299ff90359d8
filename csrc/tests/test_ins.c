/**
 * @file test_ins.c
 * @brief Unit tests of fusion_altitude_ins.h, built by tests/test_ins_c.py
 * with gcc and clang (C99, GNU modes, and as C++), strict warnings, and under
 * ASan + UBSan. Prints "N passed, M failed" and exits non-zero on any failure.
 *
 * With the argument "long" it runs only the covariance robustness test:
 * 10^7 steps at 1 kHz of a tumbling, climbing and resting vehicle in each of
 * two configurations, checking every 1000 steps that P is exactly
 * symmetric, finite, with non-negative diagonal, and positive semi-definite
 * (Cholesky in double of the correlation matrix).
 */

#include "fusion_altitude_ins.h"
#include "test_harness.h"

#include <math.h> /* the test's truth model; the header uses sqrtf only */
#include <string.h>

/* A firmware budget: the whole INS (settings, state, P) in at most 512 bytes. */
typedef char insFitsIn512Bytes[(sizeof(FusionAltitudeIns) <= 512u) ? 1 : -1];

static const float g = FUSION_ALTITUDE_GRAVITY;

static float Infinity(void) {
    const uint32_t bits = 0x7F800000u;
    float value;
    memcpy(&value, &bits, sizeof(value));
    return value;
}

static float Absolute(const float value) {
    return value < 0.0f ? -value : value;
}

static bool SameBits(const FusionAltitudeIns *const a, const FusionAltitudeIns *const b) {
    return memcmp(a, b, sizeof(*a)) == 0;
}

static FusionAltitudeInsVector Vector(const float x, const float y, const float z) {
    FusionAltitudeInsVector v;
    v.x = x;
    v.y = y;
    v.z = z;
    return v;
}

/* Deterministic noise: LCG, sum of 12 uniforms - 6 ~ N(0, 1). */
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

/*
 * Truth model in double: attitude quaternion integrated from a body rate,
 * vertical motion from a vertical acceleration; the IMU reads the body rate
 * plus bias and noise and the specific force R^T (0, 0, g + a) plus bias.
 */
typedef struct {
    double q[4];
    double h;
    double v;
} Truth;

static void TruthStep(Truth *const t, const double w[3], const double a, const double dt) {
    const double hx = 0.5 * dt * w[0], hy = 0.5 * dt * w[1], hz = 0.5 * dt * w[2];
    const double qw = t->q[0], qx = t->q[1], qy = t->q[2], qz = t->q[3];
    double q[4] = {qw - qx * hx - qy * hy - qz * hz, qx + qw * hx + qy * hz - qz * hy, qy + qw * hy - qx * hz + qz * hx,
                   qz + qw * hz + qx * hy - qy * hx};
    const double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int i = 0; i < 4; i++) {
        t->q[i] = q[i] / n;
    }
    t->h += t->v * dt + 0.5 * a * dt * dt;
    t->v += a * dt;
}

/* Body-frame specific force for vertical acceleration a (m/s^2), attitude t->q. */
static FusionAltitudeInsVector SpecificForce(const Truth *const t, const double a) {
    const double w = t->q[0], x = t->q[1], y = t->q[2], z = t->q[3];
    const double r0 = 2.0 * (x * z - w * y), r1 = 2.0 * (y * z + w * x), r2 = 1.0 - 2.0 * (x * x + y * y);
    const double up = 9.80665 + a;
    return Vector((float) (r0 * up), (float) (r1 * up), (float) (r2 * up));
}

/* Angle (rad) between the truth tilt and the estimate's: angle between their up-in-body vectors. */
static double TiltError(const Truth *const t, const FusionAltitudeIns *const ins) {
    const double w = t->q[0], x = t->q[1], y = t->q[2], z = t->q[3];
    const double a[3] = {2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)};
    float rf[3];
    FusionAltitudeInsUpInBody(ins->q, rf);
    const double r[3] = {(double) rf[0], (double) rf[1], (double) rf[2]};
    const double cx = a[1] * r[2] - a[2] * r[1], cy = a[2] * r[0] - a[0] * r[2], cz = a[0] * r[1] - a[1] * r[0];
    return asin(sqrt(cx * cx + cy * cy + cz * cz));
}

static void InitialiseIsUnalignedAtTheOriginWithTheDefaults(void) {
    FusionAltitudeIns ins;
    FusionAltitudeInsInitialise(&ins);
    const FusionAltitudeInsSettings s = FusionAltitudeInsGetSettings(&ins);
    CHECK(s.gapPeriod == 0.1f && s.baroNoise == 0.3f && s.stationaryWindow == 1.0f);
    CHECK(!ins.aligned && !ins.baroInitialised && !ins.magInitialised && !ins.stationary);
    CHECK(FusionAltitudeInsGetAltitude(&ins) == 0.0f && FusionAltitudeInsGetVerticalVelocity(&ins) == 0.0f);
    CHECK(FusionAltitudeInsGetQuaternion(&ins).w == 1.0f);
    CHECK(ins.P[0][0] == 0.05f * 0.05f && ins.P[3][3] == 0.01f * 0.01f && ins.P[6][6] == 0.0f && ins.P[7][7] == 0.25f);
    CHECK(FusionAltitudeInsGetGapCount(&ins) == 0u);
}

static void FirstUsableAccelSampleAlignsTheTiltWithZeroYaw(void) {
    FusionAltitudeIns ins;
    FusionAltitudeInsInitialise(&ins);
    /* free fall (|f| = 0) is not usable: ignored, nothing changes */
    const FusionAltitudeIns before = ins;
    CHECK(FusionAltitudeInsUpdate(&ins, Vector(0, 0, 0), Vector(0, 0, 0), FusionAltitudeInsNoMag(), FUSION_ALTITUDE_NO_BARO, 0.01f) ==
          FusionAltitudeInsStatusOk);
    CHECK(SameBits(&ins, &before));
    /* 30 deg roll: body up = (0, sin 30, cos 30) */
    CHECK(FusionAltitudeInsUpdate(&ins, Vector(0, 0, 0), Vector(0.0f, 0.5f * g, 0.8660254f * g), FusionAltitudeInsNoMag(),
                                  FUSION_ALTITUDE_NO_BARO, 0.01f) == FusionAltitudeInsStatusOk);
    CHECK(ins.aligned);
    const FusionAltitudeInsQuaternion q = FusionAltitudeInsGetQuaternion(&ins);
    /* rotation of 30 deg about x: (cos 15, sin 15, 0, 0) */
    CHECK(Absolute(q.w - 0.9659258f) < 1e-6f && Absolute(q.x - 0.2588190f) < 1e-6f && q.y == 0.0f && q.z == 0.0f);
}

static void RejectedInputsLeaveTheStateBitIdentical(void) {
    FusionAltitudeIns ins;
    FusionAltitudeInsInitialise(&ins);
    for (int i = 0; i < 200; i++) {
        (void) FusionAltitudeInsUpdate(&ins, Vector(0.01f, 0, 0), Vector(0.1f, 0, g), Vector(1, 0, -1), (i % 5 == 0) ? 50.0f : FUSION_ALTITUDE_NO_BARO,
                                       0.01f);
    }
    const FusionAltitudeIns before = ins;
    const float nan = FusionAltitudeNaN();
    const FusionAltitudeInsVector ok = Vector(0, 0, g);
    const FusionAltitudeInsVector none = FusionAltitudeInsNoMag();
    CHECK(FusionAltitudeInsUpdate(&ins, Vector(nan, 0, 0), ok, none, 1.0f, 0.01f) == FusionAltitudeInsStatusInvalidGyro);
    CHECK(FusionAltitudeInsUpdate(&ins, Vector(0, 2e6f, 0), ok, none, 1.0f, 0.01f) == FusionAltitudeInsStatusInvalidGyro);
    CHECK(FusionAltitudeInsUpdate(&ins, Vector(0, 0, 0), Vector(0, 0, Infinity()), none, 1.0f, 0.01f) == FusionAltitudeInsStatusInvalidAccel);
    CHECK(FusionAltitudeInsUpdate(&ins, Vector(0, 0, 0), ok, Vector(1, nan, 0), 1.0f, 0.01f) == FusionAltitudeInsStatusInvalidMag);
    CHECK(FusionAltitudeInsUpdate(&ins, Vector(0, 0, 0), ok, Vector(-Infinity(), 0, 0), 1.0f, 0.01f) == FusionAltitudeInsStatusInvalidMag);
    CHECK(FusionAltitudeInsUpdate(&ins, Vector(0, 0, 0), ok, none, Infinity(), 0.01f) == FusionAltitudeInsStatusInvalidBaroAltitude);
    CHECK(FusionAltitudeInsUpdate(&ins, Vector(0, 0, 0), ok, none, 1.0f, 0.0f) == FusionAltitudeInsStatusInvalidDt);
    CHECK(FusionAltitudeInsUpdate(&ins, Vector(0, 0, 0), ok, none, 1.0f, -0.01f) == FusionAltitudeInsStatusInvalidDt);
    CHECK(FusionAltitudeInsUpdate(&ins, Vector(0, 0, 0), ok, none, 1.0f, nan) == FusionAltitudeInsStatusInvalidDt);
    CHECK(SameBits(&ins, &before));
}

static void InvalidSettingsAreRejected(void) {
    FusionAltitudeIns ins;
    FusionAltitudeInsInitialise(&ins);
    const FusionAltitudeIns before = ins;
    FusionAltitudeInsSettings s = FusionAltitudeInsSettingsDefault();
    s.baroNoise = 0.0f;
    CHECK(FusionAltitudeInsSetSettings(&ins, &s) == FusionAltitudeInsStatusInvalidSettings);
    s = FusionAltitudeInsSettingsDefault();
    s.gapPeriod = FusionAltitudeNaN();
    CHECK(FusionAltitudeInsInitialiseWith(&ins, &s) == FusionAltitudeInsStatusInvalidSettings);
    s = FusionAltitudeInsSettingsDefault();
    s.gyroNoise = -1.0f;
    CHECK(FusionAltitudeInsSettingsCheck(&s) == FusionAltitudeInsStatusInvalidSettings);
    s = FusionAltitudeInsSettingsDefault();
    s.accelNoise = 2e6f;
    CHECK(FusionAltitudeInsSettingsCheck(&s) == FusionAltitudeInsStatusInvalidSettings);
    CHECK(SameBits(&ins, &before));
    for (int status = 0; status <= (int) FusionAltitudeInsStatusInvalidSettings; status++) {
        CHECK(strcmp(FusionAltitudeInsStatusMessage((FusionAltitudeInsStatus) status), "unknown status") != 0);
    }
}

static void AtRestTheGyroBiasAccelZBiasAndBaroBiasAreLearned(void) {
    FusionAltitudeIns ins;
    FusionAltitudeInsInitialise(&ins);
    rngState = 1u;
    for (int i = 0; i < 3000; i++) { /* 30 s at 100 Hz */
        const FusionAltitudeInsVector gyro = Vector(0.004f + 0.002f * Gaussian(), -0.003f + 0.002f * Gaussian(), 0.002f + 0.002f * Gaussian());
        const FusionAltitudeInsVector accel = Vector(0.05f * Gaussian(), 0.05f * Gaussian(), g + 0.12f + 0.05f * Gaussian());
        const float baro = (i % 4 == 0) ? (85.0f + 0.3f * Gaussian()) : FUSION_ALTITUDE_NO_BARO;
        CHECK(FusionAltitudeInsUpdate(&ins, gyro, accel, FusionAltitudeInsNoMag(), baro, 0.01f) == FusionAltitudeInsStatusOk);
    }
    CHECK(FusionAltitudeInsIsStationary(&ins));
    const FusionAltitudeInsVector b = FusionAltitudeInsGetGyroBias(&ins);
    CHECK(Absolute(b.x - 0.004f) < 3e-4f && Absolute(b.y + 0.003f) < 3e-4f && Absolute(b.z - 0.002f) < 3e-4f);
    CHECK(Absolute(FusionAltitudeInsGetAccelZBias(&ins) - 0.12f) < 0.012f);
    /* the baro reads d + bias; d moved a little in the first second, before stationary was detected */
    printf("  baro bias %.4f m, d %.4f m, accel z bias %.4f m/s^2\n", (double) FusionAltitudeInsGetBaroBias(&ins),
           (double) FusionAltitudeInsGetAltitude(&ins), (double) FusionAltitudeInsGetAccelZBias(&ins));
    CHECK(Absolute(FusionAltitudeInsGetBaroBias(&ins) + FusionAltitudeInsGetAltitude(&ins) - 85.0f) < 0.05f);
    CHECK(Absolute(FusionAltitudeInsGetAltitude(&ins)) < 0.2f);
    CHECK(Absolute(FusionAltitudeInsGetVerticalVelocity(&ins)) < 0.05f);
}

static void StationaryNeedsTheWholeWindowStill(void) {
    FusionAltitudeIns ins;
    FusionAltitudeInsInitialise(&ins);
    for (int i = 0; i < 99; i++) {
        (void) FusionAltitudeInsUpdate(&ins, Vector(0, 0, 0), Vector(0, 0, g), FusionAltitudeInsNoMag(), FUSION_ALTITUDE_NO_BARO, 0.01f);
    }
    CHECK(!FusionAltitudeInsIsStationary(&ins)); /* aligned on the first, 98 x 0.01 s still < 1 s */
    (void) FusionAltitudeInsUpdate(&ins, Vector(0, 0, 0), Vector(0, 0, g), FusionAltitudeInsNoMag(), FUSION_ALTITUDE_NO_BARO, 0.01f);
    (void) FusionAltitudeInsUpdate(&ins, Vector(0, 0, 0), Vector(0, 0, g), FusionAltitudeInsNoMag(), FUSION_ALTITUDE_NO_BARO, 0.01f);
    (void) FusionAltitudeInsUpdate(&ins, Vector(0, 0, 0), Vector(0, 0, g), FusionAltitudeInsNoMag(), FUSION_ALTITUDE_NO_BARO, 0.01f);
    CHECK(FusionAltitudeInsIsStationary(&ins));
    (void) FusionAltitudeInsUpdate(&ins, Vector(0.1f, 0, 0), Vector(0, 0, g), FusionAltitudeInsNoMag(), FUSION_ALTITUDE_NO_BARO, 0.01f);
    CHECK(!FusionAltitudeInsIsStationary(&ins));
    (void) FusionAltitudeInsUpdate(&ins, Vector(0, 0, 0), Vector(0, 0, g + 1.0f), FusionAltitudeInsNoMag(), FUSION_ALTITUDE_NO_BARO, 0.01f);
    CHECK(!FusionAltitudeInsIsStationary(&ins));
}

/* Tumbling with a gyro bias for 120 s; returns the worst tilt error after 20 s, rad. */
static double TumblingRun(FusionAltitudeIns *const ins, const bool magDisturbance, float *const worstAltitudeError) {
    FusionAltitudeInsInitialise(ins);
    Truth t = {{1.0, 0.0, 0.0, 0.0}, 0.0, 0.0};
    rngState = 7u;
    const double dt = 0.005;
    double worst = 0.0;
    *worstAltitudeError = 0.0f;
    for (int i = 0; i < 24000; i++) {
        const double time = (double) i * dt;
        const double w[3] = {0.4 * sin(0.5 * time), 0.3 * cos(0.7 * time), 0.2 * sin(0.3 * time)};
        const double a = (time < 10.0) ? 0.0 : 0.8 * sin(0.4 * time);
        const FusionAltitudeInsVector f = SpecificForce(&t, a);
        const FusionAltitudeInsVector gyro = Vector((float) w[0] + 0.01f + 0.003f * Gaussian(), (float) w[1] - 0.008f + 0.003f * Gaussian(),
                                                    (float) w[2] + 0.005f + 0.003f * Gaussian());
        const FusionAltitudeInsVector accel = Vector(f.x + 0.03f * Gaussian(), f.y + 0.03f * Gaussian(), f.z + 0.03f * Gaussian());
        const float baro = (i % 14 == 0) ? (float) (120.0 + t.h) + 0.2f * Gaussian() : FUSION_ALTITUDE_NO_BARO;
        FusionAltitudeInsVector mag = Vector(0.4f, 0.0f, -0.3f);
        if (magDisturbance && time > 40.0 && time < 60.0) {
            mag = Vector(5.0f, -3.0f, 2.0f);
        }
        if (time >= 10.0) {
            (void) FusionAltitudeInsUpdate(ins, gyro, accel, mag, baro, (float) dt);
        } else { /* rest: the truth does not rotate */
            (void) FusionAltitudeInsUpdate(ins, Vector(0.01f + 0.003f * Gaussian(), -0.008f, 0.005f), accel, mag, baro, (float) dt);
        }
        if (time >= 10.0) {
            TruthStep(&t, w, a, dt);
        } else {
            const double zero[3] = {0.0, 0.0, 0.0};
            TruthStep(&t, zero, a, dt);
        }
        if (time > 20.0) {
            const double e = TiltError(&t, ins);
            worst = e > worst ? e : worst;
            const float altitudeError = Absolute(FusionAltitudeInsGetAltitude(ins) - (float) t.h);
            *worstAltitudeError = altitudeError > *worstAltitudeError ? altitudeError : *worstAltitudeError;
        }
    }
    return worst;
}

static void TumblingTiltAndAltitudeFollowTheTruth(void) {
    FusionAltitudeIns ins;
    float altitudeError;
    const double tilt = TumblingRun(&ins, false, &altitudeError);
    printf("  tumbling: worst tilt error %.3f deg, worst altitude error %.3f m\n", tilt * 57.29578, (double) altitudeError);
    CHECK(tilt < 0.02);          /* 1.1 deg */
    CHECK(altitudeError < 0.5f); /* m */
    const FusionAltitudeInsVector b = FusionAltitudeInsGetGyroBias(&ins);
    CHECK(Absolute(b.x - 0.01f) < 2e-3f && Absolute(b.y + 0.008f) < 2e-3f && Absolute(b.z - 0.005f) < 2e-3f);
}

static void MagneticDisturbanceNeverTouchesTheLocalAttitudeOrAltitude(void) {
    FusionAltitudeIns clean, disturbed;
    float e1, e2;
    (void) TumblingRun(&clean, false, &e1);
    (void) TumblingRun(&disturbed, true, &e2);
    CHECK(memcmp(clean.q, disturbed.q, sizeof(clean.q)) == 0);
    CHECK(memcmp(&clean.distance, &disturbed.distance, sizeof(float)) == 0);
    CHECK(memcmp(clean.P, disturbed.P, sizeof(clean.P)) == 0);
    /* and the mag did reach the global attitude */
    CHECK(clean.magInitialised && disturbed.magInitialised);
}

static void MagnetometerSetsTheGlobalYawOnly(void) {
    FusionAltitudeIns ins;
    FusionAltitudeInsInitialise(&ins);
    /* level, field pointing to body -y with a dip: the body x axis points 90 deg left of north... */
    for (int i = 0; i < 500; i++) {
        (void) FusionAltitudeInsUpdate(&ins, Vector(0, 0, 0), Vector(0, 0, g), Vector(0.0f, -0.3f, -0.4f), FUSION_ALTITUDE_NO_BARO, 0.01f);
    }
    const FusionAltitudeInsQuaternion local = FusionAltitudeInsGetQuaternion(&ins);
    const FusionAltitudeInsQuaternion global = FusionAltitudeInsGetGlobalQuaternion(&ins);
    CHECK(local.w == 1.0f && local.z == 0.0f);
    /* body x is rotated +90 deg about up (west): q = (cos 45, 0, 0, sin 45) */
    CHECK(Absolute(global.w - 0.70710678f) < 1e-5f && Absolute(global.z - 0.70710678f) < 1e-5f);
}

static void GapIsCountedAndNotIntegrated(void) {
    FusionAltitudeIns ins;
    FusionAltitudeInsInitialise(&ins);
    for (int i = 0; i < 50; i++) {
        (void) FusionAltitudeInsUpdate(&ins, Vector(0, 0, 0), Vector(0, 0, g), FusionAltitudeInsNoMag(), 10.0f, 0.01f);
    }
    const FusionAltitudeIns before = ins;
    /* 2 s gap with a huge rate and acceleration: integrating would rotate and move */
    CHECK(FusionAltitudeInsUpdate(&ins, Vector(3.0f, 0, 0), Vector(0, 0, g + 1.5f), FusionAltitudeInsNoMag(), FUSION_ALTITUDE_NO_BARO, 2.0f) ==
          FusionAltitudeInsStatusOk);
    CHECK(FusionAltitudeInsGetGapCount(&ins) == 1u);
    CHECK(memcmp(ins.q, before.q, sizeof(ins.q)) == 0);
    CHECK(ins.distance == before.distance && ins.velocity == before.velocity);
    CHECK(ins.P[7][7] >= 0.24f); /* raised to 0.25, then this step's accel correction */
    CHECK(ins.stationaryTime == 0.0f);
}

static void PredictionFollowsTheDocumentedEquations(void) {
    FusionAltitudeIns ins;
    FusionAltitudeInsInitialise(&ins);
    (void) FusionAltitudeInsUpdate(&ins, Vector(0, 0, 0), Vector(0, 0, g), FusionAltitudeInsNoMag(), FUSION_ALTITUDE_NO_BARO, 0.01f);
    ins.velocity = 0.5f;
    const float dt = 0.02f;
    /* level, f = (0, 0, g + 1): a = 1 m/s^2; the accel correction leaves d, v alone (no d-theta correlation yet) */
    const float a = (g + 1.0f) - g;
    const float d = 0.0f + 0.5f * dt + a * (0.5f * dt * dt);
    const float v = 0.5f + a * dt;
    CHECK(FusionAltitudeInsUpdate(&ins, Vector(0, 0, 0), Vector(0, 0, g + 1.0f), FusionAltitudeInsNoMag(), FUSION_ALTITUDE_NO_BARO, dt) ==
          FusionAltitudeInsStatusOk);
    CHECK(Absolute(FusionAltitudeInsGetAltitude(&ins) - d) < 1e-7f);
    CHECK(Absolute(FusionAltitudeInsGetVerticalVelocity(&ins) - v) < 1e-6f);
    CHECK(ins.P[6][7] == ins.P[7][6]);
}

/* Smallest pivot of the Cholesky factorisation (double) of P's correlation matrix; rows with zero variance skipped. */
static double CorrelationPivot(const FusionAltitudeIns *const ins) {
    double C[FUSION_ALTITUDE_INS_STATES][FUSION_ALTITUDE_INS_STATES];
    int index[FUSION_ALTITUDE_INS_STATES];
    int n = 0;
    for (int i = 0; i < FUSION_ALTITUDE_INS_STATES; i++) {
        if (ins->P[i][i] > 0.0f) {
            index[n++] = i;
        }
    }
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) {
            const int a = index[i], b = index[j];
            C[i][j] = (double) ins->P[a][b] / sqrt((double) ins->P[a][a] * (double) ins->P[b][b]);
        }
    }
    double worst = 1.0;
    for (int k = 0; k < n; k++) {
        double pivot = C[k][k];
        for (int m = 0; m < k; m++) {
            pivot -= C[k][m] * C[k][m];
        }
        worst = pivot < worst ? pivot : worst;
        if (pivot <= 0.0) {
            return pivot;
        }
        const double root = sqrt(pivot);
        C[k][k] = root;
        for (int i = k + 1; i < n; i++) {
            double value = C[i][k];
            for (int m = 0; m < k; m++) {
                value -= C[i][m] * C[k][m];
            }
            C[i][k] = value / root;
        }
    }
    return worst;
}

/* The update steps of the fuzzer's finding csrc/fuzz/findings/ins_negative_attitude_variance.bin (default settings, no baro gate). */
#define NAN_ NAN /* math.h, a constant expression */
#include "ins_negative_attitude_variance.h"
#undef NAN_

/* The settings the findings were found with: the defaults of the time, without the baro innovation gate (added
   later; a 1e6-sigma gate passes every reading), so that their baro jumps drive the covariance as they did. */
static void FindingInitialise(FusionAltitudeIns *const ins) {
    FusionAltitudeInsSettings settings = FusionAltitudeInsSettingsDefault();
    settings.baroGate = 1e6f;
    CHECK(FusionAltitudeInsInitialiseWith(ins, &settings) == FusionAltitudeInsStatusOk);
}

/* One step of a finding's table (columns: gyro, accel, mag, baro, dt): true when the update accepted it. */
static bool FindingStep(FusionAltitudeIns *const ins, const float v[11]) {
    return FusionAltitudeInsUpdate(ins, Vector(v[0], v[1], v[2]), Vector(v[3], v[4], v[5]), Vector(v[6], v[7], v[8]), v[9], v[10]) ==
           FusionAltitudeInsStatusOk;
}

/* Replays the finding: before the fix P[0][0] went to -9.1e-6 (its 243rd accepted
   update). Now every variance stays >= 0 and every |correlation| <= 1 (all 2x2
   principal minors >= 0). What is NOT claimed: the whole P stays positive
   semi-definite on this input (its junk baro jumps drive P's condition number
   past float32; see docs/ins.md "Covariance conditioning"). */
static void FuzzerFindingKeepsVariancesNonNegativeAndCorrelationsBounded(void) {
    FusionAltitudeIns ins;
    FindingInitialise(&ins);
    int accepted = 0;
    int negativeVariances = 0;
    int unboundedCorrelations = 0;
    for (int k = 0; k < INS_FINDING_STEPS; k++) {
        if (!FindingStep(&ins, insFindingSteps[k])) {
            continue;
        }
        accepted++;
        for (int i = 0; i < FUSION_ALTITUDE_INS_STATES; i++) {
            negativeVariances += (ins.P[i][i] >= 0.0f) ? 0 : 1;
            for (int j = i + 1; j < FUSION_ALTITUDE_INS_STATES; j++) {
                /* in double: the float32 clip rounds sqrtf, so allow 1e-6 relative */
                const double bound = sqrt((double) ins.P[i][i] * (double) ins.P[j][j]) * (1.0 + 1e-6);
                unboundedCorrelations += (fabs((double) ins.P[i][j]) <= bound) ? 0 : 1;
            }
        }
    }
    CHECK(accepted >= 243);
    CHECK(negativeVariances == 0);
    CHECK(unboundedCorrelations == 0);
}

/* The update steps of the fuzzer's finding csrc/fuzz/findings/ins_attitude_variance_growth.bin (default settings, no baro gate). */
#define NAN_ NAN
#include "ins_attitude_variance_growth.h"
#undef NAN_

/* Replays the finding: before FUSION_ALTITUDE_INS_ATTITUDE_VARIANCE_LIMIT, round-off made
   the attitude block of P indefinite and P grew about 100-fold per step until
   P[1][1] = inf (its 167th accepted update). Now P stays finite, the attitude
   variances at most the limit (reached: the limit is what held it), the
   quaternion a unit one. */
static void AttitudeVarianceGrowthFindingStaysFiniteAndBounded(void) {
    FusionAltitudeIns ins;
    FindingInitialise(&ins);
    int accepted = 0;
    int nonFinite = 0;
    float largestAttitudeVariance = 0.0f;
    for (int k = 0; k < INS_GROWTH_STEPS; k++) {
        if (!FindingStep(&ins, insGrowthSteps[k])) {
            continue;
        }
        accepted++;
        for (int i = 0; i < FUSION_ALTITUDE_INS_STATES; i++) {
            for (int j = 0; j < FUSION_ALTITUDE_INS_STATES; j++) {
                nonFinite += FusionAltitudeIsFinite(ins.P[i][j]) ? 0 : 1;
            }
        }
        for (int i = 0; i < 3; i++) {
            largestAttitudeVariance = (ins.P[i][i] > largestAttitudeVariance) ? ins.P[i][i] : largestAttitudeVariance;
        }
        const float norm = ins.q[0] * ins.q[0] + ins.q[1] * ins.q[1] + ins.q[2] * ins.q[2] + ins.q[3] * ins.q[3];
        CHECK(norm > 0.998f && norm < 1.002f);
    }
    CHECK(accepted >= 167);
    CHECK(nonFinite == 0);
    CHECK(largestAttitudeVariance == FUSION_ALTITUDE_INS_ATTITUDE_VARIANCE_LIMIT);
}

static bool LongRun(const char *const name, const bool withBaro) {
    FusionAltitudeIns ins;
    FusionAltitudeInsInitialise(&ins);
    Truth t = {{1.0, 0.0, 0.0, 0.0}, 0.0, 0.0};
    const double dt = 0.001;
    const long steps = 10000000L;
    double worstPivot = 1.0;
    float maxVariance = 0.0f;
    for (long i = 0; i < steps; i++) {
        const double time = (double) i * dt;
        const long phase = i % 300000L; /* 300 s: 60 s at rest, 240 s tumbling and climbing */
        const bool rest = phase < 60000L;
        double w[3] = {0.0, 0.0, 0.0};
        double a = 0.0;
        if (!rest) {
            w[0] = 0.6 * sin(0.5 * time);
            w[1] = 0.4 * cos(0.3 * time);
            w[2] = 0.5 * sin(0.11 * time);
            a = 0.3 * sin(0.05 * time) - 0.1 * t.v;
        }
        const FusionAltitudeInsVector f = SpecificForce(&t, a);
        const FusionAltitudeInsVector gyro = Vector((float) w[0] + 0.01f + 0.003f * Gaussian(), (float) w[1] + 0.003f * Gaussian(),
                                                    (float) w[2] - 0.004f + 0.003f * Gaussian());
        FusionAltitudeInsVector accel = Vector(f.x + 0.1f * Gaussian(), f.y + 0.1f * Gaussian(), f.z + 0.1f * Gaussian());
        if ((phase > 100000L) && (phase < 102000L)) {
            accel.z += 5.0f; /* 2 s of rejected accel */
        }
        const float baro = (withBaro && (i % 14 == 0)) ? (float) (300.0 + t.h) + 0.3f * Gaussian() : FUSION_ALTITUDE_NO_BARO;
        const float stepDt = (i % 1000000L == 500000L) ? 0.5f : (float) dt; /* a gap every 1000 s */
        if (FusionAltitudeInsUpdate(&ins, gyro, accel, Vector(0.4f, 0.1f, -0.3f), baro, stepDt) != FusionAltitudeInsStatusOk) {
            printf("  %s: update rejected at step %ld\n", name, i);
            return false;
        }
        TruthStep(&t, w, a, dt);
        if (i % 1000 == 999) {
            bool ok = true;
            for (int r = 0; r < FUSION_ALTITUDE_INS_STATES; r++) {
                for (int c = 0; c < FUSION_ALTITUDE_INS_STATES; c++) {
                    if (!FusionAltitudeIsFinite(ins.P[r][c]) || (memcmp(&ins.P[r][c], &ins.P[c][r], sizeof(float)) != 0)) {
                        ok = false;
                    }
                }
                if (ins.P[r][r] < 0.0f) {
                    ok = false;
                }
                maxVariance = ins.P[r][r] > maxVariance ? ins.P[r][r] : maxVariance;
            }
            const double pivot = CorrelationPivot(&ins);
            worstPivot = pivot < worstPivot ? pivot : worstPivot;
            if (!ok || pivot < 0.0) {
                printf("  %s: covariance check failed at step %ld (pivot %g)\n", name, i, pivot);
                for (int r = 0; r < 8; r++) { for (int c = 0; c < 8; c++) printf(" %10.3g", (double) ins.P[r][c]); printf("\n"); }
                return false;
            }
        }
    }
    printf("  %s: %ld steps, worst correlation Cholesky pivot %.3g, largest variance %.3g, tilt error %.3f deg, h %.3f (truth %.3f), gaps %u\n",
           name, steps, worstPivot, (double) maxVariance, TiltError(&t, &ins) * 57.29578, (double) FusionAltitudeInsGetAltitude(&ins), t.h,
           (unsigned) FusionAltitudeInsGetGapCount(&ins));
    return true;
}

static int RunLong(void) {
    int bad = 0;
    bad += LongRun("gyro + accel + mag + baro", true) ? 0 : 1;
    bad += LongRun("no baro (height unobservable)", false) ? 0 : 1;
    printf("long: %d of %d configurations kept P symmetric PSD\n", 2 - bad, 2);
    return bad == 0 ? 0 : 1;
}

int main(int argc, char **argv) {
    if ((argc > 1) && (strcmp(argv[1], "long") == 0)) {
        return RunLong();
    }
    RUN(InitialiseIsUnalignedAtTheOriginWithTheDefaults);
    RUN(FirstUsableAccelSampleAlignsTheTiltWithZeroYaw);
    RUN(RejectedInputsLeaveTheStateBitIdentical);
    RUN(InvalidSettingsAreRejected);
    RUN(AtRestTheGyroBiasAccelZBiasAndBaroBiasAreLearned);
    RUN(StationaryNeedsTheWholeWindowStill);
    RUN(TumblingTiltAndAltitudeFollowTheTruth);
    RUN(MagneticDisturbanceNeverTouchesTheLocalAttitudeOrAltitude);
    RUN(MagnetometerSetsTheGlobalYawOnly);
    RUN(GapIsCountedAndNotIntegrated);
    RUN(PredictionFollowsTheDocumentedEquations);
    RUN(FuzzerFindingKeepsVariancesNonNegativeAndCorrelationsBounded);
    RUN(AttitudeVarianceGrowthFindingStaysFiniteAndBounded);
    return TestSummary();
}
