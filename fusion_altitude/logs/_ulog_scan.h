/*
 * _ulog_scan.h - the walks of a PX4 ULog (.ulg) that pyulog makes, in C:
 * which messages it reads, in which order, where it steps over damaged bytes
 * and resumes after a sync sequence, and where appended data starts.
 *
 * A message is a 3-byte header (uint16 payload size, uint8 type) and its
 * payload. pyulog reads a file in two parts:
 *   - the definitions (ULogWalkDefinitions): I, M, F, P, Q and B messages
 *     until the first A, L or C message; other types are skipped, or, if the
 *     header is damaged (type 0, size 0 or size > 10000), stepped over by
 *     one byte;
 *   - the data section (ULogWalkData), once per segment: up to each offset
 *     of appended data (the flag-bits message), then from that offset. A
 *     segment ends at a header or payload cut by the end of the file, or at a
 *     message that ends past the segment's end. A message of an unknown type
 *     makes pyulog look for the sync sequence: after a damaged header, from
 *     the next byte to the end of the file (if none is found, it never looks
 *     again); after a sound one, in its payload only.
 *
 * Not part of the microcontroller core: no float, bounds-checked on every
 * read, no allocation (the caller gives the output arrays), C99 and C++.
 */
#ifndef FUSION_ALTITUDE_ULOG_SCAN_H
#define FUSION_ALTITUDE_ULOG_SCAN_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "_scan_common.h"

/* Bytes of the ULog file header (magic, version, start time) before the first message. */
#define ULOG_FILE_HEADER 16

/* Bytes of the sync sequence (the payload of an S message): 2F 73 13 20 25 0C BB 12. */
#define ULOG_SYNC_SIZE 8

/* Most segments of a data section: one before each of the 3 appended offsets, one after. */
#define ULOG_MAX_SEGMENTS 4

/* Largest payload (bytes) pyulog takes for a sound header of an unknown type. */
#define ULOG_MAX_SOUND_PAYLOAD 10000

/* Where a walk's messages go: offset of each header, type, payload size (bytes); capacity entries each. */
typedef struct {
    uint64_t *offsets;
    uint8_t *types;
    uint16_t *sizes;
    size_t capacity;
} ULogMessages;

typedef struct {
    size_t count;        /* definition messages (I M F P Q B) read */
    size_t sectionStart; /* byte offset of the first A, L or C message (the data section) */
    int found;           /* 1 if a data section starts at sectionStart */
    int cut;             /* 1 if a header or payload is cut by the end of the file before it */
    int full;            /* 1 if the output arrays filled up */
} ULogDefinitionsResult;

typedef struct {
    size_t count;                           /* data-section messages read, all segments */
    size_t segmentEnds[ULOG_MAX_SEGMENTS];  /* count after each segment */
    size_t segments;                        /* segments read (1 + appended offsets) */
    size_t skipped;                         /* messages of unknown type stepped over */
    size_t synced;                          /* times reading resumed after a sync sequence */
    int full;                               /* 1 if the output arrays filled up */
} ULogDataResult;

/* Payload size (bytes) in the header at data[position] (3 bytes must be there). */
static inline size_t ULogPayloadSize(const uint8_t *const data, const size_t position) {
    return (size_t) data[position] | ((size_t) data[position + 1] << 8);
}

/* Whether pyulog reads a message of this type in the definitions (I M F P Q B). */
static inline int ULogIsDefinitionType(const uint8_t type) {
    return (type == 'I') || (type == 'M') || (type == 'F') || (type == 'P') || (type == 'Q') || (type == 'B');
}

/* Whether a message of this type starts the data section (A L C). */
static inline int ULogStartsDataSection(const uint8_t type) {
    return (type == 'A') || (type == 'L') || (type == 'C');
}

/* Whether pyulog reads a message of this type in the data section (I M P Q A L C D O S). */
static inline int ULogIsDataType(const uint8_t type) {
    /* one bit per letter from 'A' (this runs once per message): A C D I L M O P Q S */
    const uint32_t letters = (1u << ('A' - 'A')) | (1u << ('C' - 'A')) | (1u << ('D' - 'A')) | (1u << ('I' - 'A')) |
                             (1u << ('L' - 'A')) | (1u << ('M' - 'A')) | (1u << ('O' - 'A')) | (1u << ('P' - 'A')) |
                             (1u << ('Q' - 'A')) | (1u << ('S' - 'A'));
    const unsigned int letter = (unsigned int) type - 'A';
    return (letter < 32u) && (((letters >> letter) & 1u) != 0u);
}

/* Whether a header of an unknown type is damaged (pyulog's _check_packet_corruption). */
static inline int ULogHeaderDamaged(const uint8_t type, const size_t payload) {
    return (type == 0) || (payload == 0) || (payload > ULOG_MAX_SOUND_PAYLOAD);
}

/* Start of the first sync sequence wholly inside data[from .. to), or SIZE_MAX if there is none. */
static inline size_t ULogFindSync(const uint8_t *const data, const size_t from, const size_t to) {
    size_t position;
    if ((to < ULOG_SYNC_SIZE) || (from > to - ULOG_SYNC_SIZE)) {
        return SIZE_MAX;
    }
    for (position = from; position <= to - ULOG_SYNC_SIZE; position++) {
        const uint8_t *const p = data + position;
        if ((p[0] == 0x2F) && (p[1] == 0x73) && (p[2] == 0x13) && (p[3] == 0x20) && (p[4] == 0x25) &&
            (p[5] == 0x0C) && (p[6] == 0xBB) && (p[7] == 0x12)) {
            return position;
        }
    }
    return SIZE_MAX;
}

/* Append one message to out; 0 if out is full. */
static inline int ULogRecord(const ULogMessages *const out, size_t *const count, const size_t position,
                             const uint8_t type, const size_t payload) {
    if (*count >= out->capacity) {
        return 0;
    }
    out->offsets[*count] = (uint64_t) position;
    out->types[*count] = type;
    out->sizes[*count] = (uint16_t) payload;
    (*count)++;
    return 1;
}

/*
 * Byte after the last whole message of the plain walk from start (every
 * header taken as sound): where a file cut inside a message is cut.
 */
static inline size_t ULogPlainEnd(const uint8_t *const data, const size_t size, const size_t start) {
    size_t position = start;
    while ((position <= size) && (size - position >= 3) && (size - position - 3 >= ULogPayloadSize(data, position))) {
        position += 3 + ULogPayloadSize(data, position);
    }
    return position;
}

/* pyulog's definitions walk from start (ULOG_FILE_HEADER): the I M F P Q B messages to out. */
static inline void ULogWalkDefinitions(const uint8_t *const data, const size_t size, const size_t start,
                                       const ULogMessages *const out, ULogDefinitionsResult *const result) {
    size_t position = start;
    result->count = 0;
    result->found = 0;
    result->cut = 0;
    result->full = 0;
    while (position < size) {
        size_t payload;
        uint8_t type;
        if (size - position < 3) {
            result->cut = 1;
            break;
        }
        payload = ULogPayloadSize(data, position);
        type = data[position + 2];
        if (size - position - 3 < payload) {
            result->cut = 1;
            break;
        }
        if (ULogStartsDataSection(type)) {
            result->found = 1;
            break;
        }
        if (ULogIsDefinitionType(type)) {
            if (!ULogRecord(out, &result->count, position, type, payload)) {
                result->full = 1;
                break;
            }
            position += 3 + payload;
        } else if (ULogHeaderDamaged(type, payload)) {
            position += 1;
        } else {
            position += 3 + payload;
        }
    }
    result->sectionStart = position;
}

/*
 * One segment of pyulog's data walk (_read_file_data): from position until a
 * message ends past until (bytes). counted is pyulog's own count of the bytes
 * read (its curr_file_pos), which a sync search does not update; hasSync is 0
 * once a search to the end of the file failed. Returns 0 if out filled up.
 */
static inline int ULogWalkSegment(const uint8_t *const data, const size_t size, size_t position, const uint64_t until,
                                  int *const hasSync, const ULogMessages *const out, ULogDataResult *const result) {
    uint64_t *const offsets = out->offsets; /* locals: the stores below cannot alias them */
    uint8_t *const types = out->types;
    uint16_t *const sizes = out->sizes;
    const size_t capacity = out->capacity;
    size_t count = result->count;
    uint64_t counted = (uint64_t) position;
    while ((position < size) && (size - position >= 3)) {
        const size_t start = position;
        const size_t payload = ULogPayloadSize(data, position);
        const uint8_t type = data[position + 2];
        size_t sync;
        if (size - position - 3 < payload) {
            break; /* cut: pyulog stops */
        }
        counted += 3 + payload;
        if (counted > until) {
            break;
        }
        position += 3 + payload;
        if (ULogIsDataType(type)) {
            if (count >= capacity) {
                result->count = count;
                return 0;
            }
            offsets[count] = (uint64_t) start;
            types[count] = type;
            sizes[count] = (uint16_t) payload;
            count++;
            continue;
        }
        result->skipped++;
        if (ULogHeaderDamaged(type, payload)) { /* step one byte, then look for sync to the end */
            position = start + 1;
            counted = (uint64_t) position;
            if (*hasSync) {
                sync = ULogFindSync(data, position, size);
                if (sync == SIZE_MAX) {
                    *hasSync = 0;
                } else {
                    position = sync + ULOG_SYNC_SIZE;
                    result->synced++;
                }
            }
        } else if (*hasSync) { /* look for sync in the payload only */
            sync = ULogFindSync(data, start + 3, start + 3 + payload);
            if (sync != SIZE_MAX) {
                position = sync + ULOG_SYNC_SIZE;
                result->synced++;
            }
        }
    }
    result->count = count;
    return 1;
}

/*
 * pyulog's data walk from sectionStart: one segment up to each of the
 * appendedCount (at most 3) appended offsets, each next one from that offset,
 * the last to the end of the file. The messages of the known data types go to
 * out, in the order pyulog reads them; segmentEnds tells where each segment's
 * end in that list.
 */
static inline void ULogWalkData(const uint8_t *const data, const size_t size, const size_t sectionStart,
                                const uint64_t *const appended, const size_t appendedCount,
                                const ULogMessages *const out, ULogDataResult *const result) {
    size_t segment;
    int hasSync = 1;
    result->count = 0;
    result->skipped = 0;
    result->synced = 0;
    result->full = 0;
    result->segments = 0;
    for (segment = 0; (segment <= appendedCount) && (segment < ULOG_MAX_SEGMENTS); segment++) {
        const uint64_t from = (segment == 0) ? (uint64_t) sectionStart : appended[segment - 1];
        const uint64_t until = (segment < appendedCount) ? appended[segment] : UINT64_MAX;
        const size_t position = (from < (uint64_t) size) ? (size_t) from : size;
        if (!ULogWalkSegment(data, size, position, until, &hasSync, out, result)) {
            result->full = 1;
        }
        result->segmentEnds[segment] = result->count;
        result->segments = segment + 1;
        if (result->full) {
            break;
        }
    }
}

/* ---- the checks and the gather of the fast decoder (fusion_altitude/logs/_ulog_fast.py) ---- */

/* Verdicts of ULogCheckInfo. */
typedef enum {
    ULogInfoFails = 0,     /* pyulog surely raises on this message */
    ULogInfoParses = 1,    /* pyulog surely parses it */
    ULogInfoUndecided = 2, /* a non-ASCII key (pyulog drops undecodable bytes first): for the caller */
} ULogInfoVerdict;

/* Index of the first wanted byte of text[0 .. length), or length if there is none. */
static inline size_t ULogFind(const uint8_t *const text, const size_t length, const uint8_t wanted) {
    size_t k;
    for (k = 0; k < length; k++) {
        if (text[k] == wanted) {
            return k;
        }
    }
    return length;
}

/* Bytes of pyulog's basic type named text[0 .. length), or 0 if it is none. */
static inline size_t ULogBasicTypeSize(const uint8_t *const text, const size_t length) {
    static const char *const names[12] = {"int8_t", "uint8_t", "int16_t", "uint16_t", "int32_t", "uint32_t",
                                           "int64_t", "uint64_t", "float", "double", "bool", "char"};
    static const size_t sizes[12] = {1, 1, 2, 2, 4, 4, 8, 8, 4, 8, 1, 1};
    static const size_t lengths[12] = {6, 7, 7, 8, 7, 8, 7, 8, 5, 6, 4, 4}; /* strlen of each name */
    size_t k;
    for (k = 0; k < 12; k++) { /* a name of another length or first letter is passed over at once */
        if ((lengths[k] == length) && ((uint8_t) names[k][0] == text[0]) && (memcmp(text, names[k], length) == 0)) {
            return sizes[k];
        }
    }
    return 0;
}

/*
 * Whether pyulog parses an I/M/P/Q message (payload of size bytes; skip: 1
 * for M and Q, whose first byte pyulog skips) without an exception: a key
 * length, a key of at least two words (type, name) and, for a basic type, a
 * value of exactly that type's size.
 */
static inline ULogInfoVerdict ULogCheckInfo(const uint8_t *const message, const size_t size, const size_t skip) {
    const uint8_t *const payload = message + skip;
    size_t available, keyLength, space, j;
    size_t typeSize;
    uint8_t high;
    if (size < 1 + skip) {
        return ULogInfoFails;
    }
    available = size - skip; /* bytes of the payload pyulog reads */
    keyLength = (payload[0] > available - 1) ? available - 1 : payload[0];
    high = 0;
    for (j = 0; j < keyLength; j++) { /* any byte >= 0x80 (no early exit: the loop stays simple) */
        high |= payload[1 + j];
    }
    if ((high & 0x80) != 0) {
        return ULogInfoUndecided;
    }
    space = ULogFind(payload + 1, keyLength, ' ');
    if (space == keyLength) { /* one word: pyulog's split(" ") gives no name */
        return ULogInfoFails;
    }
    if ((space >= 5) && (payload[1] == 'c') && (payload[2] == 'h') && (payload[3] == 'a') && (payload[4] == 'r') &&
        (payload[5] == '[')) {
        return ULogInfoParses; /* a string */
    }
    typeSize = ULogBasicTypeSize(payload + 1, space);
    if ((typeSize != 0) && (available - 1 != (size_t) payload[0] + typeSize)) {
        return ULogInfoFails;
    }
    return ULogInfoParses;
}

/* Index of the first of the count messages at offsets (payload sizes bytes) not wholly inside the data, or count. */
static inline size_t ULogFirstOutside(const size_t size, const uint64_t *const offsets, const uint16_t *const sizes,
                                      const size_t count) {
    size_t k;
    for (k = 0; k < count; k++) {
        if ((offsets[k] > (uint64_t) size) || ((uint64_t) size - offsets[k] < 3 + (uint64_t) sizes[k])) {
            return k;
        }
    }
    return count;
}

/*
 * ULogCheckInfo of the count messages at offsets (payload sizes bytes) to
 * verdicts[]; returns 0 (verdicts unset) if one runs past the end of the data.
 */
static inline int ULogCheckInfos(const uint8_t *const data, const size_t size, const uint64_t *const offsets,
                                 const uint16_t *const sizes, const size_t count, const size_t skip,
                                 uint8_t *const verdicts) {
    size_t k;
    if (ULogFirstOutside(size, offsets, sizes, count) != count) {
        return 0;
    }
    for (k = 0; k < count; k++) {
        verdicts[k] = (uint8_t) ULogCheckInfo(data + offsets[k] + 3, sizes[k], skip);
    }
    return 1;
}

/*
 * Whether one "type name" item of a format parses in pyulog without an
 * exception, surely: a space after the type, and an array size (if any) of 1
 * to 4 digits closed by ']'.
 */
static inline int ULogFieldSimple(const uint8_t *const item, const size_t length) {
    const size_t space = ULogFind(item, length, ' ');
    size_t at, close, k;
    if (space == length) {
        return 0;
    }
    at = ULogFind(item, space, '[');
    if (at == space) {
        return 1;
    }
    close = ULogFind(item, space, ']');
    if ((close == space) || (close <= at + 1) || (close > at + 5)) { /* no ']': pyulog's slice would end at -1 */
        return 0;
    }
    for (k = at + 1; k < close; k++) {
        if ((item[k] < '0') || (item[k] > '9')) {
            return 0;
        }
    }
    return 1;
}

/*
 * Length of the name of an F (format) message whose parsing by pyulog surely
 * succeeds (ASCII, a ':' after the name, every non-empty ';'-separated item
 * of the field list simple), else SIZE_MAX (for the caller to parse).
 */
static inline size_t ULogFormatNameLength(const uint8_t *const payload, const size_t size) {
    size_t colon = size;
    size_t end, item, j;
    for (j = 0; j < size; j++) {
        if (payload[j] >= 0x80) {
            return SIZE_MAX;
        }
        if ((payload[j] == ':') && (colon == size)) {
            colon = j;
        }
    }
    if (colon == size) {
        return SIZE_MAX;
    }
    end = colon + 1 + ULogFind(payload + colon + 1, size - colon - 1, ':');
    item = colon + 1;
    for (j = colon + 1; j <= end; j++) {
        if ((j == end) || (payload[j] == ';')) {
            if ((j > item) && !ULogFieldSimple(payload + item, j - item)) {
                return SIZE_MAX;
            }
            item = j + 1;
        }
    }
    return colon;
}

/*
 * ULogFormatNameLength of the count F messages at offsets (payload sizes
 * bytes) to lengths[]; returns 0 (lengths unset) if one runs past the end.
 */
static inline int ULogFormatNameLengths(const uint8_t *const data, const size_t size, const uint64_t *const offsets,
                                        const uint16_t *const sizes, const size_t count, size_t *const lengths) {
    size_t k;
    if (ULogFirstOutside(size, offsets, sizes, count) != count) {
        return 0;
    }
    for (k = 0; k < count; k++) {
        lengths[k] = ULogFormatNameLength(data + offsets[k] + 3, sizes[k]);
    }
    return 1;
}

/*
 * Smallest payload (bytes) pyulog parses of a message of this type in the
 * data section (L C A D O; an O message must be of exactly 2), 0 for others.
 */
static inline size_t ULogMinimumPayload(const uint8_t type) {
    switch (type) {
    case 'L':
        return 9;
    case 'C':
        return 11;
    case 'A':
        return 3;
    case 'D':
    case 'O':
        return 2;
    default:
        return 0;
    }
}

/*
 * Whether pyulog raises on the message at offset (type, payload size bytes;
 * wholly inside the data): an L, C, A or D message shorter than 9, 11, 3 or 2
 * bytes, an O (dropout) message not of 2 bytes, an I/M/P/Q message
 * ULogCheckInfo fails (from byte 1 for M and Q) set failed[type] to 1 (256
 * entries). Returns 1 for an I/M/P/Q message of a non-ASCII key (undecided:
 * for the caller), else 0.
 */
static inline int ULogCheckMessage(const uint8_t *const data, const uint64_t offset, const uint8_t type,
                                   const uint16_t size, uint8_t *const failed) {
    if ((type == 'I') || (type == 'P') || (type == 'M') || (type == 'Q')) {
        const ULogInfoVerdict verdict =
            ULogCheckInfo(data + offset + 3, size, ((type == 'M') || (type == 'Q')) ? 1u : 0u);
        if (verdict == ULogInfoFails) {
            failed[type] = 1;
        }
        return verdict == ULogInfoUndecided;
    }
    if ((size < ULogMinimumPayload(type)) || ((type == 'O') && (size != 2))) {
        failed[type] = 1;
    }
    return 0;
}

/*
 * ULogCheckMessage of the count messages at offsets (each wholly inside the
 * data), in one pass; failed: the caller's zeros. The index of each undecided
 * message goes to undecided (the first capacity of them); returns how many
 * there are.
 */
static inline size_t ULogCheckMessages(const uint8_t *const data, const uint64_t *const offsets,
                                       const uint8_t *const types, const uint16_t *const sizes, const size_t count,
                                       uint8_t *const failed, size_t *const undecided, const size_t capacity) {
    size_t k, found = 0;
    for (k = 0; k < count; k++) {
        if (ULogCheckMessage(data, offsets[k], types[k], sizes[k], failed)) {
            if (found < capacity) {
                undecided[found] = k;
            }
            found++;
        }
    }
    return found;
}

/* The subscriptions whose samples ULogSamples counts and gathers. */
typedef struct {
    const uint16_t *slotOf;    /* 65536 entries: 1 + subscription of each msg_id, 0 if none */
    const uint64_t *starts;    /* byte offset of each subscription's A message (later samples count) */
    const uint64_t *itemsizes; /* bytes of one sample of each (a D message of another size is none of its) */
} ULogSubscriptions;

/*
 * Subscription (0-based) of the D message at offset (payload size bytes), or
 * SIZE_MAX if it is not one of a subscription's samples. The table pointers
 * come as arguments (locals of the caller, which a copy into the samples
 * cannot alias).
 */
static inline size_t ULogSampleSlot(const uint8_t *const data, const uint64_t offset, const uint8_t type,
                                    const uint16_t size, const uint16_t *const slotOf, const uint64_t *const starts,
                                    const uint64_t *const itemsizes) {
    size_t msgId, slot;
    if ((type != 'D') || (size < 2)) {
        return SIZE_MAX;
    }
    msgId = (size_t) data[offset + 3] | ((size_t) data[offset + 4] << 8);
    if (slotOf[msgId] == 0) {
        return SIZE_MAX;
    }
    slot = (size_t) slotOf[msgId] - 1;
    if ((offset <= starts[slot]) || ((uint64_t) size - 2 != itemsizes[slot])) {
        return SIZE_MAX;
    }
    return slot;
}

/*
 * The samples of each subscription among the count messages (each wholly
 * inside the data): with rows NULL, counted (counts[slot] += 1 each);
 * otherwise the payload after the 2-byte msg_id of each copied in file order
 * to rows[slot], advancing it (room for the count; rows[slot] NULL for a
 * subscription of no sample or of 0-byte samples).
 */
static inline void ULogSamples(const uint8_t *const data, const uint64_t *const offsets, const uint8_t *const types,
                               const uint16_t *const sizes, const size_t count,
                               const ULogSubscriptions *const subscriptions, uint64_t *const counts,
                               uint8_t **const rows) {
    const uint16_t *const slotOf = subscriptions->slotOf;
    const uint64_t *const starts = subscriptions->starts;
    const uint64_t *const itemsizes = subscriptions->itemsizes;
    size_t k, slot;
    if (rows == NULL) { /* two loops: the test of rows stays out of them */
        for (k = 0; k < count; k++) {
            slot = ULogSampleSlot(data, offsets[k], types[k], sizes[k], slotOf, starts, itemsizes);
            if (slot != SIZE_MAX) {
                counts[slot]++;
            }
        }
        return;
    }
    for (k = 0; k < count; k++) {
        slot = ULogSampleSlot(data, offsets[k], types[k], sizes[k], slotOf, starts, itemsizes);
        if ((slot != SIZE_MAX) && (rows[slot] != NULL)) {
            memcpy(rows[slot], data + offsets[k] + 5, (size_t) itemsizes[slot]);
            rows[slot] += itemsizes[slot];
        }
    }
}

/*
 * ULogCheckMessages and the counting pass of ULogSamples in one pass over the
 * count messages (each wholly inside the data): failed and undecided as
 * ULogCheckMessages (returns how many undecided there are), counts[slot] += 1
 * for each sample of a subscription, and sampleSlots[k] = 1 + the
 * subscription of message k's sample, or 0, for ULogCopySamples.
 */
static inline size_t ULogCheckAndCount(const uint8_t *const data, const uint64_t *const offsets,
                                       const uint8_t *const types, const uint16_t *const sizes, const size_t count,
                                       const ULogSubscriptions *const subscriptions, uint64_t *const counts,
                                       uint16_t *const sampleSlots, uint8_t *const failed, size_t *const undecided,
                                       const size_t capacity) {
    const uint16_t *const slotOf = subscriptions->slotOf;
    const uint64_t *const starts = subscriptions->starts;
    const uint64_t *const itemsizes = subscriptions->itemsizes;
    size_t k, slot, found = 0;
    for (k = 0; k < count; k++) {
        sampleSlots[k] = 0;
        if (types[k] == 'D') {
            slot = ULogSampleSlot(data, offsets[k], types[k], sizes[k], slotOf, starts, itemsizes);
            if (slot != SIZE_MAX) {
                counts[slot]++;
                sampleSlots[k] = (uint16_t) (slot + 1);
            }
        }
        if (ULogCheckMessage(data, offsets[k], types[k], sizes[k], failed)) {
            if (found < capacity) {
                undecided[found] = k;
            }
            found++;
        }
    }
    return found;
}

/*
 * The payload after the 2-byte msg_id of each message whose sampleSlots entry
 * (from ULogCheckAndCount) is not 0 copied in file order to rows[slot],
 * advancing it (room for the count; rows[slot] NULL: none copied).
 */
static inline void ULogCopySamples(const uint8_t *const data, const uint64_t *const offsets,
                                   const uint16_t *const sampleSlots, const size_t count,
                                   const uint64_t *const itemsizes, uint8_t **const rows) {
    size_t k;
    for (k = 0; k < count; k++) {
        if (sampleSlots[k] != 0) {
            const size_t slot = (size_t) sampleSlots[k] - 1;
            if (rows[slot] != NULL) {
                memcpy(rows[slot], data + offsets[k] + 5, (size_t) itemsizes[slot]);
                rows[slot] += itemsizes[slot];
            }
        }
    }
}

#endif
