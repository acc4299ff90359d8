/*
 * _ulog_scan.h - one pass over the messages of a PX4 ULog (.ulg): where each
 * starts, its type and payload size, as pyulog walks them (3-byte header:
 * uint16 payload size, uint8 type; then the payload).
 *
 * The walk stops where a header or a payload would run past the end of the
 * data (a cut file, as pyulog stops). Not part of the microcontroller core:
 * no float, bounds-checked on every read, no allocation (the caller gives
 * the output arrays), C99 and C++.
 */
#ifndef FUSION_ALTITUDE_ULOG_SCAN_H
#define FUSION_ALTITUDE_ULOG_SCAN_H

#include <stddef.h>
#include <stdint.h>

/* Bytes of the ULog file header (magic, version, start time) before the first message. */
#define ULOG_FILE_HEADER 16

typedef struct {
    size_t count;      /* messages found */
    size_t endOffset;  /* byte after the last whole message (where pyulog stops) */
    int full;          /* 1 if the output arrays filled up before the end */
} ULogScanResult;

/*
 * Walk data[start .. size): writes the start (byte offset of the header),
 * type and payload size (bytes) of each whole message to offsets[], types[]
 * and sizes[] (capacity entries each; (size - start) / 3 + 1 is enough).
 */
static inline void ULogScan(const uint8_t *const data, const size_t size, const size_t start,
                            uint64_t *const offsets, uint8_t *const types, uint16_t *const sizes,
                            const size_t capacity, ULogScanResult *const result) {
    size_t position = start;
    result->count = 0;
    result->full = 0;
    while ((position <= size) && (size - position >= 3)) {
        const size_t payload = (size_t) data[position] | ((size_t) data[position + 1] << 8);
        if (size - position - 3 < payload) {
            break;
        }
        if (result->count >= capacity) {
            result->full = 1;
            break;
        }
        offsets[result->count] = (uint64_t) position;
        types[result->count] = data[position + 2];
        sizes[result->count] = (uint16_t) payload;
        result->count++;
        position += 3 + payload;
    }
    result->endOffset = position;
}

#endif
