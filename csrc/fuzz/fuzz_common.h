/*
 * fuzz_common.h - what every fuzzer shares: CHECK (abort with the failed
 * condition), a Reader over the fuzzer's bytes (ReadBytes; ReadFloat: 4 bytes
 * as a float32; ReadByte), Within (finite and |value| <= limit, in the unit of
 * the value), InRange (finite and in [minimum, maximum]) and IsInfinite.
 * Included by the fuzzers only.
 */
#ifndef FUZZ_COMMON_H
#define FUZZ_COMMON_H

#include "fusion_altitude.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CHECK(condition)                                                                \
    do {                                                                                \
        if (!(condition)) {                                                             \
            fprintf(stderr, "%s:%d: CHECK(%s) failed\n", __FILE__, __LINE__, #condition); \
            abort();                                                                    \
        }                                                                               \
    } while (0)

typedef struct {
    const uint8_t *data;
    size_t size;
} Reader;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static inline bool ReadBytes(Reader *const reader, void *const value, const size_t size) {
    if (reader->size < size) {
        return false;
    }
    memcpy(value, reader->data, size);
    reader->data += size;
    reader->size -= size;
    return true;
}

static inline bool ReadFloat(Reader *const reader, float *const value) {
    return ReadBytes(reader, value, sizeof(*value));
}

static inline bool ReadByte(Reader *const reader, uint8_t *const value) {
    return ReadBytes(reader, value, sizeof(*value));
}

static inline bool Within(const float value, const float limit) {
    return FusionAltitudeIsFinite(value) && (value <= limit) && (value >= -limit);
}

static inline bool InRange(const float value, const float minimum, const float maximum) {
    return FusionAltitudeIsFinite(value) && (value >= minimum) && (value <= maximum);
}

static inline bool IsInfinite(const float value) {
    return !FusionAltitudeIsFinite(value) && !FusionAltitudeIsNaN(value);
}

#endif
