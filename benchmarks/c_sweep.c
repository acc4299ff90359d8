/* Instruction-count and timing harness for the gain sweep (docs/performance.md, issue 16).
 *
 *   cc -O2 -ffp-contract=off -fno-fast-math [-DFUSION_ALTITUDE_SWEEP_MULTIVERSION] -Icsrc benchmarks/c_sweep.c -o c_sweep
 *   valgrind --tool=callgrind --callgrind-out-file=/dev/null --toggle-collect='FusionAltitudeSweepUpdate*' ./c_sweep K SAMPLES metrics|outputs
 *   ./c_sweep K SAMPLES metrics|outputs REPEAT
 *
 * Runs FusionAltitudeSweepUpdate once over SAMPLES synthetic 100 Hz samples
 * (baro every sample, as benchmarks/targets.py) for K settings, either with
 * metrics only (against a reference series, no outputs) or with all four
 * outputs (no metrics), the two cases of the sweep targets. The
 * inputs are generated before the call; callgrind's count of SAMPLES minus
 * the count of 0 samples, divided by SAMPLES * K, is the instructions per
 * sample-setting (--toggle-collect counts only the sweep call, not the input
 * generation). With REPEAT, the call is repeated REPEAT times (the state
 * carries on) and the shortest monotonic-clock time per sample-setting is
 * printed: with short calls, the shortest is one that no other process
 * interrupted. Prints a checksum so that nothing is optimised away.
 */
#define _POSIX_C_SOURCE 199309L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fusion_altitude_sweep.h"

static float noise(uint32_t *seed) {
    *seed = *seed * 1664525u + 1013904223u;
    return (float) (int32_t) *seed * (1.0f / 2147483648.0f);
}

int main(int argc, char **argv) {
    if ((argc != 4) && (argc != 5)) {
        fprintf(stderr, "usage: %s K SAMPLES metrics|outputs [REPEAT]\n", argv[0]);
        return 2;
    }
    const size_t count = (size_t) atol(argv[1]);
    const size_t samples = (size_t) atol(argv[2]);
    const int withOutputs = strcmp(argv[3], "outputs") == 0;
    const size_t n = (samples > 0u) ? samples : 1u;
    float *accel = malloc(n * sizeof(float));
    float *baro = malloc(n * sizeof(float));
    float *reference = malloc(n * sizeof(float));
    float *gains = malloc(3u * count * sizeof(float));
    float *state = malloc(4u * count * sizeof(float));
    float *metricArrays = calloc(5u * count, sizeof(float));
    float *out = withOutputs ? malloc(4u * n * count * sizeof(float)) : NULL;
    uint32_t seed = 12345u;
    for (size_t t = 0; t < n; t++) {
        const float h = 10.0f + 0.001f * (float) (t % 5000u);
        accel[t] = 0.3f * noise(&seed);
        baro[t] = h + 0.4f * noise(&seed);
        reference[t] = h;
    }
    for (size_t k = 0; k < count; k++) {
        const float scale = 0.5f + (float) k / (float) count;
        gains[k] = 2.4f * scale;
        gains[count + k] = 2.88f * scale * scale;
        gains[2u * count + k] = 0.675f * scale * scale * scale;
    }
    FusionAltitudeSweep sweep;
    sweep.count = count;
    sweep.positionGain = &gains[0];
    sweep.velocityGain = &gains[count];
    sweep.biasGain = &gains[2u * count];
    sweep.altitude = &state[0];
    sweep.verticalVelocity = &state[count];
    sweep.accelBias = &state[2u * count];
    sweep.baroResidual = &state[3u * count];
    FusionAltitudeSweepInitialise(&sweep);
    FusionAltitudeSweepOutputs outputs;
    FusionAltitudeSweepMetrics metrics;
    if (withOutputs) {
        outputs.altitude = &out[0];
        outputs.verticalVelocity = &out[n * count];
        outputs.accelBias = &out[2u * n * count];
        outputs.baroResidual = &out[3u * n * count];
        outputs.stride = count;
    } else {
        metrics.reference = reference;
        metrics.mask = NULL;
        metrics.sumError = &metricArrays[0];
        metrics.sumSquaredError = &metricArrays[count];
        metrics.maxAbsError = &metricArrays[2u * count];
        metrics.blockSumError = &metricArrays[3u * count];
        metrics.blockSumSquaredError = &metricArrays[4u * count];
        metrics.samplesInBlock = 0;
        metrics.metricSamples = 0;
    }
    const float dt = 0.01f;
    size_t bad = 0;
    const long repeat = (argc == 5) ? atol(argv[4]) : 1;
    double best = 1e30;
    for (long r = 0; r < repeat; r++) {
        struct timespec start;
        struct timespec stop;
        clock_gettime(CLOCK_MONOTONIC, &start);
        if (FusionAltitudeSweepUpdate(&sweep, accel, baro, &dt, 0, samples, withOutputs ? &outputs : NULL,
                                      withOutputs ? NULL : &metrics, &bad) != FusionAltitudeStatusOk) {
            return 1;
        }
        clock_gettime(CLOCK_MONOTONIC, &stop);
        const double ns = (double) (stop.tv_sec - start.tv_sec) * 1e9 + (double) (stop.tv_nsec - start.tv_nsec);
        best = (ns < best) ? ns : best;
    }
    if (argc == 5) {
        printf("best of %ld: %.3f ns per sample-setting\n", repeat, best / ((double) n * (double) count));
    }
    if (!withOutputs) {
        FusionAltitudeSweepFlushMetrics(&sweep, &metrics);
    }
    float checksum = 0.0f;
    for (size_t k = 0; k < count; k++) {
        checksum += state[k] + metricArrays[k] + metricArrays[count + k];
    }
    printf("sweep K=%zu %zu samples %s checksum %.9g\n", count, samples, argv[3], (double) checksum);
    free(accel);
    free(baro);
    free(reference);
    free(gains);
    free(state);
    free(metricArrays);
    free(out);
    return 0;
}
