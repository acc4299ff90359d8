/* Memory write bandwidth of this machine, for the sweep-output floor in docs/performance.md.
 *
 *   cc -O2 benchmarks/store_bandwidth.c -o store_bandwidth && ./store_bandwidth 51200000   (x86-64)
 *
 * Writes FLOATS floats (default 51 200 000: 195 MiB, far beyond the caches)
 * five times with ordinary 16-byte stores and five times with non-temporal
 * (streaming) stores, and prints the best rate of each and the time per 16
 * bytes: the four outputs of one sample-setting of the sweep.
 */
#define _POSIX_C_SOURCE 200112L
#include <immintrin.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double) t.tv_sec + 1e-9 * (double) t.tv_nsec;
}

int main(int argc, char **argv) {
    const size_t n = (argc > 1) ? (size_t) atol(argv[1]) : 51200000u;
    float *a = NULL;
    if (posix_memalign((void **) &a, 64, n * sizeof(float)) != 0) {
        return 1;
    }
    for (size_t i = 0; i < n; i++) {
        a[i] = 0.0f;
    }
    double bestStore = 1e9, bestStream = 1e9;
    for (int r = 0; r < 5; r++) {
        const __m128 v = _mm_set1_ps((float) r);
        const double t0 = now();
        for (size_t i = 0; i + 4 <= n; i += 4) {
            _mm_store_ps(&a[i], v);
        }
        const double t1 = now();
        for (size_t i = 0; i + 4 <= n; i += 4) {
            _mm_stream_ps(&a[i], v);
        }
        _mm_sfence();
        const double t2 = now();
        bestStore = (t1 - t0 < bestStore) ? (t1 - t0) : bestStore;
        bestStream = (t2 - t1 < bestStream) ? (t2 - t1) : bestStream;
    }
    const double bytes = (double) n * sizeof(float);
    printf("%.0f MiB: stores %.2f GB/s (%.3f ns per 16 B), streaming stores %.2f GB/s (%.3f ns per 16 B) [%g]\n",
           bytes / 1048576.0, bytes / bestStore / 1e9, bestStore / (bytes / 16.0) * 1e9, bytes / bestStream / 1e9,
           bestStream / (bytes / 16.0) * 1e9, (double) a[n / 2]);
    free(a);
    return 0;
}
