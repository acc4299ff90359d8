/*
 * fuzz_common.h - what the observer, complementary-filter and sweep fuzzers
 * share: CHECK (abort with the failed condition), a Reader over the fuzzer's
 * bytes (ReadFloat: 4 bytes as a float32; ReadByte), and Within (finite and
 * |value| <= limit, in the unit of the value). Included by those fuzzers only.
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

static bool ReadFloat(Reader *const reader, float *const value) {
    if (reader->size < sizeof(*value)) {
        return false;
    }
    memcpy(value, reader->data, sizeof(*value));
    reader->data += sizeof(*value);
    reader->size -= sizeof(*value);
    return true;
}

static bool ReadByte(Reader *const reader, uint8_t *const value) {
    if (reader->size < 1u) {
        return false;
    }
    *value = reader->data[0];
    reader->data++;
    reader->size--;
    return true;
}

static bool Within(const float value, const float limit) {
    return FusionAltitudeIsFinite(value) && (value <= limit) && (value >= -limit);
}

#endif
