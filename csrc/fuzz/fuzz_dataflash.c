/**
 * @file fuzz_dataflash.c
 * @brief libFuzzer target for the DataFlash scanner of the fast log decoder
 * (fusion_altitude/logs/_dataflash_scan.h), built with clang under
 * AddressSanitizer + UndefinedBehaviorSanitizer:
 *
 *   clang -std=c99 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
 *       -Ifusion_altitude/logs -Icsrc csrc/fuzz/fuzz_dataflash.c -o fuzz_dataflash
 *   ./fuzz_dataflash -max_total_time=600 csrc/fuzz/corpus_dataflash
 *
 * The input is a whole log file (seeds: csrc/fuzz/make_seeds_dataflash.py, the
 * test fixtures of both generations); libFuzzer truncates, flips bits and
 * splices it. Asserted on every input (abort, so libFuzzer reports a crash):
 *   - DataFlashScan gives exactly what a byte-at-a-time transcription of
 *     pymavlink's indexer (ReferenceScan below) gives: every offset and type,
 *     the bad-header count, the status and where it stopped;
 *   - every offset found starts an A3 95 header of the type reported, inside
 *     the data, in increasing order;
 *   - DataFlashGather of each type's messages copies exactly the bytes of
 *     the body inside the data and zeros past its end;
 *   - the field lookup and the column reader the fast decoder runs on every
 *     log (CheckFormats below), against plain transcriptions: for every whole
 *     FMT message, DataFlashColumnIndexes of the reader's and the clock's
 *     field names (the last column of each name), DataFlashFieldOffset,
 *     DataFlashCharStruct (same size as DataFlashCharSize), DataFlashNameKey
 *     and DataFlashNameSeen (a linear search of the names met), and for each
 *     field found DataFlashColumn over the messages of that type (each value
 *     as memcpy into the C type gives it, divided as pymavlink's multiplier
 *     does, bit for bit); ScanCountTypes and DataFlashSplit (every
 *     type's offsets in file order) against a filter.
 * No read or write outside the input (ASan), no undefined behaviour (UBSan).
 */
#include "_dataflash_scan.h"
#include "fuzz_common.h" /* CHECK */

/* pymavlink's scan_offsets, one byte at a time (its process exit becomes a status). */
static DataFlashScanStatus ReferenceScan(const uint8_t *data, size_t size, uint64_t *offsets, uint8_t *types,
                                         DataFlashScanResult *result) {
    size_t i = 0;
    memset(result->lengths, 0, sizeof(result->lengths));
    result->lengths[DATAFLASH_FMT_TYPE] = DATAFLASH_FMT_LENGTH;
    result->count = 0;
    result->badHeaders = 0;
    result->stopOffset = size;
    while (i + 3 < size) {
        if (data[i] != DATAFLASH_HEAD1 || data[i + 1] != DATAFLASH_HEAD2) {
            if (size - i >= DATAFLASH_TAIL_ALLOWANCE || size < DATAFLASH_TAIL_ALLOWANCE) {
                result->badHeaders++;
            }
            i++;
            continue;
        }
        if (data[i + 2] == DATAFLASH_FMT_TYPE) {
            const uint8_t length = (i + 4 < size) ? data[i + 4] : 0;
            if (length < 3) {
                result->stopOffset = i;
                return DataFlashScanBadFmtLength;
            }
            result->lengths[data[i + 3]] = length;
        }
        if (result->lengths[data[i + 2]] == 0) {
            result->stopOffset = i;
            return DataFlashScanUnknownType;
        }
        offsets[result->count] = i;
        types[result->count] = data[i + 2];
        result->count++;
        i += result->lengths[data[i + 2]];
    }
    return DataFlashScanOk;
}

/* Column names looked up in every FMT: the DataFlash reader's fields and pymavlink's clock fields. */
static const char *const fieldNames[] = {"TimeUS", "TimeMS", "T", "Week", "GWk", "GMS", "Wk", "TWk", "GPSTime",
                                         "StartTime", "ModeNum", "MainState", "Default", "BU", "I", "C", "AccX",
                                         "AccY", "AccZ", "GyrX", "GyrY", "GyrZ", "Roll", "Pitch", "Yaw", "Alt",
                                         "Press", "Temp", "Status", "NSats", "VAcc", "Dist", "Dist1", "Stat", "PD",
                                         "VD", "ArmState", "Message", ""};
#define FIELD_COUNT (sizeof(fieldNames) / sizeof(fieldNames[0]))

/* The last column named `name` in columns[0 .. length) (names joined by commas), or -1. */
static int ReferenceColumn(const uint8_t *columns, size_t length, const char *name) {
    int found = -1;
    int column = 0;
    size_t start = 0;
    size_t k;
    if (length == 0) {
        return -1;
    }
    for (k = 0; k <= length; k++) {
        if (k == length || columns[k] == ',') {
            if (k - start == strlen(name) && strlen(name) > 0 && memcmp(columns + start, name, k - start) == 0) {
                found = column;
            }
            column++;
            start = k + 1;
        }
    }
    return found;
}

/* One value of format character c at p, as pymavlink gives it converted to float (memcpy into the C type). */
static double ReferenceValue(const uint8_t *p, uint8_t c) {
    int8_t i8; uint8_t u8; int16_t i16; uint16_t u16; int32_t i32; uint32_t u32; int64_t i64; uint64_t u64;
    float f32; double f64;
    switch (c) {
        case 'b': case 'M': memcpy(&i8, p, 1); return (double) i8;
        case 'B': memcpy(&u8, p, 1); return (double) u8;
        case 'h': memcpy(&i16, p, 2); return (double) i16;
        case 'c': memcpy(&i16, p, 2); return (double) i16 / 100.0;
        case 'H': memcpy(&u16, p, 2); return (double) u16;
        case 'C': memcpy(&u16, p, 2); return (double) u16 / 100.0;
        case 'i': memcpy(&i32, p, 4); return (double) i32;
        case 'e': memcpy(&i32, p, 4); return (double) i32 / 100.0;
        case 'L': memcpy(&i32, p, 4); return (double) i32 / 10000000.0;
        case 'I': memcpy(&u32, p, 4); return (double) u32;
        case 'E': memcpy(&u32, p, 4); return (double) u32 / 100.0;
        case 'f': memcpy(&f32, p, 4); return (double) f32;
        case 'd': memcpy(&f64, p, 8); return f64;
        case 'q': memcpy(&i64, p, 8); return (double) i64;
        case 'Q': memcpy(&u64, p, 8); return (double) u64;
        default: CHECK(0); return 0.0;
    }
}

/* ScanCountTypes and DataFlashSplit against a filter; rows[t] (NULL for every third type: dropped) is
 * left holding type t's offsets, counts[t] their number. */
static void CheckSplit(const uint64_t *offsets, const uint8_t *types, size_t count, uint64_t *counts,
                       uint64_t **rows) {
    size_t k;
    size_t j;
    ScanCountTypes(types, count, counts);
    for (j = 0; j < 256; j++) {
        size_t expected = 0;
        for (k = 0; k < count; k++) {
            expected += (types[k] == j) ? 1 : 0;
        }
        CHECK(counts[j] == expected);
        rows[j] = (counts[j] > 0 && (j % 3) != 2) ? (uint64_t *) malloc(counts[j] * sizeof(uint64_t)) : NULL;
    }
    DataFlashSplit(offsets, types, count, rows);
    for (j = 0; j < 256; j++) {
        size_t filled = 0;
        if (rows[j] == NULL) {
            continue;
        }
        for (k = 0; k < count; k++) {
            if (types[k] == j) {
                CHECK(rows[j][filled++] == offsets[k]);
            }
        }
    }
}

/* DataFlashColumn of the field `formatChar` at `offset` bytes into the body of the messages at rows[0 .. count)
 * (total: their length with the header, by the FMT read), against ReferenceValue. */
static void CheckColumn(const uint8_t *data, size_t size, const uint64_t *rows, size_t count, size_t total,
                        size_t offset, uint8_t formatChar) {
    double *values = (double *) malloc(count * sizeof(double) + 1);
    size_t whole = 0;
    DataFlashColumnStatus status;
    size_t row;
    CHECK(values != NULL);
    while (whole < count && rows[whole] + total <= size) {
        whole++;
    }
    status = DataFlashColumn(data, size, rows, whole, offset, formatChar, values);
    if (DataFlashCharIsText(formatChar) || formatChar == 'g') {
        CHECK(status == DataFlashColumnNotNumeric);
        free(values);
        return;
    }
    CHECK(status == DataFlashColumnOk);
    for (row = 0; row < whole; row++) {
        const double expected = ReferenceValue(data + rows[row] + 3 + offset, formatChar);
        CHECK(memcmp(&values[row], &expected, sizeof(double)) == 0);
    }
    if (whole < count && rows[whole] + 3 + offset + DataFlashCharSize(formatChar) > size) {
        /* a field past the end of the data is refused, not read */
        CHECK(DataFlashColumn(data, size, rows + whole, 1, offset, formatChar, values) == DataFlashColumnOutside);
    }
    free(values);
}

/* The lookups on one whole FMT message (body: its 86 bytes after the header), and the column reader on the
 * messages of the type it defines (rows[type], counts[type]). */
static void CheckFormatMessage(const uint8_t *data, size_t size, const uint8_t *body, const uint64_t *counts,
                               uint64_t *const *rows) {
    size_t lengths[FIELD_COUNT];
    int16_t index[FIELD_COUNT];
    size_t nchars = 0;
    size_t ncolumns = 0;
    size_t total = 3;
    int valid = 1;
    size_t j;
    while (nchars < 16 && body[6 + nchars] != 0) {
        const size_t bytes = DataFlashCharSize(body[6 + nchars]);
        CHECK((bytes == 0) == (DataFlashCharStruct(body[6 + nchars]) == 0));
        valid = valid && (bytes > 0);
        total += bytes;
        nchars++;
    }
    while (ncolumns < 64 && body[22 + ncolumns] != 0) {
        ncolumns++;
    }
    for (j = 0; j < FIELD_COUNT; j++) {
        lengths[j] = strlen(fieldNames[j]);
    }
    DataFlashColumnIndexes(body + 22, ncolumns, fieldNames, lengths, FIELD_COUNT, index);
    for (j = 0; j < FIELD_COUNT; j++) {
        size_t offset = 0;
        size_t c;
        CHECK(index[j] == ReferenceColumn(body + 22, ncolumns, fieldNames[j]));
        if (index[j] < 0 || (size_t) index[j] >= nchars || !valid) {
            continue;
        }
        for (c = 0; c < (size_t) index[j]; c++) {
            offset += DataFlashCharSize(body[6 + c]);
        }
        CHECK(DataFlashFieldOffset(body + 6, (size_t) index[j]) == offset);
        CHECK(offset < total);
        if (rows[body[0]] != NULL) {
            CheckColumn(data, size, rows[body[0]], counts[body[0]], total, offset, body[6 + index[j]]);
        }
    }
}

/* The format lookups and the column reader on every whole FMT message of the scan, the name hash against a
 * linear search, and the split by type. */
static void CheckFormats(const uint8_t *data, size_t size, const uint64_t *offsets, const uint8_t *types,
                         size_t count) {
    uint32_t keys[DATAFLASH_NAME_SLOTS];
    size_t keyCount = 0;
    uint64_t slots[DATAFLASH_NAME_SLOTS];
    uint64_t counts[256];
    uint64_t *rows[256];
    size_t k;
    size_t j;
    memset(slots, 0, sizeof(slots));
    CheckSplit(offsets, types, count, counts, rows);
    for (k = 0; k < count; k++) {
        uint32_t key;
        size_t seenBefore = 0;
        if (types[k] != DATAFLASH_FMT_TYPE || offsets[k] + DATAFLASH_FMT_LENGTH > size) {
            continue;
        }
        key = DataFlashNameKey(data + offsets[k] + 5);
        for (j = 0; j < keyCount; j++) {
            seenBefore = seenBefore || (keys[j] == key);
        }
        if (keyCount < DATAFLASH_NAME_SLOTS) {
            CHECK(DataFlashNameSeen(slots, key) == (int) seenBefore);
            if (!seenBefore) {
                keys[keyCount++] = key;
            }
        } else {
            CHECK(DataFlashNameSeen(slots, key) == (seenBefore ? 1 : -1));
        }
        CheckFormatMessage(data, size, data + offsets[k] + 3, counts, rows);
    }
    for (j = 0; j < 256; j++) {
        free(rows[j]);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const size_t capacity = size / 3 + 1;
    uint64_t *offsets = (uint64_t *) malloc(capacity * sizeof(uint64_t));
    uint8_t *types = (uint8_t *) malloc(capacity);
    uint64_t *expectedOffsets = (uint64_t *) malloc(capacity * sizeof(uint64_t));
    uint8_t *expectedTypes = (uint8_t *) malloc(capacity);
    DataFlashScanResult result;
    DataFlashScanResult expected;
    DataFlashScanStatus status;
    DataFlashScanStatus expectedStatus;
    size_t k;
    CHECK(offsets != NULL && types != NULL && expectedOffsets != NULL && expectedTypes != NULL);

    status = DataFlashScan(data, size, offsets, types, capacity, &result);
    expectedStatus = ReferenceScan(data, size, expectedOffsets, expectedTypes, &expected);
    CHECK(status == expectedStatus);
    CHECK(result.count == expected.count);
    CHECK(result.badHeaders == expected.badHeaders);
    CHECK(result.stopOffset == expected.stopOffset);
    CHECK(memcmp(result.lengths, expected.lengths, sizeof(result.lengths)) == 0);
    for (k = 0; k < result.count; k++) {
        CHECK(offsets[k] == expectedOffsets[k] && types[k] == expectedTypes[k]);
        CHECK(offsets[k] + 3 < size);
        CHECK(data[offsets[k]] == DATAFLASH_HEAD1 && data[offsets[k] + 1] == DATAFLASH_HEAD2);
        CHECK(data[offsets[k] + 2] == types[k]);
        CHECK(k == 0 || offsets[k] > offsets[k - 1]);
    }

    /* gather each type present (at the length the scan ended with), compare with the bytes */
    {
        int type;
        for (type = 0; type < 256; type++) {
            const size_t length = result.lengths[type];
            size_t count = 0;
            size_t complete;
            size_t row;
            uint64_t *mine;
            uint8_t *bodies;
            if (length < 3) {
                continue;
            }
            mine = (uint64_t *) malloc((result.count + 1) * sizeof(uint64_t));
            CHECK(mine != NULL);
            for (k = 0; k < result.count; k++) {
                if (types[k] == type) {
                    mine[count++] = offsets[k];
                }
            }
            if (count == 0) {
                free(mine);
                continue;
            }
            bodies = (uint8_t *) malloc(count * (length - 3) + 1);
            CHECK(bodies != NULL);
            complete = DataFlashGather(data, size, mine, count, length, bodies);
            CHECK(complete <= count);
            for (row = 0; row < count; row++) {
                size_t byte;
                for (byte = 0; byte < length - 3; byte++) {
                    const size_t at = (size_t) mine[row] + 3 + byte;
                    CHECK(bodies[row * (length - 3) + byte] == ((at < size) ? data[at] : 0));
                }
            }
            free(bodies);
            free(mine);
        }
    }
    CheckFormats(data, size, offsets, types, result.count);
    free(offsets);
    free(types);
    free(expectedOffsets);
    free(expectedTypes);
    return 0;
}
