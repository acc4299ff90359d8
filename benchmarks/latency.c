/* Clock and float32 latencies of this machine, for the dependency-chain floors in docs/performance.md.
 *
 *   cc -O2 benchmarks/latency.c -o latency && ./latency        (x86-64, gcc or clang)
 *
 * Times chains of dependent instructions (each waits for the previous one):
 * integer add (1 cycle on every x86-64 core of the last 20 years, so its
 * rate is the clock), addss, mulss and divss. The shortest of 1000 short
 * runs is taken: on a loaded machine the shortest is one that no other
 * process interrupted. Latency in cycles = time per instruction / time per
 * integer add. divss divides by 1.0 so the operand never becomes subnormal.
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <time.h>

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double) t.tv_sec * 1e9 + (double) t.tv_nsec;
}

int main(void) {
    double bestAdd = 1e30, bestAddss = 1e30, bestMulss = 1e30, bestDivss = 1e30;
    unsigned long y = 1;
    float x = 1.0f, z = 1.25f;
    const float zero = 0.0f, one = 1.0f;
    for (int r = 0; r < 1000; r++) {
        const double t0 = now();
        for (long i = 0; i < 1000000; i++) {
            __asm__ volatile("add $1,%0\n\tadd $1,%0\n\tadd $1,%0\n\tadd $1,%0" : "+r"(y));
        }
        const double t1 = now();
        for (long i = 0; i < 1000000; i++) {
            __asm__ volatile("addss %1,%0\n\taddss %1,%0\n\taddss %1,%0\n\taddss %1,%0" : "+x"(x) : "x"(zero));
        }
        const double t2 = now();
        for (long i = 0; i < 1000000; i++) {
            __asm__ volatile("mulss %1,%0\n\tmulss %1,%0\n\tmulss %1,%0\n\tmulss %1,%0" : "+x"(x) : "x"(one));
        }
        const double t3 = now();
        for (long i = 0; i < 100000; i++) {
            __asm__ volatile("divss %1,%0\n\tdivss %1,%0\n\tdivss %1,%0\n\tdivss %1,%0" : "+x"(z) : "x"(one));
        }
        const double t4 = now();
        bestAdd = (t1 - t0 < bestAdd) ? (t1 - t0) : bestAdd;
        bestAddss = (t2 - t1 < bestAddss) ? (t2 - t1) : bestAddss;
        bestMulss = (t3 - t2 < bestMulss) ? (t3 - t2) : bestMulss;
        bestDivss = (t4 - t3 < bestDivss) ? (t4 - t3) : bestDivss;
    }
    printf("clock %.3f GHz (dependent integer adds); latency in cycles: addss %.2f, mulss %.2f, divss %.2f (%g %g %lu)\n",
           4e6 / bestAdd, bestAddss / bestAdd, bestMulss / bestAdd, 10.0 * bestDivss / bestAdd, (double) x, (double) z, y);
    return 0;
}
