/**
 * @file replay_common.h
 * @brief The replay loop shared by every replay_<name>.c but the observer's
 * (written by tools/make_replays.py): each record of a hashed vector header (written by
 * csrc/tests/vectors/vector_common.py, or generate_kalman.py) is applied to
 * the filter, the state after it is read as words, and the status and the
 * FNV-1a hash of the words are compared; at each checkpoint record the words
 * are also compared one by one, and after a mismatch there the replay
 * continues from the expected state. Runs on the host (gcc, clang) and bare
 * metal on an emulated Cortex-M4F (QEMU mps2-an386, semihosting for printf
 * and exit).
 *
 * Prints "replay: N records, M mismatches" and returns non-zero on any
 * mismatch. Uses no double: printf only formats integers.
 *
 * Before including it, a replay defines:
 *   ReplayFilter, ReplayVector (op, status, input[], hash) and
 *   ReplayCheckpoint (record, state[]) types;
 *   REPLAY_STATE_WORDS, REPLAY_VECTORS, REPLAY_VECTOR_COUNT,
 *   REPLAY_CHECKPOINTS, REPLAY_CHECKPOINT_COUNT;
 * and after it the three hooks declared below.
 */

#ifndef REPLAY_COMMON_H
#define REPLAY_COMMON_H

#include <inttypes.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#define REPLAY_MAX_REPORTED (10)

/* Build with -DREPLAY_CORRUPT_RECORD=n to flip one bit of record n's expected
 * hash: the tests use it to check that a mismatch is caught and fails the run. */
#ifndef REPLAY_CORRUPT_RECORD
#define REPLAY_CORRUPT_RECORD (0xFFFFFFFFu)
#endif

/* Initialises the filter before the first record. */
static void ReplayInitialise(ReplayFilter *const filter);

/* Applies one record's call to the filter and returns its status. */
static uint32_t ReplayApply(ReplayFilter *const filter, const ReplayVector *const vector);

/* Kept out of line: inlined into the loop, gcc -O2 threads ReplayApply's
 * switch on the op through it into its own tests of the op and copies the
 * whole state read once per op (the rocket replay no longer fitted an
 * ATmega1284P's 128 kB at -O2). */
#if defined(__GNUC__)
#define REPLAY_OUT_OF_LINE __attribute__((noinline))
#else
#define REPLAY_OUT_OF_LINE
#endif

/* The state words after a call; false if the filter is inconsistent in a way
 * the words cannot show (e.g. an asymmetric covariance, or a check function
 * that disagrees with the call). */
static REPLAY_OUT_OF_LINE bool ReplayStateWords(const ReplayFilter *const filter, const ReplayVector *const vector, uint32_t status,
                             uint32_t words[REPLAY_STATE_WORDS]);

/* Sets the filter to the given state words (after a mismatch at a checkpoint). */
static void ReplaySetStateWords(ReplayFilter *const filter, const uint32_t words[REPLAY_STATE_WORDS]);

static inline float ReplayFloat(const uint32_t bits) {
    float value;
    memcpy(&value, &bits, sizeof(value));
    return value;
}

static inline uint32_t ReplayBits(const float value) {
    uint32_t bits;
    memcpy(&bits, &value, sizeof(bits));
    return bits;
}

static uint32_t ReplayHash(const uint32_t words[REPLAY_STATE_WORDS]) {
    uint32_t hash = 2166136261u;
    for (int i = 0; i < REPLAY_STATE_WORDS; i++) {
        hash = (hash ^ words[i]) * 16777619u;
    }
    return hash;
}

int main(void) {
    static ReplayFilter filter;
    ReplayInitialise(&filter);
    uint32_t mismatches = 0;
    uint32_t checkpoint = 0;
    for (uint32_t index = 0; index < (uint32_t) REPLAY_VECTOR_COUNT; index++) {
        const ReplayVector *const vector = &REPLAY_VECTORS[index];
        const uint32_t status = ReplayApply(&filter, vector);
        uint32_t words[REPLAY_STATE_WORDS];
        const bool consistent = ReplayStateWords(&filter, vector, status, words);
        const uint32_t hash = ReplayHash(words);
        const uint32_t expected = vector->hash ^ ((index == (uint32_t) REPLAY_CORRUPT_RECORD) ? 1u : 0u);
        bool same = (status == vector->status) && consistent && (hash == expected);
        const bool atCheckpoint = (checkpoint < (uint32_t) REPLAY_CHECKPOINT_COUNT) && (REPLAY_CHECKPOINTS[checkpoint].record == index);
        const uint32_t *const state = atCheckpoint ? REPLAY_CHECKPOINTS[checkpoint].state : NULL;
        if (atCheckpoint) {
            checkpoint++;
            same = same && (memcmp(words, state, sizeof(words)) == 0);
        }
        if (same) {
            continue;
        }
        if (mismatches < REPLAY_MAX_REPORTED) {
            printf("record %" PRIu32 " op %u: status %" PRIu32 " expected %u, consistent %u, hash 0x%08" PRIx32
                   " expected 0x%08" PRIx32 "\n",
                   index, (unsigned) vector->op, status, (unsigned) vector->status, (unsigned) consistent, hash, expected);
            for (int word = 0; (state != NULL) && (word < REPLAY_STATE_WORDS); word++) {
                if (words[word] != state[word]) {
                    printf("  word %d 0x%08" PRIx32 " expected 0x%08" PRIx32 "\n", word, words[word], state[word]);
                }
            }
        }
        mismatches++;
        if (state != NULL) {
            ReplaySetStateWords(&filter, state); /* continue from the expected state */
        }
    }
    printf("replay: %" PRIu32 " records, %" PRIu32 " mismatches\n", (uint32_t) REPLAY_VECTOR_COUNT, mismatches);
    return (mismatches == 0u) ? 0 : 1;
}

#endif
