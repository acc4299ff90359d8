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
 *     the body inside the data and zeros past its end.
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
    free(offsets);
    free(types);
    free(expectedOffsets);
    free(expectedTypes);
    return 0;
}
