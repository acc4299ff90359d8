/*
 * _dataflash_scan.h - one pass over the bytes of an ArduPilot DataFlash log
 * (.bin): where every message starts and of which type, the way pymavlink's
 * indexer (dfindexer) walks the file, so that the fast reader and pymavlink
 * find the same messages.
 *
 * A message is 0xA3 0x95, a type byte, then a body; its length (header
 * included, bytes) is the one the latest FMT message gave for that type
 * when the message is reached (FMT itself is 89 bytes unless an FMT
 * redefines it). Bytes that do not start a header are stepped over one at
 * a time and counted ("bad header"), except in the last 528 bytes of a file
 * of at least 528 bytes (end-of-log padding, as pymavlink).
 *
 * Not part of the microcontroller core: no float, bounds-checked on every
 * read, no allocation (the caller gives the output arrays), C99 and C++.
 */
#ifndef FUSION_ALTITUDE_DATAFLASH_SCAN_H
#define FUSION_ALTITUDE_DATAFLASH_SCAN_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

/* First two bytes of every message. */
#define DATAFLASH_HEAD1 0xA3
#define DATAFLASH_HEAD2 0x95
/* Type and length (bytes) of the FMT message that defines the others. */
#define DATAFLASH_FMT_TYPE 0x80
#define DATAFLASH_FMT_LENGTH 89
/* Trailing bytes of a file in which bad headers are not counted (pymavlink's end-of-log allowance). */
#define DATAFLASH_TAIL_ALLOWANCE 528

typedef enum {
    DataFlashScanOk = 0,
    /* An FMT gives a length below 3 bytes: pymavlink's indexer stops the program here. */
    DataFlashScanBadFmtLength = 1,
    /* A header of a type no FMT has defined yet: pymavlink's indexer stops the program here. */
    DataFlashScanUnknownType = 2,
    /* More messages than the output arrays hold. */
    DataFlashScanFull = 3,
} DataFlashScanStatus;

typedef struct {
    size_t count;          /* messages found (entries written to offsets/types) */
    size_t badHeaders;     /* bytes stepped over that did not start a header (counted as pymavlink prints them) */
    size_t stopOffset;     /* byte where the scan stopped on an error status, else the file size */
    uint8_t lengths[256];  /* length (bytes) of each type when the scan ended; 0: never defined */
} DataFlashScanResult;

/*
 * Scan data[0 .. size) once. Writes the start (byte offset) and the type of
 * every message, in file order, to offsets[] and types[] (capacity entries
 * each; size / 3 + 1 is always enough). Returns the status; result is filled
 * in every case (the messages found before an error stay valid).
 */
static inline DataFlashScanStatus DataFlashScan(const uint8_t *const data, const size_t size,
                                                uint64_t *const offsets, uint8_t *const types,
                                                const size_t capacity, DataFlashScanResult *const result) {
    size_t index;
    size_t i = 0;
    const int countAllBad = size < DATAFLASH_TAIL_ALLOWANCE;
    for (index = 0; index < 256; index++) {
        result->lengths[index] = 0;
    }
    result->lengths[DATAFLASH_FMT_TYPE] = DATAFLASH_FMT_LENGTH;
    result->count = 0;
    result->badHeaders = 0;
    result->stopOffset = size;
    while (i + 3 < size) {
        uint8_t type;
        uint8_t length;
        if ((data[i] != DATAFLASH_HEAD1) || (data[i + 1] != DATAFLASH_HEAD2)) {
            /* find the next candidate header in one call; each skipped byte is one "bad header" */
            const uint8_t *next = (const uint8_t *) memchr(data + i + 1, DATAFLASH_HEAD1, size - i - 1);
            const size_t end = (next == NULL) ? size : (size_t) (next - data);
            const size_t stop = (end < size - 3) ? end : size - 3; /* the loop runs while i + 3 < size */
            size_t step = (stop > i) ? (stop - i) : 1;
            size_t counted = step;
            if (!countAllBad) {
                /* only bytes with at least 528 bytes from them to the end are counted */
                const size_t lastCounted = size - DATAFLASH_TAIL_ALLOWANCE; /* i <= lastCounted is counted */
                counted = (i > lastCounted) ? 0 : (((i + step - 1) <= lastCounted) ? step : (lastCounted - i + 1));
            }
            result->badHeaders += counted;
            i += step;
            continue;
        }
        type = data[i + 2];
        if (type == DATAFLASH_FMT_TYPE) {
            /* the FMT body starts with the defined type and its length; a byte past the end reads as 0 */
            const uint8_t defined = data[i + 3];
            const uint8_t definedLength = (i + 4 < size) ? data[i + 4] : 0;
            if (definedLength < 3) {
                result->stopOffset = i;
                return DataFlashScanBadFmtLength;
            }
            result->lengths[defined] = definedLength;
        }
        length = result->lengths[type];
        if (length == 0) {
            result->stopOffset = i;
            return DataFlashScanUnknownType;
        }
        if (result->count >= capacity) {
            result->stopOffset = i;
            return DataFlashScanFull;
        }
        offsets[result->count] = (uint64_t) i;
        types[result->count] = type;
        result->count++;
        i += length;
    }
    return DataFlashScanOk;
}

/*
 * Copy the bodies (the length - 3 bytes after each header) of the messages
 * starting at offsets[0 .. count) into out (count rows of length - 3 bytes).
 * A body that runs past the end of the data is padded with zeros. Returns
 * the number of complete bodies.
 */
static inline size_t DataFlashGather(const uint8_t *const data, const size_t size, const uint64_t *const offsets,
                                     const size_t count, const size_t length, uint8_t *const out) {
    size_t row;
    size_t complete = 0;
    const size_t body = (length >= 3) ? (length - 3) : 0;
    for (row = 0; row < count; row++) {
        const uint64_t start = offsets[row] + 3;
        uint8_t *const destination = out + row * body;
        if ((start <= size) && (body <= size - start)) {
            memcpy(destination, data + start, body);
            complete++;
        } else {
            const size_t available = (start < size) ? (size_t) (size - start) : 0;
            if (available > 0) {
                memcpy(destination, data + start, available);
            }
            memset(destination + available, 0, body - available);
        }
    }
    return complete;
}

#endif
