/**
 * @file test_harness.h
 * @brief The few lines every C test program here shares: CHECK a condition,
 * RUN a test function, and a closing "N passed, M failed" line that
 * tests/test_c_core.py (and CI) read.
 */

#ifndef FUSION_ALTITUDE_TEST_HARNESS_H
#define FUSION_ALTITUDE_TEST_HARNESS_H

#include <stdio.h>

static int testsPassed = 0;
static int testsFailed = 0;
static int currentTestFailed = 0;

/** Records a failure of the current test (and carries on with it). */
#define CHECK(condition)                                                           \
    do {                                                                           \
        if (!(condition)) {                                                        \
            printf("  %s:%d: CHECK(%s) failed\n", __FILE__, __LINE__, #condition); \
            currentTestFailed = 1;                                                 \
        }                                                                          \
    } while (0)

/** Runs one test function and prints "ok" or "FAIL" with its name. */
#define RUN(test)                                                  \
    do {                                                           \
        currentTestFailed = 0;                                     \
        test();                                                    \
        printf("%s %s\n", currentTestFailed ? "FAIL" : "ok  ", #test); \
        if (currentTestFailed) {                                   \
            testsFailed++;                                         \
        } else {                                                   \
            testsPassed++;                                         \
        }                                                          \
    } while (0)

/** Prints the closing line; returns the process exit status. */
static inline int TestSummary(void) {
    printf("%d passed, %d failed\n", testsPassed, testsFailed);
    return testsFailed == 0 ? 0 : 1;
}

#endif
