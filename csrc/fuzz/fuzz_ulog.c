/**
 * @file fuzz_ulog.c
 * @brief libFuzzer target for the ULog scanner of the fast log decoder
 * (fusion_altitude/logs/_ulog_scan.h), built with clang under
 * AddressSanitizer + UndefinedBehaviorSanitizer:
 *
 *   clang -std=c99 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
 *       -Ifusion_altitude/logs -Icsrc csrc/fuzz/fuzz_ulog.c -o fuzz_ulog
 *   ./fuzz_ulog -max_total_time=600 csrc/fuzz/corpus_ulog
 *
 * The input is a whole ULog file (seeds: csrc/fuzz/make_seeds_ulog.py, the
 * test fixture); libFuzzer truncates, flips bits and splices it. Asserted on
 * every input (abort, so libFuzzer reports a crash):
 *   - ULogScan gives what a transcription of pyulog's message walk
 *     (ReferenceWalk: read a 3-byte header, stop if short; read the payload,
 *     stop if short) gives: every offset, type and size, and the end;
 *   - each message found lies wholly inside the data, in increasing order.
 * No read or write outside the input (ASan), no undefined behaviour (UBSan).
 */
#include "_ulog_scan.h"
#include "fuzz_common.h" /* CHECK */

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const size_t start = (size > ULOG_FILE_HEADER) ? ULOG_FILE_HEADER : size;
    const size_t capacity = size / 3 + 1;
    uint64_t *offsets = (uint64_t *) malloc(capacity * sizeof(uint64_t));
    uint8_t *types = (uint8_t *) malloc(capacity);
    uint16_t *sizes = (uint16_t *) malloc(capacity * sizeof(uint16_t));
    ULogScanResult result;
    size_t position = start;
    size_t k = 0;
    CHECK(offsets != NULL && types != NULL && sizes != NULL);
    ULogScan(data, size, start, offsets, types, sizes, capacity, &result);
    CHECK(result.full == 0);
    for (;;) { /* pyulog's walk: a header of 3 bytes, then its payload, else stop */
        size_t payload;
        if (size - position < 3) {
            break;
        }
        payload = (size_t) data[position] | ((size_t) data[position + 1] << 8);
        if (size - position - 3 < payload) {
            break;
        }
        CHECK(k < result.count);
        CHECK(offsets[k] == position && types[k] == data[position + 2] && sizes[k] == payload);
        CHECK(offsets[k] + 3 + sizes[k] <= size);
        CHECK(k == 0 || offsets[k] > offsets[k - 1]);
        position += 3 + payload;
        k++;
    }
    CHECK(k == result.count);
    CHECK(result.endOffset == position);
    free(offsets);
    free(types);
    free(sizes);
    return 0;
}
