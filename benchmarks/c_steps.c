/* Instruction-count harness for docs/performance.md (the per-case speed targets).
 *
 *   cc -O2 -ffp-contract=off -fno-fast-math -Icsrc benchmarks/c_steps.c -o c_steps
 *   valgrind --tool=callgrind --callgrind-out-file=/dev/null ./c_steps alphabeta 100000
 *
 * Runs N steps of one estimator's C update (the same call the Cython batch
 * loop makes) on synthetic 100 Hz inputs with every sensor sampled on every
 * step (the worst cases), and prints a checksum of the outputs so
 * that nothing is optimised away. Instruction counts (callgrind "Collected")
 * are repeatable on a loaded machine where wall time is not; divide the
 * count of N steps minus the count of 0 steps by N.
 *
 * With a third argument REPEAT, the N steps are run REPEAT times (a fresh
 * estimator each time) and the shortest monotonic-clock time per step is
 * printed: on a loaded machine the shortest of many short runs is one that
 * no other process interrupted (its other hardware thread may still be
 * busy).
 *
 * Cases: alphabeta (IMU, baro, lidar, GPS every step), kalman (baro,
 * rangefinder, GPS every step), complementary (baro every step), observer
 * (baro every step), ins (raw IMU rocking +-10 deg about x and y, the
 * accelerometer correction on every step, a magnetometer sample on every
 * step and a baro sample on every 7th: benchmarks/ins_bench.py's inputs, the
 * seed's 500 Hz / 71.4 Hz ratio).
 */
#define _POSIX_C_SOURCE 199309L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fusion_altitude.h"
#include "fusion_altitude_alphabeta.h"
#include "fusion_altitude_complementary.h"
#include "fusion_altitude_ins.h"
#include "fusion_altitude_kalman.h"

/* Deterministic noise in [-1, 1) without libm: a 32-bit LCG. */
static float noise(uint32_t *seed) {
    *seed = *seed * 1664525u + 1013904223u;
    return (float) (int32_t) *seed * (1.0f / 2147483648.0f);
}

/* A slow triangle wave of amplitude 2 m instead of a sine (no libm). */
static float truth(const long i) {
    const long period = 2000;
    const long p = i % period;
    const float t = (float) p / (float) period;
    return 4.0f + ((t < 0.5f) ? (8.0f * t - 2.0f) : (6.0f - 8.0f * t));
}

#if defined(__GNUC__)
#define C_STEPS_NOINLINE __attribute__((noinline))
#else
#define C_STEPS_NOINLINE
#endif

/* One function per case, so that inlining decisions in one do not move the
 * instruction counts of another. Each returns the sum of the altitudes. */
static C_STEPS_NOINLINE float runAlphaBeta(const long n, const float dt, uint32_t seed) {
    float checksum = 0.0f;
    FusionAltitudeAlphaBeta fusion;
    FusionAltitudeAlphaBetaInitialise(&fusion);
    for (long i = 0; i < n; i++) {
        const float h = truth(i);
        FusionAltitudeAlphaBetaMeasurements m = FusionAltitudeAlphaBetaMeasurementsNone();
        m.baroAltitude = h + 0.4f * noise(&seed);
        m.lidarAltitude = h + 0.04f * noise(&seed);
        m.gpsAltitude = h + 1.5f * noise(&seed);
        if (FusionAltitudeAlphaBetaUpdate(&fusion, 0.3f * noise(&seed), dt, &m) != FusionAltitudeAlphaBetaStatusOk) {
            exit(1);
        }
        checksum += FusionAltitudeAlphaBetaGetAltitude(&fusion);
    }
    return checksum;
}

static C_STEPS_NOINLINE float runKalman(const long n, const float dt, uint32_t seed) {
    float checksum = 0.0f;
    FusionAltitudeKalman kalman;
    FusionAltitudeKalmanInitialise(&kalman);
    for (long i = 0; i < n; i++) {
        const float h = truth(i);
        FusionAltitudeKalmanMeasurements m = FusionAltitudeKalmanMeasurementsNone();
        m.baroAltitude = 250.0f + h + 0.4f * noise(&seed);
        m.rangeDistance = h + 0.04f * noise(&seed);
        m.gpsAltitude = 290.0f + h + 1.2f * noise(&seed);
        m.gpsSatellites = 9;
        if (FusionAltitudeKalmanUpdate(&kalman, 0.1f + 0.3f * noise(&seed), dt, &m) != FusionAltitudeKalmanStatusOk) {
            exit(1);
        }
        checksum += FusionAltitudeKalmanGetAltitude(&kalman);
    }
    return checksum;
}

static C_STEPS_NOINLINE float runComplementary(const long n, const float dt, uint32_t seed) {
    float checksum = 0.0f;
    FusionAltitudeComplementary filter;
    FusionAltitudeComplementaryInitialise(&filter);
    for (long i = 0; i < n; i++) {
        if (FusionAltitudeComplementaryUpdate(&filter, 0.3f * noise(&seed), truth(i) + 0.4f * noise(&seed), dt) !=
            FusionAltitudeComplementaryStatusOk) {
            exit(1);
        }
        checksum += FusionAltitudeComplementaryGetAltitude(&filter);
    }
    return checksum;
}

static C_STEPS_NOINLINE float runObserver(const long n, const float dt, uint32_t seed) {
    float checksum = 0.0f;
    FusionAltitude observer;
    FusionAltitudeInitialise(&observer);
    for (long i = 0; i < n; i++) {
        if (FusionAltitudeUpdate(&observer, 0.3f * noise(&seed), truth(i) + 0.4f * noise(&seed), dt) != FusionAltitudeStatusOk) {
            exit(1);
        }
        checksum += FusionAltitudeGetAltitude(&observer);
    }
    return checksum;
}

/* sin and cos of a small angle (|x| <= 0.2 rad) without libm: Taylor series to x^5 and x^6. */
static float smallSin(const float x) {
    const float x2 = x * x;
    return x * (1.0f - x2 / 6.0f * (1.0f - x2 / 20.0f));
}

static float smallCos(const float x) {
    const float x2 = x * x;
    return 1.0f - x2 / 2.0f * (1.0f - x2 / 12.0f * (1.0f - x2 / 30.0f));
}

/* Triangle wave of amplitude 1 and the given period in steps, and its slope per step. */
static float triangle(const long i, const long period, float *slope) {
    const float t = (float) (i % period) / (float) period;
    *slope = ((t < 0.5f) ? 4.0f : -4.0f) / (float) period;
    return (t < 0.5f) ? (4.0f * t - 1.0f) : (3.0f - 4.0f * t);
}

static C_STEPS_NOINLINE float runIns(const long n, const float dt, uint32_t seed) {
    float checksum = 0.0f;
    FusionAltitudeIns ins;
    FusionAltitudeInsInitialise(&ins);
    const float amplitude = 0.17f; /* rad, +-10 deg */
    for (long i = 0; i < n; i++) {
        float rollSlope, pitchSlope;
        const float roll = amplitude * triangle(i, 400, &rollSlope);
        const float pitch = amplitude * triangle(i + 130, 700, &pitchSlope);
        const float g = FUSION_ALTITUDE_GRAVITY;
        const FusionAltitudeInsVector gyro = {amplitude * rollSlope / dt + 0.002f + 0.003f * noise(&seed),
                                              amplitude * pitchSlope / dt - 0.001f + 0.003f * noise(&seed),
                                              0.003f * noise(&seed)};
        const FusionAltitudeInsVector accel = {-g * smallSin(pitch) + 0.05f * noise(&seed),
                                               g * smallSin(roll) * smallCos(pitch) + 0.05f * noise(&seed),
                                               g * smallCos(roll) * smallCos(pitch) + 0.05f * noise(&seed)};
        const FusionAltitudeInsVector mag = {0.2f + 0.01f * noise(&seed), 0.01f * noise(&seed), -0.4f + 0.01f * noise(&seed)};
        const float baro = (i % 7 == 0) ? truth(i) + 0.3f * noise(&seed) : FUSION_ALTITUDE_NO_BARO;
        if (FusionAltitudeInsUpdate(&ins, gyro, accel, mag, baro, dt) != FusionAltitudeInsStatusOk) {
            exit(1);
        }
        checksum += FusionAltitudeInsGetAltitude(&ins);
    }
    return checksum;
}

static float run(const char *const name, const long n, const float dt, const uint32_t seed) {
    if (strcmp(name, "alphabeta") == 0) {
        return runAlphaBeta(n, dt, seed);
    }
    if (strcmp(name, "kalman") == 0) {
        return runKalman(n, dt, seed);
    }
    if (strcmp(name, "complementary") == 0) {
        return runComplementary(n, dt, seed);
    }
    if (strcmp(name, "observer") == 0) {
        return runObserver(n, dt, seed);
    }
    if (strcmp(name, "ins") == 0) {
        return runIns(n, dt, seed);
    }
    fprintf(stderr, "unknown case %s\n", name);
    exit(2);
}

int main(int argc, char **argv) {
    if ((argc != 3) && (argc != 4)) {
        fprintf(stderr, "usage: %s alphabeta|kalman|complementary|observer|ins N [REPEAT]\n", argv[0]);
        return 2;
    }
    const char *const name = argv[1];
    const long n = atol(argv[2]);
    const float dt = 0.01f;
    const uint32_t seed = 12345u;
    if (argc == 4) {
        const long repeat = atol(argv[3]);
        double best = 1e30;
        float checksum = 0.0f;
        for (long r = 0; r < repeat; r++) {
            struct timespec start;
            struct timespec stop;
            clock_gettime(CLOCK_MONOTONIC, &start);
            checksum += run(name, n, dt, seed);
            clock_gettime(CLOCK_MONOTONIC, &stop);
            const double ns = (double) (stop.tv_sec - start.tv_sec) * 1e9 + (double) (stop.tv_nsec - start.tv_nsec);
            best = (ns < best) ? ns : best;
        }
        printf("%s %ld steps, best of %ld: %.1f ns/step (checksum %.9g)\n", name, n, repeat, best / (double) n, (double) checksum);
        return 0;
    }
    const float checksum = run(name, n, dt, seed);
    printf("%s %ld steps checksum %.9g\n", name, n, (double) checksum);
    return 0;
}
