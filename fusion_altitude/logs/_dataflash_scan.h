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

#include "_scan_common.h"

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

/* Bytes of one value of format character c (pymavlink's FORMAT_TO_STRUCT); 0 if pymavlink does not read c. */
static inline size_t DataFlashCharSize(const uint8_t c) {
    switch (c) {
        case 'b': case 'B': case 'M':
            return 1;
        case 'g': case 'h': case 'H': case 'c': case 'C':
            return 2;
        case 'i': case 'I': case 'f': case 'n': case 'e': case 'E': case 'L':
            return 4;
        case 'd': case 'q': case 'Q':
            return 8;
        case 'N':
            return 16;
        case 'a': case 'Z':
            return 64;
        default:
            return 0;
    }
}

/* Whether format character c holds text (or pymavlink's int16 array), not a number. */
static inline int DataFlashCharIsText(const uint8_t c) {
    return (c == 'a') || (c == 'n') || (c == 'N') || (c == 'Z');
}

/*
 * The column of each of names[0 .. nameCount) in a format: columns[0 ..
 * columnsLength) is the FMT's column text (names joined by commas);
 * nameLengths[j] is strlen(names[j]). index[j] is the last column named
 * names[j] (pymavlink's column lookup keeps the last), or -1 if none is.
 */
static inline void DataFlashColumnIndexes(const uint8_t *const columns, const size_t columnsLength,
                                          const char *const *const names, const size_t *const nameLengths,
                                          const size_t nameCount, int16_t *const index) {
    size_t start = 0;
    int16_t column = 0;
    size_t j;
    for (j = 0; j < nameCount; j++) {
        index[j] = -1;
    }
    if (columnsLength == 0) {
        return; /* no columns (pymavlink: an empty list) */
    }
    while (start <= columnsLength) {
        size_t end = start;
        while ((end < columnsLength) && (columns[end] != ',')) {
            end++;
        }
        for (j = 0; j < nameCount; j++) {
            if ((nameLengths[j] == end - start) && (nameLengths[j] > 0) && ((uint8_t) names[j][0] == columns[start]) &&
                (memcmp(columns + start, names[j], nameLengths[j]) == 0)) {
                index[j] = column;
            }
        }
        start = end + 1;
        column++;
    }
}

/* Bytes before field `index` of a message body with format characters chars[0 .. index). */
static inline size_t DataFlashFieldOffset(const uint8_t *const chars, const size_t index) {
    size_t k;
    size_t offset = 0;
    for (k = 0; k < index; k++) {
        offset += DataFlashCharSize(chars[k]);
    }
    return offset;
}

/*
 * Split offsets[0 .. count) by type, keeping file order: the offsets of
 * type t go to rows[t] (sized by ScanCountTypes; rows[t] may be NULL
 * for a type not wanted, whose offsets are then dropped).
 */
static inline void DataFlashSplit(const uint64_t *const offsets, const uint8_t *const types, const size_t count,
                                  uint64_t *const *const rows) {
    size_t filled[256];
    size_t k;
    for (k = 0; k < 256; k++) {
        filled[k] = 0;
    }
    for (k = 0; k < count; k++) {
        uint64_t *const row = rows[types[k]];
        if (row != NULL) {
            row[filled[types[k]]++] = offsets[k];
        }
    }
}

/* Little-endian unsigned integer of `bytes` bytes at p. */
static inline uint64_t DataFlashUnsigned(const uint8_t *const p, const size_t bytes) {
    uint64_t value = 0;
    size_t k;
    for (k = bytes; k > 0; k--) {
        value = (value << 8) | p[k - 1];
    }
    return value;
}

/* The two's-complement value of the low `bytes` bytes of `value`. */
static inline int64_t DataFlashSigned(const uint64_t value, const size_t bytes) {
    const uint64_t sign = (uint64_t) 1 << (8 * bytes - 1);
    if ((value & sign) == 0) {
        return (int64_t) value;
    }
    /* value - 2^(8 bytes), without overflow: -(complement) - 1 */
    return -(int64_t) ((~value) & ((sign - 1) | sign)) - 1;
}

typedef enum {
    DataFlashColumnOk = 0,
    /* A character the column reader does not read as a number (text, half float 'g', unknown). */
    DataFlashColumnNotNumeric = 1,
    /* A field that runs past the end of the data. */
    DataFlashColumnOutside = 2,
} DataFlashColumnStatus;

/*
 * One numeric field of the messages at offsets[0 .. count) as doubles, the
 * value pymavlink's DFMessage gives converted to float: integers exactly
 * (q/Q rounded to nearest), f widened, d as it is, c/C/e/E divided by 100
 * (pymavlink: value / (1 / 0.01)), L divided by 1e7 (value / (1 / 1e-7)).
 * The field is formatChar at fieldOffset bytes into the body (after the
 * 3-byte header). out[k] for message k. Returns the status (out is then
 * partly written).
 */
static inline DataFlashColumnStatus DataFlashColumn(const uint8_t *const data, const size_t size,
                                                    const uint64_t *const offsets, const size_t count,
                                                    const size_t fieldOffset, const uint8_t formatChar,
                                                    double *const out) {
    const size_t bytes = DataFlashCharSize(formatChar);
    double divisor = 0.0; /* 0: no multiplier */
    size_t k;
    if ((bytes == 0) || DataFlashCharIsText(formatChar) || (formatChar == 'g')) {
        return DataFlashColumnNotNumeric;
    }
    if ((formatChar == 'c') || (formatChar == 'C') || (formatChar == 'e') || (formatChar == 'E')) {
        divisor = 100.0;
    } else if (formatChar == 'L') {
        divisor = 10000000.0;
    }
    for (k = 0; k < count; k++) {
        const uint64_t start = offsets[k] + 3 + fieldOffset;
        const uint8_t *p;
        uint64_t raw;
        double value;
        if ((start > size) || (bytes > size - start)) {
            return DataFlashColumnOutside;
        }
        p = data + start;
        raw = DataFlashUnsigned(p, bytes);
        switch (formatChar) {
            case 'f': {
                const uint32_t word = (uint32_t) raw;
                float single;
                memcpy(&single, &word, sizeof single);
                value = (double) single;
                break;
            }
            case 'd':
                memcpy(&value, &raw, sizeof value);
                break;
            case 'B': case 'H': case 'I': case 'C': case 'E': case 'Q':
                value = (double) raw;
                break;
            default: /* b M h c i e L q: signed */
                value = (double) DataFlashSigned(raw, bytes);
                break;
        }
        out[k] = (divisor != 0.0) ? (value / divisor) : value;
    }
    return DataFlashColumnOk;
}

/* Slots of DataFlashNameSeen's table: more than twice the 256 types. */
#define DATAFLASH_NAME_SLOTS 1024

/* The 4-byte name field of an FMT, cut at its first NUL, as a number (first byte lowest). */
static inline uint32_t DataFlashNameKey(const uint8_t *const name) {
    uint32_t key = 0;
    size_t k;
    for (k = 0; (k < 4) && (name[k] != 0); k++) {
        key |= (uint32_t) name[k] << (8 * k);
    }
    return key;
}

/*
 * Whether `key` was met before in `slots` (DATAFLASH_NAME_SLOTS entries,
 * zeroed before the first call): 1 if so, else 0 and it is added; -1 if the
 * table is full (more keys than slots: a log has at most 256, one per type).
 * Open addressing.
 */
static inline int DataFlashNameSeen(uint64_t *const slots, const uint32_t key) {
    size_t slot = (size_t) ((key * 2654435761u) % DATAFLASH_NAME_SLOTS);
    size_t probe;
    for (probe = 0; probe < DATAFLASH_NAME_SLOTS; probe++) {
        if (slots[slot] == 0) {
            slots[slot] = (uint64_t) key + 1;
            return 0;
        }
        if (slots[slot] == (uint64_t) key + 1) {
            return 1;
        }
        slot = (slot + 1) % DATAFLASH_NAME_SLOTS;
    }
    return -1;
}

/*
 * The struct code pymavlink unpacks format character c with (FORMAT_TO_STRUCT):
 * characters of one code read the same bytes the same way (c and h, e and i, ...)
 * and differ at most in their multiplier. 0 if pymavlink does not read c.
 */
static inline uint8_t DataFlashCharStruct(const uint8_t c) {
    switch (c) {
        case 'b': case 'M':
            return 'b';
        case 'h': case 'c':
            return 'h';
        case 'H': case 'C':
            return 'H';
        case 'i': case 'e': case 'L':
            return 'i';
        case 'I': case 'E':
            return 'I';
        case 'a': case 'Z':
            return 'Z';
        case 'B': case 'g': case 'f': case 'n': case 'N': case 'd': case 'q': case 'Q':
            return c;
        default:
            return 0;
    }
}

#endif
