/**
 * @file fuzz_ulog.c
 * @brief libFuzzer target for the ULog walks of the fast log decoder
 * (fusion_altitude/logs/_ulog_scan.h), built with clang under
 * AddressSanitizer + UndefinedBehaviorSanitizer:
 *
 *   clang -std=c99 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
 *       -Ifusion_altitude/logs -Icsrc csrc/fuzz/fuzz_ulog.c -o fuzz_ulog
 *   ./fuzz_ulog -max_total_time=600 -max_len=8192 -seed=1 corpus   (a copy of csrc/fuzz/corpus_ulog)
 *
 * The input is a whole ULog file (seeds: csrc/fuzz/make_seeds_ulog.py, the
 * test fixtures, plain, with stray bytes before a sync message and with data
 * appended); libFuzzer truncates, flips bits and splices it. Asserted on
 * every input (abort, so libFuzzer reports a crash):
 *   - ULogWalkDefinitions and ULogWalkData give what a transcription of
 *     pyulog's reading (Reference*: a file position, reads that come back
 *     short at the end, the sync search in 512-byte chunks overlapping by 7
 *     bytes as pyulog's _find_sync) gives: every message, the segments, the
 *     data section's start;
 *   - the data walk is run with the flag-bits message's appended offsets and
 *     with three offsets taken from the file header's time stamp bytes (so
 *     the fuzzer steers them);
 *   - ULogPlainEnd is the end of the plain walk;
 *   - each message found lies wholly inside the data;
 *   - the checks and the gather of the fast decoder on the messages found:
 *     ULogCheckInfos (a verdict of 0, 1 or 2; "parses" only with a space in
 *     an ASCII key), ULogFormatNameLengths (a name is ASCII and ends at the
 *     first ':'), ScanCountTypes (they add up), ULogSamples (counting, then
 *     copying) with a subscription per A message of the data
 *     section (its msg_id; the sample size that of the first D message of
 *     that msg_id after it): each gathered sample is, in order, the payload of
 *     a D message of that msg_id and size after the A message, as a plain
 *     loop finds them;
 *   - the fast decoder's per-message checks on the same messages (both walks):
 *     ULogCheckInfos' verdicts equal a byte-at-a-time transcription of pyulog's
 *     key reading (ReferenceCheckInfo); ULogCheckMessages and ULogCheckAndCount
 *     give the failed table, the undecided list (capacity 0-3 from byte 15 of
 *     the header) and its count of a plain loop (ReferenceCheckMessage: L C A D
 *     shorter than 9 11 3 2 bytes, O not of 2); ULogCheckAndCount's counts and
 *     sample slots are a plain loop's over the subscriptions (ReferenceSampleSlot);
 *     ULogCopySamples fills each table with exactly the samples' bytes in file
 *     order and writes nothing past them, nothing where rows is NULL (chosen by
 *     the bits of byte 16). Extra seeds: csrc/fuzz/make_seeds_ulog_checks.py.
 * No read or write outside the input (ASan), no undefined behaviour (UBSan).
 */
#include <string.h>

#include "_ulog_scan.h"
#include "fuzz_common.h" /* CHECK */

static void CheckChecks(const uint8_t *data, size_t size, const ULogMessages *walk, size_t count);
static void CheckMessageChecks(const uint8_t *data, const ULogMessages *walk, size_t count, size_t capacity);
static uint8_t ReferenceCheckInfo(const uint8_t *payload, size_t size, size_t skip);

static const uint8_t SYNC[ULOG_SYNC_SIZE] = {0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12};

typedef struct { /* pyulog's file handle: a position that may lie past the end */
    const uint8_t *data;
    size_t size;
    uint64_t position;
} File;

static size_t FileRead(File *const file, const size_t wanted) { /* bytes a read of wanted gives */
    const size_t left = (file->position < file->size) ? file->size - (size_t) file->position : 0;
    const size_t got = (wanted < left) ? wanted : left;
    file->position += got;
    return got;
}

/* pyulog's _find_sync(): 512-byte chunks, each next one 7 bytes back; position after the sync or unchanged. */
static int ReferenceFindSyncToEnd(File *const file) {
    const uint64_t initial = file->position;
    for (;;) {
        const uint64_t chunkStart = file->position;
        const size_t got = FileRead(file, 512);
        size_t k;
        if (got < ULOG_SYNC_SIZE) {
            break;
        }
        for (k = 0; k + ULOG_SYNC_SIZE <= got; k++) {
            if (memcmp(file->data + chunkStart + k, SYNC, ULOG_SYNC_SIZE) == 0) {
                file->position = chunkStart + k + ULOG_SYNC_SIZE;
                return 1;
            }
        }
        file->position -= ULOG_SYNC_SIZE - 1;
    }
    file->position = initial;
    return 0;
}

/* pyulog's _find_sync(last_n_bytes): the last n bytes read only. */
static int ReferenceFindSyncIn(File *const file, const size_t n) {
    const uint64_t initial = file->position;
    const uint64_t chunkStart = initial - n;
    size_t k;
    if (n >= ULOG_SYNC_SIZE) {
        for (k = 0; k + ULOG_SYNC_SIZE <= n; k++) {
            if (memcmp(file->data + chunkStart + k, SYNC, ULOG_SYNC_SIZE) == 0) {
                file->position = chunkStart + k + ULOG_SYNC_SIZE;
                return 1;
            }
        }
    }
    file->position = initial;
    return 0;
}

/* pyulog's _read_file_data for one segment; checks each message against walk[*next ..]. */
static void ReferenceSegment(File *const file, const uint64_t until, int *const hasSync, const ULogMessages *const walk,
                             size_t *const next) {
    uint64_t counted = file->position;
    for (;;) {
        const uint64_t start = file->position;
        size_t payload;
        uint8_t type;
        if (FileRead(file, 3) < 3) {
            return;
        }
        payload = (size_t) file->data[start] | ((size_t) file->data[start + 1] << 8);
        type = file->data[start + 2];
        counted += 3;
        counted += FileRead(file, payload);
        if (file->position - start - 3 < payload) {
            return;
        }
        if (counted > until) {
            return;
        }
        if (strchr("IMPQALCDOS", type) != NULL && type != 0) {
            CHECK(walk->offsets[*next] == start && walk->types[*next] == type && walk->sizes[*next] == payload);
            (*next)++;
        } else if (type == 0 || payload == 0 || payload > 10000) {
            file->position = start + 1;
            counted = file->position;
            if (*hasSync && !ReferenceFindSyncToEnd(file)) {
                *hasSync = 0;
            }
        } else if (*hasSync) {
            (void) ReferenceFindSyncIn(file, payload);
        }
    }
}

/* The data walk with the given appended offsets, against the reference. */
static void CheckDataWalk(const uint8_t *data, size_t size, size_t sectionStart, const uint64_t *appended,
                          size_t count, const ULogMessages *walk) {
    ULogDataResult result;
    File file = {data, size, sectionStart};
    int hasSync = 1;
    size_t next = 0;
    size_t segment;
    ULogWalkData(data, size, sectionStart, appended, count, walk, &result);
    CHECK(result.full == 0 && result.segments == count + 1);
    for (segment = 0; segment <= count; segment++) {
        ReferenceSegment(&file, (segment < count) ? appended[segment] : UINT64_MAX, &hasSync, walk, &next);
        CHECK(next == result.segmentEnds[segment]);
        if (segment < count) {
            file.position = appended[segment];
        }
    }
    for (next = 0; next < result.count; next++) {
        CHECK(walk->offsets[next] + 3 + walk->sizes[next] <= size);
    }
}

/* pyulog's _read_file_definitions against ULogWalkDefinitions; returns the data section's start (or size + 1). */
static size_t CheckDefinitions(const uint8_t *data, size_t size, const ULogMessages *walk, uint64_t *appended,
                               size_t *appendedCount) {
    ULogDefinitionsResult result;
    File file = {data, size, ULOG_FILE_HEADER};
    size_t next = 0;
    int incompatible = 0;
    ULogWalkDefinitions(data, size, ULOG_FILE_HEADER, walk, &result);
    CHECK(result.full == 0);
    *appendedCount = 0;
    for (;;) {
        const uint64_t start = file.position;
        size_t payload;
        uint8_t type;
        if (FileRead(&file, 3) < 3) {
            CHECK(!result.found && (result.cut == (file.position != start)));
            break;
        }
        payload = (size_t) data[start] | ((size_t) data[start + 1] << 8);
        type = data[start + 2];
        if (FileRead(&file, payload) < payload) {
            CHECK(!result.found && result.cut && next == result.count);
            break;
        }
        if (type == 'A' || type == 'L' || type == 'C') {
            CHECK(result.found && !result.cut && result.sectionStart == start && next == result.count);
            break;
        }
        if (type != 0 && strchr("IMFPQB", type) != NULL) {
            CHECK(next < result.count && walk->offsets[next] == start && walk->sizes[next] == payload);
            next++;
            if (type == 'B' && payload >= 40) { /* the last flag bits of 40 bytes or more win */
                size_t k;
                incompatible = data[start + 3 + 8] & 1;
                *appendedCount = 0;
                for (k = 0; k < 3; k++) {
                    memcpy(&appended[k], data + start + 3 + 16 + 8 * k, 8); /* little-endian hosts */
                    if (appended[k] != 0) {
                        *appendedCount = k + 1;
                    }
                }
            }
        } else if (type == 0 || payload == 0 || payload > 10000) {
            file.position = start + 1;
        }
    }
    if (!incompatible) {
        *appendedCount = 0;
    }
    CheckChecks(data, size, walk, result.count);
    return result.found ? result.sectionStart : size + 1;
}

/* ULogCheckInfos and ULogFormatNameLengths on the messages found, against what their verdicts promise. */
static void CheckChecks(const uint8_t *data, size_t size, const ULogMessages *walk, size_t count) {
    uint8_t *verdicts = (uint8_t *) malloc(count + 1);
    size_t *lengths = (size_t *) malloc((count + 1) * sizeof(size_t));
    uint64_t counts[256];
    uint64_t total = 0;
    size_t k, j, skip;
    CHECK(verdicts != NULL && lengths != NULL);
    for (skip = 0; skip < 2; skip++) {
        CHECK(ULogCheckInfos(data, size, walk->offsets, walk->sizes, count, skip, verdicts) == 1);
        for (k = 0; k < count; k++) {
            const uint8_t *payload = data + walk->offsets[k] + 3 + skip;
            int space = 0;
            CHECK(verdicts[k] <= ULogInfoUndecided);
            CHECK(verdicts[k] == ReferenceCheckInfo(data + walk->offsets[k] + 3, walk->sizes[k], skip));
            if (verdicts[k] == ULogInfoParses) {
                for (j = 0; j < payload[0] && j + 1 < walk->sizes[k] - skip; j++) {
                    CHECK(payload[1 + j] < 0x80);
                    space |= payload[1 + j] == ' ';
                }
                CHECK(space);
            }
        }
    }
    CHECK(ULogFormatNameLengths(data, size, walk->offsets, walk->sizes, count, lengths) == 1);
    for (k = 0; k < count; k++) {
        if (lengths[k] != SIZE_MAX) {
            const uint8_t *payload = data + walk->offsets[k] + 3;
            CHECK(lengths[k] < walk->sizes[k] && payload[lengths[k]] == ':');
            for (j = 0; j < lengths[k]; j++) {
                CHECK(payload[j] < 0x80 && payload[j] != ':');
            }
        }
    }
    ScanCountTypes(walk->types, count, counts);
    for (k = 0; k < 256; k++) {
        total += counts[k];
    }
    CHECK(total == count);
    CheckMessageChecks(data, walk, count, data[15] % 4);
    free(verdicts);
    free(lengths);
}

/* The msg_id of message k (a D or A message: bytes 0-1 or 1-2 of the payload). */
static size_t MsgId(const uint8_t *data, const ULogMessages *walk, size_t k, size_t at) {
    return (size_t) data[walk->offsets[k] + 3 + at] | ((size_t) data[walk->offsets[k] + 4 + at] << 8);
}

/*
 * A subscription per A message of the count messages (the first of each msg_id,
 * at most 64): slotOf[msg_id] = 1 + its index, its A message's offset, the
 * sample size of the first D message of that msg_id after it (0 if none) and,
 * if msgIds is not NULL, its msg_id. Returns how many there are.
 */
static size_t Subscribe(const uint8_t *data, const ULogMessages *walk, size_t count, uint16_t *slotOf,
                        uint64_t *starts, uint64_t *itemsizes, size_t *msgIds) {
    size_t nsub = 0, k, j;
    for (k = 0; k < count && nsub < 64; k++) {
        if (walk->types[k] == 'A' && walk->sizes[k] >= 3 && slotOf[MsgId(data, walk, k, 1)] == 0) {
            starts[nsub] = walk->offsets[k];
            itemsizes[nsub] = 0;
            for (j = k + 1; j < count; j++) {
                if (walk->types[j] == 'D' && walk->sizes[j] >= 2 &&
                    MsgId(data, walk, j, 0) == MsgId(data, walk, k, 1)) {
                    itemsizes[nsub] = walk->sizes[j] - 2u;
                    break;
                }
            }
            if (msgIds != NULL) {
                msgIds[nsub] = MsgId(data, walk, k, 1);
            }
            slotOf[MsgId(data, walk, k, 1)] = (uint16_t) ++nsub;
        }
    }
    return nsub;
}

/* ULogSamples (counts, then copies) against a plain loop, a subscription per A message. */
static void CheckGather(const uint8_t *data, const ULogMessages *walk, size_t count) {
    uint16_t *slotOf = (uint16_t *) calloc(65536, sizeof(uint16_t));
    uint64_t starts[64], itemsizes[64], counts[64];
    uint8_t *tables[64], *rows[64];
    ULogSubscriptions wanted = {slotOf, starts, itemsizes};
    size_t nsub, k, slot;
    CHECK(slotOf != NULL);
    nsub = Subscribe(data, walk, count, slotOf, starts, itemsizes, NULL);
    for (slot = 0; slot < nsub; slot++) {
        counts[slot] = 0;
    }
    ULogSamples(data, walk->offsets, walk->types, walk->sizes, count, &wanted, counts, NULL);
    for (slot = 0; slot < nsub; slot++) {
        tables[slot] = (uint8_t *) malloc((size_t) (counts[slot] * itemsizes[slot]) + 1);
        CHECK(tables[slot] != NULL);
        rows[slot] = (counts[slot] > 0 && itemsizes[slot] > 0) ? tables[slot] : NULL;
    }
    ULogSamples(data, walk->offsets, walk->types, walk->sizes, count, &wanted, NULL, rows);
    for (slot = 0; slot < nsub; slot++) { /* the plain loop */
        const uint8_t *row = tables[slot];
        uint64_t found = 0;
        for (k = 0; k < count; k++) {
            if (walk->types[k] == 'D' && walk->sizes[k] >= 2 && slotOf[MsgId(data, walk, k, 0)] == slot + 1 &&
                walk->offsets[k] > starts[slot] && walk->sizes[k] - 2u == itemsizes[slot]) {
                CHECK(itemsizes[slot] == 0 ||
                      memcmp(row, data + walk->offsets[k] + 5, (size_t) itemsizes[slot]) == 0);
                row += itemsizes[slot];
                found++;
            }
        }
        CHECK(found == counts[slot]);
        CHECK(counts[slot] == 0 || itemsizes[slot] == 0 ||
              rows[slot] == tables[slot] + counts[slot] * itemsizes[slot]);
        free(tables[slot]);
    }
    free(slotOf);
}

/* ---- the per-message checks (ULogCheckMessages, ULogCheckAndCount, ULogCopySamples) against plain loops ---- */

/*
 * pyulog's reading of an I/M/P/Q message's key, byte at a time (payload of
 * size bytes, skip leading bytes not read): the key length byte (cut to what
 * is there), undecided at any key byte >= 0x80, fails without a space, a
 * "char[" type parses, a basic type's value must be exactly its size.
 */
static uint8_t ReferenceCheckInfo(const uint8_t *payload, size_t size, size_t skip) {
    static const char *const names[12] = {"int8_t", "uint8_t", "int16_t", "uint16_t", "int32_t", "uint32_t",
                                           "int64_t", "uint64_t", "float", "double", "bool", "char"};
    static const size_t bytes[12] = {1, 1, 2, 2, 4, 4, 8, 8, 4, 8, 1, 1};
    size_t keyLength, space, k, j;
    if (size < skip + 1) {
        return ULogInfoFails;
    }
    keyLength = payload[skip];
    if (keyLength > size - skip - 1) {
        keyLength = size - skip - 1;
    }
    for (k = 0; k < keyLength; k++) {
        if (payload[skip + 1 + k] >= 0x80) {
            return ULogInfoUndecided;
        }
    }
    for (space = 0; space < keyLength && payload[skip + 1 + space] != ' '; space++) {
    }
    if (space == keyLength) {
        return ULogInfoFails;
    }
    if (space >= 5 && memcmp(payload + skip + 1, "char[", 5) == 0) {
        return ULogInfoParses;
    }
    for (k = 0; k < 12; k++) {
        int same = strlen(names[k]) == space;
        for (j = 0; same && j < space; j++) {
            same = payload[skip + 1 + j] == (uint8_t) names[k][j];
        }
        if (same) {
            return (size - skip - 1 == payload[skip] + bytes[k]) ? ULogInfoParses : ULogInfoFails;
        }
    }
    return ULogInfoParses;
}

/* 2 if pyulog leaves the message to the caller (undecided), 1 if it raises on it, else 0. */
static int ReferenceCheckMessage(const uint8_t *data, const ULogMessages *walk, size_t k) {
    const uint8_t type = walk->types[k];
    const size_t size = walk->sizes[k];
    uint8_t verdict;
    if (type == 'I' || type == 'P' || type == 'M' || type == 'Q') {
        verdict = ReferenceCheckInfo(data + walk->offsets[k] + 3, size, (type == 'M' || type == 'Q') ? 1 : 0);
        return (verdict == ULogInfoUndecided) ? 2 : (verdict == ULogInfoFails);
    }
    return (type == 'L' && size < 9) || (type == 'C' && size < 11) || (type == 'A' && size < 3) ||
           (type == 'D' && size < 2) || (type == 'O' && size != 2);
}

/* The failed table and undecided list of the count messages, as ULogCheckMessages gives them, against the plain loop. */
static void CheckVerdicts(const uint8_t *data, const ULogMessages *walk, size_t count, const uint8_t *failed,
                          const size_t *undecided, size_t found, size_t capacity) {
    uint8_t expected[256];
    size_t k, seen = 0;
    memset(expected, 0, sizeof expected);
    for (k = 0; k < count; k++) {
        const int verdict = ReferenceCheckMessage(data, walk, k);
        if (verdict == 1) {
            expected[walk->types[k]] = 1;
        } else if (verdict == 2) {
            CHECK(seen >= capacity || undecided[seen] == k);
            seen++;
        }
    }
    CHECK(found == seen && memcmp(failed, expected, sizeof expected) == 0);
}

/* Subscription (1-based) of message k's sample as a plain loop over the subscriptions finds it, or 0. */
static size_t ReferenceSampleSlot(const uint8_t *data, const ULogMessages *walk, size_t k, const size_t *msgIds,
                                  const uint64_t *starts, const uint64_t *itemsizes, size_t nsub) {
    size_t slot;
    if (walk->types[k] != 'D' || walk->sizes[k] < 2) {
        return 0;
    }
    for (slot = 0; slot < nsub; slot++) {
        if (msgIds[slot] == MsgId(data, walk, k, 0)) {
            return (walk->offsets[k] > starts[slot] && walk->sizes[k] - 2u == itemsizes[slot]) ? slot + 1 : 0;
        }
    }
    return 0;
}

/*
 * ULogCopySamples from ULogCheckAndCount's sample slots against the bytes a
 * plain loop gathers (a subscription's rows NULL when the fuzzer's byte says
 * so: none copied), each table exactly filled.
 */
static void CheckCopy(const uint8_t *data, const ULogMessages *walk, size_t count, const uint16_t *sampleSlots,
                      const uint64_t *counts, const uint64_t *itemsizes, size_t nsub) {
    uint8_t *tables[64], *rows[64];
    size_t slot, k;
    for (slot = 0; slot < nsub; slot++) {
        const size_t bytes = (size_t) (counts[slot] * itemsizes[slot]);
        tables[slot] = (uint8_t *) malloc(bytes + 1);
        CHECK(tables[slot] != NULL);
        rows[slot] = ((data[16] >> (slot % 8)) & 1) ? NULL : tables[slot];
        memset(tables[slot], 0xA5, bytes + 1);
    }
    ULogCopySamples(data, walk->offsets, sampleSlots, count, itemsizes, rows);
    for (slot = 0; slot < nsub; slot++) {
        const uint8_t *row = tables[slot];
        const size_t bytes = (size_t) (counts[slot] * itemsizes[slot]);
        CHECK(rows[slot] == NULL || rows[slot] == tables[slot] + bytes);
        for (k = 0; rows[slot] != NULL && k < count; k++) {
            if (sampleSlots[k] == slot + 1) {
                CHECK(memcmp(row, data + walk->offsets[k] + 5, (size_t) itemsizes[slot]) == 0);
                row += itemsizes[slot];
            }
        }
        for (k = (rows[slot] != NULL) ? bytes : 0; k <= bytes; k++) { /* nothing past the samples, nothing if NULL */
            CHECK(tables[slot][k] == 0xA5);
        }
        free(tables[slot]);
    }
}

/*
 * ULogCheckMessages and ULogCheckAndCount (a subscription per A message) on
 * the count messages against the plain loops (undecided list of capacity
 * entries), then ULogCopySamples.
 */
static void CheckMessageChecks(const uint8_t *data, const ULogMessages *walk, size_t count, size_t capacity) {
    uint16_t *slotOf = (uint16_t *) calloc(65536, sizeof(uint16_t));
    uint16_t *sampleSlots = (uint16_t *) malloc((count + 1) * sizeof(uint16_t));
    uint64_t starts[64], itemsizes[64], counts[64], counted[64];
    size_t msgIds[64], undecided[4];
    uint8_t failed[256];
    ULogSubscriptions wanted = {slotOf, starts, itemsizes};
    size_t nsub, k, found, expected;
    CHECK(slotOf != NULL && sampleSlots != NULL);
    memset(failed, 0, sizeof failed);
    found = ULogCheckMessages(data, walk->offsets, walk->types, walk->sizes, count, failed, undecided, capacity);
    CheckVerdicts(data, walk, count, failed, undecided, found, capacity);
    nsub = Subscribe(data, walk, count, slotOf, starts, itemsizes, msgIds);
    for (k = 0; k < nsub; k++) {
        counts[k] = 0;
        counted[k] = 0;
    }
    memset(failed, 0, sizeof failed);
    found = ULogCheckAndCount(data, walk->offsets, walk->types, walk->sizes, count, &wanted, counts, sampleSlots,
                              failed, undecided, capacity);
    CheckVerdicts(data, walk, count, failed, undecided, found, capacity);
    for (k = 0; k < count; k++) {
        expected = ReferenceSampleSlot(data, walk, k, msgIds, starts, itemsizes, nsub);
        CHECK(sampleSlots[k] == expected);
        if (expected != 0) {
            counted[expected - 1]++;
        }
    }
    CHECK(memcmp(counts, counted, nsub * sizeof(uint64_t)) == 0);
    CheckCopy(data, walk, count, sampleSlots, counts, itemsizes, nsub);
    free(slotOf);
    free(sampleSlots);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const size_t capacity = 4 * (size / 3 + 1);
    ULogMessages walk;
    uint64_t appended[3] = {0, 0, 0};
    size_t appendedCount, sectionStart, k;
    size_t plain = ULOG_FILE_HEADER;
    walk.offsets = (uint64_t *) malloc(capacity * sizeof(uint64_t));
    walk.types = (uint8_t *) malloc(capacity);
    walk.sizes = (uint16_t *) malloc(capacity * sizeof(uint16_t));
    walk.capacity = capacity;
    CHECK(walk.offsets != NULL && walk.types != NULL && walk.sizes != NULL);
    if (size > ULOG_FILE_HEADER) {
        while (size - plain >= 3 && size - plain - 3 >= ((size_t) data[plain] | ((size_t) data[plain + 1] << 8))) {
            plain += 3 + ((size_t) data[plain] | ((size_t) data[plain + 1] << 8));
        }
        CHECK(ULogPlainEnd(data, size, ULOG_FILE_HEADER) == plain);
        sectionStart = CheckDefinitions(data, size, &walk, appended, &appendedCount);
        if (sectionStart <= size) {
            for (k = 0; k < appendedCount; k++) {
                appended[k] &= 0x7FFFFFFFFFFFFFFFull; /* the caller declines offsets of 2**63 and more */
            }
            CheckDataWalk(data, size, sectionStart, appended, appendedCount, &walk);
            {
                ULogDataResult result;
                ULogWalkData(data, size, sectionStart, appended, appendedCount, &walk, &result);
                CheckChecks(data, size, &walk, result.count);
                CheckGather(data, &walk, result.segmentEnds[0]);
            }
            for (k = 0; k < 3; k++) { /* offsets the fuzzer steers: the header's time stamp bytes */
                appended[k] = (uint64_t) (data[8 + k] | (data[11 + k] << 8)) % (size + 16);
            }
            CheckDataWalk(data, size, sectionStart, appended, 1 + data[14] % 3, &walk);
        }
    }
    free(walk.offsets);
    free(walk.types);
    free(walk.sizes);
    return 0;
}
