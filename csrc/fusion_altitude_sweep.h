/**
 * @file fusion_altitude_sweep.h
 * @brief K complementary observers, each with its own gains, over one input
 * stream: for gain sweeps and tuning on a host. Column k equals, bit for bit,
 * FusionAltitudeUpdate run alone with the gains of setting k, except where a
 * baro step is a gap by the stability rule for some settings but not for k:
 * the settings share one timeline (the reference, gaps, restarts and the baro
 * timeout come from the shared inputs), so such a step is a gap for every
 * setting (it is unstable for at least one: FusionAltitudeIsStepStable). On a
 * log with no step near any setting's stability limit, or for K = 1, every
 * column equals its own observer.
 *
 * States and gains are arrays over the K settings (structure of arrays) and the
 * inner loop runs over k, so that a compiler vectorizes it; the optional
 * outputs are time-major, [sample][stride]. Per-setting error metrics against
 * a reference series can be accumulated without writing any output.
 *
 * Units: altitude m, vertical velocity m/s, acceleration m/s^2 (+up, gravity
 * removed), time s, gains 1/s, 1/s^2, 1/s^3. Float32, no malloc, no libm.
 */

#ifndef FUSION_ALTITUDE_SWEEP_H
#define FUSION_ALTITUDE_SWEEP_H

#include <stddef.h>
#include <stdint.h>

#include "fusion_altitude.h"

#ifdef __cplusplus
extern "C" {
#endif

/* gcc contracts a*b + c into a fused multiply-add by default in its GNU modes
 * (-std=gnu99/gnu11/gnu17, what vendor IDEs use) and for C++: the functions of
 * this header are compiled with contraction off, so they give the same bits
 * whatever the caller's flags. ISO C modes (-std=c99, -std=c11) already have
 * it off and are left alone, so that the functions still inline there; in
 * GNU modes they inline into callers built with -ffp-contract=off. */
#if defined(__GNUC__) && !defined(__clang__) && (defined(__cplusplus) || !defined(__STRICT_ANSI__))
#define FUSION_ALTITUDE_SWEEP_GCC_NO_CONTRACT
#pragma GCC push_options
#pragma GCC optimize("fp-contract=off")
#endif

#if defined(__cplusplus)
#define FUSION_ALTITUDE_RESTRICT __restrict
#else
#define FUSION_ALTITUDE_RESTRICT restrict
#endif

#if defined(__clang__)
#define FUSION_ALTITUDE_SWEEP_NO_CONTRACT _Pragma("clang fp contract(off)")
#else
#define FUSION_ALTITUDE_SWEEP_NO_CONTRACT
#endif

/** Output floats written per time tile when outputs are requested (about 256 KiB). */
#define FUSION_ALTITUDE_SWEEP_TILE_FLOATS (65536u)

/*
 * Define FUSION_ALTITUDE_SWEEP_MULTIVERSION (the Python build does, on x86-64
 * with gcc or clang) to compile the sweep for AVX2 as well as the baseline and
 * pick one at load time. AVX2 brings no FMA, so the results are the same bits.
 */
#if defined(FUSION_ALTITUDE_SWEEP_MULTIVERSION) && defined(__x86_64__) && defined(__GNUC__) && !defined(__cplusplus)
#define FUSION_ALTITUDE_SWEEP_CLONES __attribute__((target_clones("avx2", "default")))
#define FUSION_ALTITUDE_SWEEP_INLINE static inline __attribute__((always_inline))
#else
#define FUSION_ALTITUDE_SWEEP_CLONES
#define FUSION_ALTITUDE_SWEEP_INLINE static inline
#endif

/** Samples summed in float32 before a block sum is added to the running total (bounds rounding growth). */
#define FUSION_ALTITUDE_SWEEP_BLOCK (1024u)

/**
 * @brief K observers. All arrays hold count elements and are owned by the
 * caller; none may overlap another.
 */
typedef struct {
    size_t count;             /**< K, number of settings */
    const float *positionGain; /**< Kh[k], 1/s */
    const float *velocityGain; /**< Kv[k], 1/s^2 */
    const float *biasGain;     /**< Kb[k], 1/s^3 */
    float *altitude;          /**< h[k], m */
    float *verticalVelocity;  /**< v[k], m/s */
    float *accelBias;         /**< b[k], m/s^2 */
    float *baroResidual;      /**< r[k], m (NaN after a step without baro) */
    float gapPeriod;          /**< shared, s: a dt above this is a gap (FusionAltitudeUpdate); set it after FusionAltitudeSweepInitialise */
    float baroTimeout;        /**< shared, s: no baro sample for longer than this times out (FusionAltitudeUpdate); set it after FusionAltitudeSweepInitialise */
    float gapTime;            /**< shared, s: time since h was updated while a restart after a gap is pending; 0 otherwise */
    float sinceRestart;       /**< shared, s since the last restart after a gap or timeout; -1 before any (column k holds its bias while sinceRestart*Kh[k] < 8) */
    float sinceBaro;          /**< shared, s since the latest baro sample */
    uint32_t gapCount;        /**< shared: gaps so far (dt > gapPeriod, or a baro step unstable for at least one setting) */
    uint32_t baroTimeouts;    /**< shared: baro timeouts so far */
    bool referenceSet;        /**< shared: every setting auto-zeroes on the same first baro sample, and restarts on the same one after a gap */
    bool baroTimedOut;        /**< shared: true from a baro timeout to the next baro sample (output not baro-aided) */
    size_t ruleBefore;        /**< settings [-ruleBefore, 0) of the same gain arrays that the stability rule checks too (0 after Initialise) */
    size_t ruleAfter;         /**< settings [count, count + ruleAfter) likewise: a sweep split into parts (threads) applies one rule */
} FusionAltitudeSweep;

/**
 * @brief Optional per-sample outputs, each NULL or an array of
 * samples * stride floats; setting k of sample t goes to [t * stride + k].
 */
typedef struct {
    float *altitude;
    float *verticalVelocity;
    float *accelBias;
    float *baroResidual;
    size_t stride; /**< >= count */
} FusionAltitudeSweepOutputs;

/**
 * @brief Optional error metrics of altitude against a reference series:
 * e = h[k] - reference[t] after sample t, over the samples where mask[t] != 0
 * (all when mask is NULL) and reference[t] is finite. Sums are kept in float32
 * per block of FUSION_ALTITUDE_SWEEP_BLOCK metric samples, then added to the
 * totals. Accumulates into whatever the arrays hold (zero them to start).
 */
typedef struct {
    const float *reference;   /**< [samples], m */
    const uint8_t *mask;      /**< [samples] or NULL */
    float *sumError;          /**< [count], m */
    float *sumSquaredError;   /**< [count], m^2 */
    float *maxAbsError;       /**< [count], m */
    float *blockSumError;     /**< [count] scratch, zeroed by the caller */
    float *blockSumSquaredError; /**< [count] scratch, zeroed by the caller */
    size_t samplesInBlock;    /**< in/out, 0 to start */
    size_t metricSamples;     /**< in/out: samples counted so far */
} FusionAltitudeSweepMetrics;

/* What every setting shares, since the inputs are shared: the reference, the
 * pending restart after a gap, the gap count and the baro timeout (the fields
 * of FusionAltitude). */
typedef struct {
    float gapTime;
    float sinceRestart;
    float sinceBaro;
    uint32_t gapCount;
    uint32_t baroTimeouts;
    bool referenceSet;
    bool baroTimedOut;
} FusionAltitudeSweepShared;

/* The shared state of the sweep (the fields of FusionAltitude that every setting shares). */
FUSION_ALTITUDE_SWEEP_INLINE FusionAltitudeSweepShared FusionAltitudeSweepGetShared(const FusionAltitudeSweep *const sweep) {
    const FusionAltitudeSweepShared shared = {sweep->gapTime, sweep->sinceRestart, sweep->sinceBaro, sweep->gapCount,
                                              sweep->baroTimeouts, sweep->referenceSet, sweep->baroTimedOut};
    return shared;
}

/* Stores the shared state back into the sweep. */
FUSION_ALTITUDE_SWEEP_INLINE void FusionAltitudeSweepSetShared(FusionAltitudeSweep *const sweep, const FusionAltitudeSweepShared *const shared) {
    sweep->gapTime = shared->gapTime;
    sweep->sinceRestart = shared->sinceRestart;
    sweep->sinceBaro = shared->sinceBaro;
    sweep->gapCount = shared->gapCount;
    sweep->baroTimeouts = shared->baroTimeouts;
    sweep->referenceSet = shared->referenceSet;
    sweep->baroTimedOut = shared->baroTimedOut;
}

/**
 * @brief Initialises a sweep: every state zero, reference not set, no gap,
 * no timeout, gap period FUSION_ALTITUDE_DEFAULT_GAP_PERIOD and baro timeout
 * FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT (assign sweep->gapPeriod and
 * sweep->baroTimeout afterwards to change them; both must be > 0). The gains
 * are the caller's arrays; check each setting with FusionAltitudeSettingsCheck.
 */
static inline void FusionAltitudeSweepInitialise(FusionAltitudeSweep *const sweep) {
    for (size_t k = 0; k < sweep->count; k++) {
        sweep->altitude[k] = 0.0f;
        sweep->verticalVelocity[k] = 0.0f;
        sweep->accelBias[k] = 0.0f;
        sweep->baroResidual[k] = 0.0f;
    }
    sweep->gapPeriod = FUSION_ALTITUDE_DEFAULT_GAP_PERIOD;
    sweep->baroTimeout = FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT;
    const FusionAltitudeSweepShared start = {0.0f, -1.0f, 0.0f, 0u, 0u, false, false}; /* no gap, no pending restart, no reference */
    FusionAltitudeSweepSetShared(sweep, &start);
    sweep->ruleBefore = 0u;
    sweep->ruleAfter = 0u;
}

/** Adds the open block sums into the totals and clears them. Call once after the last update. */
static inline void FusionAltitudeSweepFlushMetrics(const FusionAltitudeSweep *const sweep, FusionAltitudeSweepMetrics *const metrics) {
    for (size_t k = 0; k < sweep->count; k++) {
        metrics->sumError[k] += metrics->blockSumError[k];
        metrics->sumSquaredError[k] += metrics->blockSumSquaredError[k];
        metrics->blockSumError[k] = 0.0f;
        metrics->blockSumSquaredError[k] = 0.0f;
    }
    metrics->samplesInBlock = 0;
}

/**
 * Settings processed together: their states live in local arrays of this many
 * lanes for the whole run, which a compiler keeps in vector registers and L1.
 */
#define FUSION_ALTITUDE_SWEEP_LANES (32)

/*
 * 1 (the default with gcc and clang compiling C): sweeps of up to 8 settings
 * keep their states in 8-float vector registers (FusionAltitudeSweepChunk8);
 * 0: the lane arrays, as wider chunks. Both give the same bits.
 */
#ifndef FUSION_ALTITUDE_SWEEP_VECTOR
#if (defined(__GNUC__) || defined(__clang__)) && !defined(__cplusplus)
#define FUSION_ALTITUDE_SWEEP_VECTOR 1
#else
#define FUSION_ALTITUDE_SWEEP_VECTOR 0
#endif
#endif

#if FUSION_ALTITUDE_SWEEP_VECTOR
typedef float FusionAltitudeSweepVector8 __attribute__((vector_size(32)));
typedef float FusionAltitudeSweepUnaligned8 __attribute__((vector_size(32), aligned(4))); /* 8 floats anywhere in memory */
typedef int32_t FusionAltitudeSweepMask8 __attribute__((vector_size(32)));
#endif

/* Copies width lanes into output row data[offset...] (nothing if data is NULL);
 * a full chunk copies a constant number of lanes, which compiles to vector stores. */
FUSION_ALTITUDE_SWEEP_INLINE void FusionAltitudeSweepCopyRow(float *const data, const size_t offset, const float *const values,
                                                             const size_t width, const size_t lanes) {
    if (data == NULL) {
        return;
    }
    float *const FUSION_ALTITUDE_RESTRICT row = &data[offset];
    if (width == lanes) {
        for (size_t j = 0; j < lanes; j++) {
            row[j] = values[j];
        }
    } else {
        for (size_t j = 0; j < width; j++) {
            row[j] = values[j];
        }
    }
}

/* The states, gains and metric sums of one chunk of settings, lane by lane. */
typedef struct {
    float kh[FUSION_ALTITUDE_SWEEP_LANES], kv[FUSION_ALTITUDE_SWEEP_LANES], kb[FUSION_ALTITUDE_SWEEP_LANES];
    float h[FUSION_ALTITUDE_SWEEP_LANES], v[FUSION_ALTITUDE_SWEEP_LANES], b[FUSION_ALTITUDE_SWEEP_LANES];
    float r[FUSION_ALTITUDE_SWEEP_LANES];
    float sum[FUSION_ALTITUDE_SWEEP_LANES], sumSquared[FUSION_ALTITUDE_SWEEP_LANES], maxAbs[FUSION_ALTITUDE_SWEEP_LANES];
} FusionAltitudeSweepLanes;

/** Samples per pass of the stability rule: their flags are kept in a local array of this many bytes. */
#define FUSION_ALTITUDE_SWEEP_FLAG_TILE (4096u)

/* Loads settings [first, first + width) into lanes; lanes past width repeat the last setting. */
FUSION_ALTITUDE_SWEEP_INLINE void FusionAltitudeSweepLoad(const FusionAltitudeSweep *const sweep, const FusionAltitudeSweepMetrics *const metrics,
                                                          const size_t first, const size_t width, const size_t lanes,
                                                          FusionAltitudeSweepLanes *const x) {
    for (size_t j = 0; j < lanes; j++) {
        const size_t k = first + ((j < width) ? j : (width - 1u));
        x->kh[j] = sweep->positionGain[k];
        x->kv[j] = sweep->velocityGain[k];
        x->kb[j] = sweep->biasGain[k];
        x->h[j] = sweep->altitude[k];
        x->v[j] = sweep->verticalVelocity[k];
        x->b[j] = sweep->accelBias[k];
        x->r[j] = sweep->baroResidual[k];
        x->sum[j] = (metrics != NULL) ? metrics->blockSumError[k] : 0.0f;
        x->sumSquared[j] = (metrics != NULL) ? metrics->blockSumSquaredError[k] : 0.0f;
        x->maxAbs[j] = (metrics != NULL) ? metrics->maxAbsError[k] : 0.0f;
    }
}

/* Stores the first width lanes back into settings [first, first + width). */
FUSION_ALTITUDE_SWEEP_INLINE void FusionAltitudeSweepStore(FusionAltitudeSweep *const sweep, FusionAltitudeSweepMetrics *const metrics,
                                                           const size_t first, const size_t width, const FusionAltitudeSweepLanes *const x) {
    for (size_t j = 0; j < width; j++) {
        const size_t k = first + j;
        sweep->altitude[k] = x->h[j];
        sweep->verticalVelocity[k] = x->v[j];
        sweep->accelBias[k] = x->b[j];
        sweep->baroResidual[k] = x->r[j];
        if (metrics != NULL) {
            metrics->blockSumError[k] = x->sum[j];
            metrics->blockSumSquaredError[k] = x->sumSquared[j];
            metrics->maxAbsError[k] = x->maxAbs[j];
        }
    }
}

/* The shared part of FusionAltitudeUpdate before the lanes (FusionAltitudeTiming):
 * gap detection, the time of a pending restart or since the last one, and the
 * baro timeout. unstable: a baro step that the stability rule makes a gap. */
FUSION_ALTITUDE_SWEEP_INLINE void FusionAltitudeSweepTiming(FusionAltitudeSweepShared *const shared, const float step, const bool baroSample,
                                                            const bool unstable, const float gapPeriod, const float baroTimeout) {
    FUSION_ALTITUDE_SWEEP_NO_CONTRACT
    if (shared->referenceSet && (step > gapPeriod)) {
        shared->gapCount++;
        shared->referenceSet = false;
        shared->gapTime = step;
    } else if (shared->referenceSet && unstable) { /* a stability gap: the lanes restart at this step's sample */
        shared->gapCount++;
        shared->sinceRestart = 0.0f;
    } else if (!shared->referenceSet && (shared->gapTime > 0.0f)) {
        shared->gapTime += step;
    } else if (shared->referenceSet && (shared->sinceRestart >= 0.0f)) {
        shared->sinceRestart += step;
    }
    if (baroSample) {
        shared->sinceBaro = 0.0f;
    } else if (shared->referenceSet || (shared->gapTime > 0.0f)) {
        shared->sinceBaro += step;
        if (!shared->baroTimedOut && (shared->sinceBaro > baroTimeout)) {
            shared->baroTimeouts++;
            shared->baroTimedOut = true;
        }
    }
}

/* The shared part of a restart (FusionAltitudeRestart): after a gap the bias hold restarts (sinceRestart = 0, s);
 * the gap ends, the reference is set and a baro timeout ends. */
FUSION_ALTITUDE_SWEEP_INLINE void FusionAltitudeSweepRestartShared(FusionAltitudeSweepShared *const shared) {
    if (shared->gapTime > 0.0f) {
        shared->sinceRestart = 0.0f;
    }
    shared->gapTime = 0.0f;
    shared->referenceSet = true;
    shared->baroTimedOut = false;
}

/* The stability rule of the sweep, for samples [0, samples) (at most
 * FUSION_ALTITUDE_SWEEP_FLAG_TILE) from the shared state *start: unstable[t]
 * is 1 when sample t carries a baro sample, the reference is set, no timeout
 * is on, and FusionAltitudeIsStepStable fails for at least one setting (at
 * dt and the baro interval sinceBaro + dt it ends) of
 * [-ruleBefore, count + ruleAfter). The shared state evolves
 * only with the inputs, so one pass gives the flags every chunk uses. */
FUSION_ALTITUDE_SWEEP_INLINE void FusionAltitudeSweepUnstableSteps(const FusionAltitudeSweep *const sweep, FusionAltitudeSweepShared shared,
                                                                   const float *const baroAltitude, const float *const dt,
                                                                   const size_t dtStride, const size_t samples, uint8_t *const unstable) {
    FUSION_ALTITUDE_SWEEP_NO_CONTRACT
    FusionAltitudeSettings settings = FusionAltitudeSettingsDefault();
    settings.gapPeriod = sweep->gapPeriod;
    settings.baroTimeout = sweep->baroTimeout;
    /* the verdict is a function of (dt, interval) alone: the last one is reused when both repeat bit for bit
     * (a constant dt and baro rate: the common case), so most steps check no setting */
    uint32_t lastStep = 0u;
    uint32_t lastInterval = 0u;
    bool lastAny = false;
    bool lastValid = false;
    for (size_t t = 0; t < samples; t++) {
        const float step = dt[t * dtStride];
        const bool baroSample = !FusionAltitudeIsNaN(baroAltitude[t]);
        bool any = false;
        if (baroSample && shared.referenceSet && !shared.baroTimedOut) {
            const float interval = FusionAltitudeIsFinite(sweep->baroTimeout) ? (shared.sinceBaro + step) : step;
            const bool cached = lastValid && (FusionAltitudeFloatBits(step) == lastStep) &&
                                (FusionAltitudeFloatBits(interval) == lastInterval);
            any = cached && lastAny;
            const float *const kh = sweep->positionGain - sweep->ruleBefore;
            const float *const kv = sweep->velocityGain - sweep->ruleBefore;
            const float *const kb = sweep->biasGain - sweep->ruleBefore;
            const size_t ruleCount = sweep->ruleBefore + sweep->count + sweep->ruleAfter;
            for (size_t k = 0; !cached && (k < ruleCount) && !any; k++) {
                settings.positionGain = kh[k];
                settings.velocityGain = kv[k];
                settings.biasGain = kb[k];
                any = !FusionAltitudeIsStepStable(&settings, step, interval);
            }
            lastStep = FusionAltitudeFloatBits(step);
            lastInterval = FusionAltitudeFloatBits(interval);
            lastAny = any;
            lastValid = true;
        }
        unstable[t] = (uint8_t) any;
        FusionAltitudeSweepTiming(&shared, step, baroSample, any, sweep->gapPeriod, sweep->baroTimeout);
        if (baroSample && !shared.referenceSet) {
            FusionAltitudeSweepRestartShared(&shared);
        } else if (baroSample && shared.baroTimedOut) { /* and of the restart after a timeout */
            shared.sinceRestart = 0.0f;
            shared.baroTimedOut = false;
        }
    }
}

/* FusionAltitudeRestart on every lane: h = z, v = 0 or the mean velocity over the gap (0 if it overflows), r = 0. */
FUSION_ALTITUDE_SWEEP_INLINE void FusionAltitudeSweepRestart(FusionAltitudeSweepLanes *const x, FusionAltitudeSweepShared *const shared,
                                                             const float z, const size_t lanes) {
    FUSION_ALTITUDE_SWEEP_NO_CONTRACT
    const float gapTime = shared->gapTime;
    for (size_t j = 0; j < lanes; j++) {
        const float velocity = (gapTime > 0.0f) ? ((z - x->h[j]) / gapTime) : 0.0f;
        x->v[j] = FusionAltitudeIsFinite(velocity) ? velocity : 0.0f;
        x->h[j] = z;
        x->r[j] = 0.0f;
    }
    FusionAltitudeSweepRestartShared(shared);
}

/* The correction on every lane; after a restart each lane holds its bias
 * while sinceRestart*Kh < FUSION_ALTITUDE_BIAS_HOLD. */
FUSION_ALTITUDE_SWEEP_INLINE void FusionAltitudeSweepCorrect(FusionAltitudeSweepLanes *const x, const float sinceRestart, const float a,
                                                             const float z, const float step, const size_t lanes) {
    FUSION_ALTITUDE_SWEEP_NO_CONTRACT
    if (sinceRestart < 0.0f) {
        for (size_t j = 0; j < lanes; j++) {
            const float residual = z - x->h[j];
            x->v[j] += ((a - x->b[j]) + x->kv[j] * residual) * step;
            x->h[j] += (x->v[j] + x->kh[j] * residual) * step;
            x->b[j] -= (x->kb[j] * residual) * step;
            x->r[j] = residual;
        }
        return;
    }
    for (size_t j = 0; j < lanes; j++) {
        const float residual = z - x->h[j];
        x->v[j] += ((a - x->b[j]) + x->kv[j] * residual) * step;
        x->h[j] += (x->v[j] + x->kh[j] * residual) * step;
        x->b[j] = (sinceRestart * x->kh[j] < FUSION_ALTITUDE_BIAS_HOLD) ? x->b[j] : (x->b[j] - (x->kb[j] * residual) * step);
        x->r[j] = residual;
    }
}

/* FusionAltitudeUpdate, lane by lane, the same operations in the same order
 * (inputs already checked): gap detection and the timeout, integration
 * without baro (or the velocity decay when timed out), the restart on the
 * first baro sample after a gap or a timeout, or the correction. */
FUSION_ALTITUDE_SWEEP_INLINE void FusionAltitudeSweepStep(FusionAltitudeSweepLanes *const x, FusionAltitudeSweepShared *const shared,
                                                          const float a, const float z, const float step, const bool unstable,
                                                          const float gapPeriod, const float baroTimeout, const size_t lanes) {
    FUSION_ALTITUDE_SWEEP_NO_CONTRACT
    const bool baroSample = !FusionAltitudeIsNaN(z);
    const bool stabilityGap = unstable && shared->referenceSet && !(step > gapPeriod);
    const float interval = FusionAltitudeIsFinite(baroTimeout) ? (shared->sinceBaro + step) : step;
    FusionAltitudeSweepTiming(shared, step, baroSample, unstable, gapPeriod, baroTimeout);
    if (!baroSample) {
        if (shared->referenceSet) {
            if (shared->baroTimedOut) {
                const float decay = baroTimeout / (baroTimeout + step);
                for (size_t j = 0; j < lanes; j++) {
                    x->v[j] *= decay;
                    x->h[j] += x->v[j] * step;
                }
            } else {
                for (size_t j = 0; j < lanes; j++) {
                    x->v[j] += (a - x->b[j]) * step;
                    x->h[j] += x->v[j] * step;
                }
            }
        }
        const float nan = FusionAltitudeNaN();
        for (size_t j = 0; j < lanes; j++) {
            x->r[j] = nan;
        }
    } else if (!shared->referenceSet) {
        FusionAltitudeSweepRestart(x, shared, z, lanes);
    } else if (stabilityGap) {
        for (size_t j = 0; j < lanes; j++) {
            FusionAltitudeStabilityRestart(&x->h[j], &x->v[j], &x->r[j], x->kh[j], x->kv[j], z, step, interval);
        }
    } else if (shared->baroTimedOut) {
        for (size_t j = 0; j < lanes; j++) {
            x->h[j] = z;
            x->r[j] = 0.0f;
        }
        shared->sinceRestart = 0.0f;
        shared->baroTimedOut = false;
    } else {
        FusionAltitudeSweepCorrect(x, shared->sinceRestart, a, z, step, lanes);
    }
}

/* Adds a full block's sums of the error (m) and of its square (m^2) into the totals of settings [first, first + width). */
FUSION_ALTITUDE_SWEEP_INLINE void FusionAltitudeSweepAddBlock(FusionAltitudeSweepMetrics *const metrics, const size_t first, const size_t width,
                                                              const float *const sum, const float *const sumSquared) {
    FUSION_ALTITUDE_SWEEP_NO_CONTRACT
    for (size_t j = 0; j < width; j++) {
        metrics->sumError[first + j] += sum[j];
        metrics->sumSquaredError[first + j] += sumSquared[j];
    }
}

/* Adds the errors h - reference of one sample to the block sums, and the
 * block sums into the totals of settings [first, first + width) when the
 * block is full. Returns the metric samples in the open block afterwards. */
FUSION_ALTITUDE_SWEEP_INLINE size_t FusionAltitudeSweepAccumulate(FusionAltitudeSweepLanes *const x, FusionAltitudeSweepMetrics *const metrics,
                                                                  const float reference, size_t samplesInBlock, const size_t first,
                                                                  const size_t width, const size_t lanes) {
    FUSION_ALTITUDE_SWEEP_NO_CONTRACT
    for (size_t j = 0; j < lanes; j++) {
        const float error = x->h[j] - reference;
        const float absolute = (error < 0.0f) ? -error : error;
        x->sum[j] += error;
        x->sumSquared[j] += error * error;
        x->maxAbs[j] = (absolute > x->maxAbs[j]) ? absolute : x->maxAbs[j];
    }
    if (++samplesInBlock == FUSION_ALTITUDE_SWEEP_BLOCK) {
        FusionAltitudeSweepAddBlock(metrics, first, width, x->sum, x->sumSquared);
        for (size_t j = 0; j < lanes; j++) {
            x->sum[j] = 0.0f;
            x->sumSquared[j] = 0.0f;
        }
        samplesInBlock = 0;
    }
    return samplesInBlock;
}

/* Runs settings [first, first + width) (width <= lanes <= LANES) over samples inputs;
 * outputs rows and metrics inputs start at the same sample as the inputs.
 * Lanes past width repeat the last setting and are never stored. *shared
 * starts as the sweep's and ends as it is after the samples (the same for
 * every chunk). Returns the metric samples in the open block afterwards. */
FUSION_ALTITUDE_SWEEP_INLINE size_t FusionAltitudeSweepChunk(FusionAltitudeSweep *const sweep, const size_t first, const size_t width,
                                            const float *const accel, const float *const baroAltitude, const float *const dt,
                                            const size_t dtStride, const size_t samples,
                                            const FusionAltitudeSweepOutputs *const outputs,
                                            FusionAltitudeSweepMetrics *const metrics, const size_t lanes,
                                            FusionAltitudeSweepShared *const shared, const uint8_t *const unstable) {
    FusionAltitudeSweepLanes x;
    FusionAltitudeSweepLoad(sweep, metrics, first, width, lanes, &x);
    size_t samplesInBlock = (metrics != NULL) ? metrics->samplesInBlock : 0u;
    for (size_t t = 0; t < samples; t++) {
        FusionAltitudeSweepStep(&x, shared, accel[t], baroAltitude[t], dt[t * dtStride], unstable[t] != 0u, sweep->gapPeriod,
                                sweep->baroTimeout, lanes);
        if (outputs != NULL) {
            const size_t offset = t * outputs->stride + first;
            FusionAltitudeSweepCopyRow(outputs->altitude, offset, x.h, width, lanes);
            FusionAltitudeSweepCopyRow(outputs->verticalVelocity, offset, x.v, width, lanes);
            FusionAltitudeSweepCopyRow(outputs->accelBias, offset, x.b, width, lanes);
            FusionAltitudeSweepCopyRow(outputs->baroResidual, offset, x.r, width, lanes);
        }
        if ((metrics != NULL) && ((metrics->mask == NULL) || (metrics->mask[t] != 0u)) &&
            FusionAltitudeIsFinite(metrics->reference[t])) {
            samplesInBlock = FusionAltitudeSweepAccumulate(&x, metrics, metrics->reference[t], samplesInBlock, first, width, lanes);
        }
    }
    FusionAltitudeSweepStore(sweep, metrics, first, width, &x);
    return samplesInBlock;
}

#if FUSION_ALTITUDE_SWEEP_VECTOR
/* The states, gains and metric sums of FusionAltitudeSweepLanes for 8 lanes, in vector registers. */
typedef struct {
    FusionAltitudeSweepVector8 kh, kv, kb, h, v, b, r, sum, sumSquared, maxAbs;
} FusionAltitudeSweepVectors8;

/* 8 copies of a float, as a vector initialiser (vectors are not passed by value: their ABI depends on AVX). */
#define FUSION_ALTITUDE_SWEEP_SPLAT8(value) {(value), (value), (value), (value), (value), (value), (value), (value)}

/* The first baro sample after a gap (or the first one), FusionAltitudeSweepRestart on 8 lanes:
 * h = z, r = 0, v = (z - h) / gapTime (m/s; 0 where it is not finite) after a gap, else 0. */
FUSION_ALTITUDE_SWEEP_INLINE void FusionAltitudeSweepRestart8(FusionAltitudeSweepVectors8 *const x, FusionAltitudeSweepShared *const shared,
                                                              const float z) {
    FUSION_ALTITUDE_SWEEP_NO_CONTRACT
    typedef FusionAltitudeSweepVector8 V;
    typedef FusionAltitudeSweepMask8 M;
    const V zeros = FUSION_ALTITUDE_SWEEP_SPLAT8(0.0f);
    const V zs = FUSION_ALTITUDE_SWEEP_SPLAT8(z);
    const float gapTime = shared->gapTime;
    if (gapTime > 0.0f) {
        const V gapTimes = FUSION_ALTITUDE_SWEEP_SPLAT8(gapTime);
        const V velocity = (zs - x->h) / gapTimes;
        const M finite = (M) ((velocity - velocity) == zeros); /* x - x is 0 exactly when x is finite */
        x->v = (V) ((M) velocity & finite);
    } else {
        x->v = zeros;
    }
    x->h = zs;
    x->r = zeros;
    FusionAltitudeSweepRestartShared(shared);
}

/* FusionAltitudeStabilityRestart lane by lane (rare: no need to vectorize); z in m, step and interval in s. */
FUSION_ALTITUDE_SWEEP_INLINE void FusionAltitudeSweepStabilityRestart8(FusionAltitudeSweepVectors8 *const x, const float z, const float step,
                                                                       const float interval) {
    FUSION_ALTITUDE_SWEEP_NO_CONTRACT
    typedef FusionAltitudeSweepUnaligned8 U;
    float lanesOf[5][8];
    *(U *) lanesOf[0] = x->h;
    *(U *) lanesOf[1] = x->v;
    *(U *) lanesOf[2] = x->r;
    *(U *) lanesOf[3] = x->kh;
    *(U *) lanesOf[4] = x->kv;
    for (size_t j = 0; j < 8u; j++) {
        FusionAltitudeStabilityRestart(&lanesOf[0][j], &lanesOf[1][j], &lanesOf[2][j], lanesOf[3][j], lanesOf[4][j], z, step, interval);
    }
    x->h = *(const U *) lanesOf[0];
    x->v = *(const U *) lanesOf[1];
    x->r = *(const U *) lanesOf[2];
}

/* The correction, FusionAltitudeSweepCorrect on 8 lanes: r = z - h, v += ((a - b) + Kv r) dt, h += (v + Kh r) dt,
 * b -= Kb r dt except in the lanes still holding their bias after a restart (sinceRestart Kh < FUSION_ALTITUDE_BIAS_HOLD). */
FUSION_ALTITUDE_SWEEP_INLINE void FusionAltitudeSweepCorrect8(FusionAltitudeSweepVectors8 *const x, const float sinceRestart, const float a,
                                                              const float z, const float step) {
    FUSION_ALTITUDE_SWEEP_NO_CONTRACT
    typedef FusionAltitudeSweepVector8 V;
    typedef FusionAltitudeSweepMask8 M;
    const V as = FUSION_ALTITUDE_SWEEP_SPLAT8(a);
    const V zs = FUSION_ALTITUDE_SWEEP_SPLAT8(z);
    const V steps = FUSION_ALTITUDE_SWEEP_SPLAT8(step);
    const V residual = zs - x->h;
    x->v += ((as - x->b) + x->kv * residual) * steps;
    x->h += (x->v + x->kh * residual) * steps;
    const V corrected = x->b - (x->kb * residual) * steps;
    if (sinceRestart < 0.0f) {
        x->b = corrected;
    } else {
        const V sinces = FUSION_ALTITUDE_SWEEP_SPLAT8(sinceRestart);
        const V hold = FUSION_ALTITUDE_SWEEP_SPLAT8(FUSION_ALTITUDE_BIAS_HOLD);
        const M held = (M) (sinces * x->kh < hold);
        x->b = (V) (((M) x->b & held) | ((M) corrected & ~held)); /* held lanes keep their bias */
    }
    x->r = residual;
}

/* One sample on 8 lanes, FusionAltitudeSweepStep's operations in their order: a in m/s^2, z in m (NaN: no baro), step in s. */
FUSION_ALTITUDE_SWEEP_INLINE void FusionAltitudeSweepStep8(FusionAltitudeSweepVectors8 *const x, FusionAltitudeSweepShared *const shared,
                                                           const FusionAltitudeSweep *const sweep, const float a, const float z,
                                                           const float step, const bool unstable) {
    FUSION_ALTITUDE_SWEEP_NO_CONTRACT
    typedef FusionAltitudeSweepVector8 V;
    const bool baroSample = !FusionAltitudeIsNaN(z);
    const bool stabilityGap = unstable && shared->referenceSet && !(step > sweep->gapPeriod);
    const float interval = FusionAltitudeIsFinite(sweep->baroTimeout) ? (shared->sinceBaro + step) : step;
    FusionAltitudeSweepTiming(shared, step, baroSample, unstable, sweep->gapPeriod, sweep->baroTimeout);
    const V steps = FUSION_ALTITUDE_SWEEP_SPLAT8(step);
    if (!baroSample) {
        if (shared->referenceSet) {
            if (shared->baroTimedOut) {
                const float decay = sweep->baroTimeout / (sweep->baroTimeout + step);
                const V decays = FUSION_ALTITUDE_SWEEP_SPLAT8(decay);
                x->v *= decays;
            } else {
                const V as = FUSION_ALTITUDE_SWEEP_SPLAT8(a);
                x->v += (as - x->b) * steps;
            }
            x->h += x->v * steps;
        }
        const float nan = FusionAltitudeNaN();
        const V nans = FUSION_ALTITUDE_SWEEP_SPLAT8(nan);
        x->r = nans;
    } else if (!shared->referenceSet) {
        FusionAltitudeSweepRestart8(x, shared, z);
    } else if (stabilityGap) {
        FusionAltitudeSweepStabilityRestart8(x, z, step, interval);
    } else if (shared->baroTimedOut) {
        const V zs = FUSION_ALTITUDE_SWEEP_SPLAT8(z);
        const V zeros = FUSION_ALTITUDE_SWEEP_SPLAT8(0.0f);
        x->h = zs;
        x->r = zeros;
        shared->sinceRestart = 0.0f;
        shared->baroTimedOut = false;
    } else {
        FusionAltitudeSweepCorrect8(x, shared->sinceRestart, a, z, step);
    }
}

/* FusionAltitudeSweepAccumulate on 8 lanes: adds the errors h - reference (m) to the block sums, and the block sums
 * into the totals of settings [first, first + width) when the block is full. Returns the samples in the open block. */
FUSION_ALTITUDE_SWEEP_INLINE size_t FusionAltitudeSweepAccumulate8(FusionAltitudeSweepVectors8 *const x, FusionAltitudeSweepMetrics *const metrics,
                                                                   const float reference, size_t samplesInBlock, const size_t first,
                                                                   const size_t width) {
    FUSION_ALTITUDE_SWEEP_NO_CONTRACT
    typedef FusionAltitudeSweepVector8 V;
    typedef FusionAltitudeSweepMask8 M;
    typedef FusionAltitudeSweepUnaligned8 U;
    const V zeros = FUSION_ALTITUDE_SWEEP_SPLAT8(0.0f);
    const V references = FUSION_ALTITUDE_SWEEP_SPLAT8(reference);
    const V error = x->h - references;
    const M negative = (M) (error < zeros);
    const V absolute = (V) (((M) (-error) & negative) | ((M) error & ~negative));
    x->sum += error;
    x->sumSquared += error * error;
    const M larger = (M) (absolute > x->maxAbs);
    x->maxAbs = (V) (((M) absolute & larger) | ((M) x->maxAbs & ~larger));
    if (++samplesInBlock == FUSION_ALTITUDE_SWEEP_BLOCK) {
        float sums[2][8];
        *(U *) sums[0] = x->sum;
        *(U *) sums[1] = x->sumSquared;
        FusionAltitudeSweepAddBlock(metrics, first, width, sums[0], sums[1]);
        x->sum = zeros;
        x->sumSquared = zeros;
        samplesInBlock = 0;
    }
    return samplesInBlock;
}

/* Writes the 8 lanes' h, v, b and r (the first width of them) into output row t. */
FUSION_ALTITUDE_SWEEP_INLINE void FusionAltitudeSweepWrite8(const FusionAltitudeSweepVectors8 *const x, const FusionAltitudeSweepOutputs *const outputs,
                                                            const size_t t, const size_t first, const size_t width) {
    typedef FusionAltitudeSweepUnaligned8 U;
    const size_t offset = t * outputs->stride + first;
    if (width == 8u) {
        if (outputs->altitude != NULL) {
            *(U *) &outputs->altitude[offset] = x->h;
        }
        if (outputs->verticalVelocity != NULL) {
            *(U *) &outputs->verticalVelocity[offset] = x->v;
        }
        if (outputs->accelBias != NULL) {
            *(U *) &outputs->accelBias[offset] = x->b;
        }
        if (outputs->baroResidual != NULL) {
            *(U *) &outputs->baroResidual[offset] = x->r;
        }
        return;
    }
    float lanes[4][8];
    *(U *) lanes[0] = x->h;
    *(U *) lanes[1] = x->v;
    *(U *) lanes[2] = x->b;
    *(U *) lanes[3] = x->r;
    FusionAltitudeSweepCopyRow(outputs->altitude, offset, lanes[0], width, 8u);
    FusionAltitudeSweepCopyRow(outputs->verticalVelocity, offset, lanes[1], width, 8u);
    FusionAltitudeSweepCopyRow(outputs->accelBias, offset, lanes[2], width, 8u);
    FusionAltitudeSweepCopyRow(outputs->baroResidual, offset, lanes[3], width, 8u);
}

/* FusionAltitudeSweepChunk for 8 lanes with the states in vector registers
 * (gcc/clang vector extensions) instead of the lane arrays: with few settings
 * the time step is a chain of dependent operations per lane, and keeping h, v
 * and b in memory between steps lengthened it by a store and a reload. Each
 * lane does the operations of FusionAltitudeSweepStep and
 * FusionAltitudeSweepAccumulate in their order, so the same bits. */
FUSION_ALTITUDE_SWEEP_INLINE size_t FusionAltitudeSweepChunk8(FusionAltitudeSweep *const sweep, const size_t first, const size_t width,
                                                             const float *const accel, const float *const baroAltitude, const float *const dt,
                                                             const size_t dtStride, const size_t samples,
                                                             const FusionAltitudeSweepOutputs *const outputs,
                                                             FusionAltitudeSweepMetrics *const metrics, FusionAltitudeSweepShared *const shared,
                                                             const uint8_t *const unstable) {
    FUSION_ALTITUDE_SWEEP_NO_CONTRACT
    typedef FusionAltitudeSweepUnaligned8 U;
    FusionAltitudeSweepLanes lanes;
    FusionAltitudeSweepLoad(sweep, metrics, first, width, 8u, &lanes);
    FusionAltitudeSweepVectors8 x;
    x.kh = *(const U *) lanes.kh;
    x.kv = *(const U *) lanes.kv;
    x.kb = *(const U *) lanes.kb;
    x.h = *(const U *) lanes.h;
    x.v = *(const U *) lanes.v;
    x.b = *(const U *) lanes.b;
    x.r = *(const U *) lanes.r;
    x.sum = *(const U *) lanes.sum;
    x.sumSquared = *(const U *) lanes.sumSquared;
    x.maxAbs = *(const U *) lanes.maxAbs;
    size_t samplesInBlock = (metrics != NULL) ? metrics->samplesInBlock : 0u;
    for (size_t t = 0; t < samples; t++) {
        FusionAltitudeSweepStep8(&x, shared, sweep, accel[t], baroAltitude[t], dt[t * dtStride], unstable[t] != 0u);
        if (outputs != NULL) {
            FusionAltitudeSweepWrite8(&x, outputs, t, first, width);
        }
        if ((metrics != NULL) && ((metrics->mask == NULL) || (metrics->mask[t] != 0u)) &&
            FusionAltitudeIsFinite(metrics->reference[t])) {
            samplesInBlock = FusionAltitudeSweepAccumulate8(&x, metrics, metrics->reference[t], samplesInBlock, first, width);
        }
    }
    *(U *) lanes.h = x.h;
    *(U *) lanes.v = x.v;
    *(U *) lanes.b = x.b;
    *(U *) lanes.r = x.r;
    *(U *) lanes.sum = x.sum;
    *(U *) lanes.sumSquared = x.sumSquared;
    *(U *) lanes.maxAbs = x.maxAbs;
    FusionAltitudeSweepStore(sweep, metrics, first, width, &lanes);
    return samplesInBlock;
}
#endif

/* true if FusionAltitudeCheckInputs accepts every sample: accel finite, baro
 * finite or NaN, dt finite and > 0. A branch-free pass (it vectorizes), so
 * that small sweeps do not pay a per-sample test; the per-sample tests run
 * only to find the first rejected sample. */
FUSION_ALTITUDE_SWEEP_INLINE bool FusionAltitudeSweepInputsValid(const float *const accel, const float *const baroAltitude,
                                                                 const float *const dt, const size_t dtStride, const size_t samples) {
    uint32_t invalid = 0u;
    size_t t = 0u;
    /* blocks of a constant 16 samples, so that gcc -O2 vectorizes them */
    for (; (t + 16u) <= samples; t += 16u) {
        uint32_t block[16];
        for (size_t j = 0; j < 16u; j++) {
            const uint32_t a = FusionAltitudeFloatBits(accel[t + j]);
            const uint32_t z = FusionAltitudeFloatBits(baroAltitude[t + j]);
            block[j] = (uint32_t) ((a & 0x7F800000u) == 0x7F800000u) | (uint32_t) ((z & 0x7FFFFFFFu) == 0x7F800000u);
        }
        for (size_t j = 0; j < 16u; j++) {
            invalid |= block[j];
        }
    }
    for (; t < samples; t++) {
        const uint32_t a = FusionAltitudeFloatBits(accel[t]);
        const uint32_t z = FusionAltitudeFloatBits(baroAltitude[t]);
        invalid |= (uint32_t) ((a & 0x7F800000u) == 0x7F800000u) | (uint32_t) ((z & 0x7FFFFFFFu) == 0x7F800000u);
    }
    const size_t dtCount = (dtStride == 0u) ? ((samples > 0u) ? 1u : 0u) : samples;
    for (size_t i = 0; i < dtCount; i++) {
        const float step = dt[i * dtStride];
        invalid |= (uint32_t) !FusionAltitudeIsFinite(step) | (uint32_t) !(step > 0.0f);
    }
    return invalid == 0u;
}

/* FusionAltitudeStatusOk, or the status of the first sample (its index in *badIndex) that FusionAltitudeCheckInputs rejects. */
FUSION_ALTITUDE_SWEEP_INLINE FusionAltitudeStatus FusionAltitudeSweepCheckInputs(const float *const accel, const float *const baroAltitude,
                                                                                 const float *const dt, const size_t dtStride,
                                                                                 const size_t samples, size_t *const badIndex) {
    if (FusionAltitudeSweepInputsValid(accel, baroAltitude, dt, dtStride, samples)) {
        return FusionAltitudeStatusOk;
    }
    for (size_t t = 0; t < samples; t++) {
        const FusionAltitudeStatus status = FusionAltitudeCheckInputs(accel[t], baroAltitude[t], dt[t * dtStride]);
        if (status != FusionAltitudeStatusOk) {
            *badIndex = t;
            return status;
        }
    }
    return FusionAltitudeStatusOk;
}

/* The samples of [start, start + length) that count in the metrics: a finite reference, and the mask (if any) set. */
FUSION_ALTITUDE_SWEEP_INLINE size_t FusionAltitudeSweepMetricSamples(const FusionAltitudeSweepMetrics *const metrics, const size_t start,
                                                                     const size_t length) {
    size_t counted = 0u;
    if (metrics->mask == NULL) {
        for (size_t t = start; t < start + length; t++) {
            counted += (size_t) FusionAltitudeIsFinite(metrics->reference[t]);
        }
    } else {
        for (size_t t = start; t < start + length; t++) {
            counted += (size_t) ((metrics->mask[t] != 0u) && FusionAltitudeIsFinite(metrics->reference[t]));
        }
    }
    return counted;
}

/**
 * @brief Runs every setting over samples inputs (the rules of
 * FusionAltitudeUpdate: baroAltitude NaN = no baro this step).
 *
 * @param dt sample period(s), s: dt[t * dtStride] (dtStride 0 for one value).
 * @param outputs NULL, or where to write the per-sample states.
 * @param metrics NULL, or error metrics to accumulate (flush at the end).
 * @param badIndex set to the first rejected sample on failure.
 * @return FusionAltitudeStatusOk, or the status of the first sample whose
 * inputs FusionAltitudeCheckInputs rejects; all inputs are checked before any
 * is applied, so on failure nothing (state, outputs, metrics) is touched.
 */
FUSION_ALTITUDE_SWEEP_CLONES static inline FusionAltitudeStatus FusionAltitudeSweepUpdate(FusionAltitudeSweep *const sweep, const float *const accel,
                                                             const float *const baroAltitude, const float *const dt,
                                                             const size_t dtStride, const size_t samples,
                                                             const FusionAltitudeSweepOutputs *const outputs,
                                                             FusionAltitudeSweepMetrics *const metrics, size_t *const badIndex) {
    const FusionAltitudeStatus status = FusionAltitudeSweepCheckInputs(accel, baroAltitude, dt, dtStride, samples, badIndex);
    if ((status != FusionAltitudeStatusOk) || (samples == 0u) || (sweep->count == 0u)) {
        return status;
    }
    /* With outputs, go through time in tiles of about FUSION_ALTITUDE_SWEEP_TILE_FLOATS
     * output floats, so every chunk writes its columns of a row while the row is in cache. */
    size_t tile = samples;
    if (outputs != NULL) {
        tile = FUSION_ALTITUDE_SWEEP_TILE_FLOATS / sweep->count;
        tile = (tile < 16u) ? 16u : tile;
    }
    tile = (tile < FUSION_ALTITUDE_SWEEP_FLAG_TILE) ? tile : FUSION_ALTITUDE_SWEEP_FLAG_TILE;
    uint8_t unstable[FUSION_ALTITUDE_SWEEP_FLAG_TILE];
    for (size_t start = 0; start < samples; start += tile) {
        const size_t length = ((samples - start) < tile) ? (samples - start) : tile;
        FusionAltitudeSweepOutputs rows;
        if (outputs != NULL) {
            const size_t offset = start * outputs->stride;
            rows.altitude = (outputs->altitude != NULL) ? &outputs->altitude[offset] : NULL;
            rows.verticalVelocity = (outputs->verticalVelocity != NULL) ? &outputs->verticalVelocity[offset] : NULL;
            rows.accelBias = (outputs->accelBias != NULL) ? &outputs->accelBias[offset] : NULL;
            rows.baroResidual = (outputs->baroResidual != NULL) ? &outputs->baroResidual[offset] : NULL;
            rows.stride = outputs->stride;
        }
        FusionAltitudeSweepMetrics window;
        if (metrics != NULL) {
            window = *metrics;
            window.reference = &metrics->reference[start];
            window.mask = (metrics->mask != NULL) ? &metrics->mask[start] : NULL;
        }
        size_t samplesInBlock = (metrics != NULL) ? metrics->samplesInBlock : 0u;
        FusionAltitudeSweepShared shared = FusionAltitudeSweepGetShared(sweep);
        FusionAltitudeSweepUnstableSteps(sweep, shared, &baroAltitude[start], &dt[start * dtStride], dtStride, length, unstable);
        for (size_t first = 0; first < sweep->count; first += (size_t) FUSION_ALTITUDE_SWEEP_LANES) {
            const size_t remaining = sweep->count - first;
            const size_t width = (remaining < (size_t) FUSION_ALTITUDE_SWEEP_LANES) ? remaining : (size_t) FUSION_ALTITUDE_SWEEP_LANES;
            const FusionAltitudeSweepOutputs *const chunkOutputs = (outputs != NULL) ? &rows : NULL;
            FusionAltitudeSweepMetrics *const chunkMetrics = (metrics != NULL) ? &window : NULL;
            shared = FusionAltitudeSweepGetShared(sweep); /* every chunk starts from the same shared state and ends with the same one */
            /* constant lane counts, so that each call compiles to fixed-width vector code */
            if (width <= 8u) {
#if FUSION_ALTITUDE_SWEEP_VECTOR
                samplesInBlock = FusionAltitudeSweepChunk8(sweep, first, width, &accel[start], &baroAltitude[start], &dt[start * dtStride],
                                                           dtStride, length, chunkOutputs, chunkMetrics, &shared, unstable);
#else
                samplesInBlock = FusionAltitudeSweepChunk(sweep, first, width, &accel[start], &baroAltitude[start], &dt[start * dtStride],
                                                          dtStride, length, chunkOutputs, chunkMetrics, 8u, &shared, unstable);
#endif
            } else {
                samplesInBlock = FusionAltitudeSweepChunk(sweep, first, width, &accel[start], &baroAltitude[start], &dt[start * dtStride],
                                                          dtStride, length, chunkOutputs, chunkMetrics, (size_t) FUSION_ALTITUDE_SWEEP_LANES,
                                                          &shared, unstable);
            }
        }
        FusionAltitudeSweepSetShared(sweep, &shared);
        if (metrics != NULL) {
            metrics->metricSamples += FusionAltitudeSweepMetricSamples(metrics, start, length);
            metrics->samplesInBlock = samplesInBlock;
        }
    }
    return FusionAltitudeStatusOk;
}

#undef FUSION_ALTITUDE_SWEEP_NO_CONTRACT

#ifdef FUSION_ALTITUDE_SWEEP_GCC_NO_CONTRACT
#pragma GCC pop_options
#undef FUSION_ALTITUDE_SWEEP_GCC_NO_CONTRACT
#endif

#ifdef __cplusplus
}
#endif

#endif
