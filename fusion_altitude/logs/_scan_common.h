/**
 * @file _scan_common.h
 * @brief What the DataFlash and ULog scanners share: counting messages by type.
 *
 * Part of the fast log decoder (fusion_altitude/logs/_decode.pyx), not of the
 * MCU core. C99, no allocation, no globals.
 */

#ifndef FUSION_ALTITUDE_SCAN_COMMON_H
#define FUSION_ALTITUDE_SCAN_COMMON_H

#include <stddef.h>
#include <stdint.h>

/* How many of types[0 .. count) are of each message type (counts: 256 entries, overwritten). */
static inline void ScanCountTypes(const uint8_t *const types, const size_t count, uint64_t *const counts) {
    size_t k;
    for (k = 0; k < 256; k++) {
        counts[k] = 0;
    }
    for (k = 0; k < count; k++) {
        counts[types[k]]++;
    }
}

#endif
