/**
 * @file fusion_altitude_complementary.h
 * @brief The classic hobbyist two-stage complementary filter (baro +
 * accelerometer), as published for quadcopter altitude hold: low-pass both
 * signals, blend the integrated acceleration with a finite-difference baro
 * velocity, then blend the predicted altitude with the baro altitude.
 *
 * Header-only C99 (also valid C++), float32 only, no malloc, no globals, no
 * libm. Needs fusion_altitude.h (float classification) next to it.
 *
 * Units and frame: altitude m, vertical velocity m/s, acceleration m/s^2,
 * time and time constants s, coefficients dimensionless. Vertical is +up.
 *
 * One step with acceleration a, sample period dt and (maybe) a baro sample z:
 *   first-order low-pass     y += dt/(tau + dt) * (x - y)        (both signals)
 *   accel low-pass           aLp += dt/(tauA + dt) * (a - aLp)
 *   predicted velocity       vPred = v + aLp*dt
 *   predicted altitude       hPred = h + vPred*dt + 0.5*aLp*dt*dt
 * With a baro sample, D = time since the previous baro sample (dt when the
 * baro comes every step):
 *   baro low-pass            zLp' = zLp + D/(tauB + D) * (z - zLp)
 *   baro velocity            vBaro = (zLp' - zLp) / D
 *   velocity blend           v = cV*vPred + (1 - cV)*vBaro
 *   altitude blend           h = cH*hPred + (1 - cH)*zLp'
 * Without one: v = vPred, h = hPred. (hPred uses vPred, which already holds
 * aLp*dt, plus 0.5*aLp*dt^2 as the write-up does; the O(dt^2) surplus is
 * absorbed by the blend.)
 *
 * The blend coefficients cV, cH are either the write-up's fixed per-sample
 * numbers (0.999, 0.998: behaviour changes with the sample rate) or come from
 * time constants TV, TH in seconds, cV = TV/(TV + D), cH = TH/(TH + D), so the
 * filter behaves the same at any rate. The default is the time constants
 * TV = 9.99 s, TH = 4.99 s: exactly 0.999 and 0.998 at 100 Hz.
 *
 * Continuous-time picture (small D): dv/dt = a + (vBaro - v)/TV and
 * dh/dt = v + (zLp - h)/TH. A baro step of size S (a = 0) gives
 *   h(t) = S * (1 - (p e^{-pt} - q e^{-qt}) / (p - q)),  p = 1/TH, q = 1/TV,
 * (defaults: 50 % at 2.6 s, zero crossing of the error at 6.9 s, 12.5 %
 * overshoot at 13.9 s) and a constant accelerometer bias b, which this filter
 * has no state for, a steady altitude error of b*TV*TH (12 mg: 5.9 m).
 *
 * Stability: the homogeneous update is triangular, with eigenvalues
 * 1 - dt/(tauA + dt), 1 - D/(tauB + D), cV and cH, all in [0, 1] at every
 * dt and D (cV, cH in [0, 1] in both modes), so unlike the observer no step
 * is too long to integrate stably and there is no stability gap: a long step
 * costs dead-reckoning error (hPred carries aLp*dt^2), which the gap period
 * and the baro timeout bound. (The 7.7 km a 2.7 Hz telemetry log with 11 s
 * gaps produced came from dead reckoning, not from an unstable blend.)
 *
 * Baro timeout: once the reference is set, when no baro sample has come for
 * more than baroTimeout s (default 2 s, as the observer's) the timeout count
 * goes up and the filter is timed out (IsBaroTimedOut: not baro-aided) until
 * the next baro sample: the acceleration is no longer integrated (aLp kept),
 * the velocity decays to 0 with time constant T = baroTimeout,
 * v *= T/(T + dt), h += v*dt, so h moves at most |v|*T further. The next
 * baro sample restarts h = zLp = z with v kept (vBaro = v).
 *
 * Gaps: once the reference is set, a step with dt > gapPeriod (default 0.5 s,
 * as the observer's: no jitter trips it at 10 Hz or faster) is a gap and is
 * not integrated: the gap count goes up, the reference is released, h, v and
 * aLp are frozen, and the next baro sample z (this step's if it has one)
 * restarts the filter: h = zLp = z, v = vBaro = (z - h_before)/T, the mean
 * velocity over the T s since h was last updated, and the baro interval
 * starts again. The mean velocity, not 0, because with TV = 10 s a wrong
 * velocity takes tens of seconds to leave this filter (0 if it overflows).
 *
 * Bit-exact results across compilers and targets need IEEE float32 arithmetic
 * without fused multiply-add contraction. The header turns contraction off for
 * its own functions: a scoped pragma for clang, and for gcc in its GNU modes
 * and C++ (which contract by default) #pragma GCC optimize; ISO C modes
 * (-std=c99, -std=c11) have it off already. Under gcc's GNU modes, compile
 * with -ffp-contract=off as well, so that the functions still inline.
 *
 * Usage:
 * @code
 * FusionAltitudeComplementary filter;
 * FusionAltitudeComplementaryInitialise(&filter);         // default time constants
 * for (;;) {
 *     if (FusionAltitudeComplementaryUpdate(&filter, accel, baroOrNaN, 0.01f) != FusionAltitudeComplementaryStatusOk) {
 *         // input rejected, state unchanged
 *     }
 *     const float h = FusionAltitudeComplementaryGetAltitude(&filter);
 * }
 * @endcode
 */

#ifndef FUSION_ALTITUDE_COMPLEMENTARY_H
#define FUSION_ALTITUDE_COMPLEMENTARY_H

#include "fusion_altitude.h"

#include <stdbool.h>
#include <stdint.h>

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
#define FUSION_ALTITUDE_COMPLEMENTARY_GCC_NO_CONTRACT
#pragma GCC push_options
#pragma GCC optimize("fp-contract=off")
#endif

#if defined(__clang__)
#define FUSION_ALTITUDE_COMPLEMENTARY_NO_CONTRACT _Pragma("clang fp contract(off)")
#else
#define FUSION_ALTITUDE_COMPLEMENTARY_NO_CONTRACT
#endif

//------------------------------------------------------------------------------
// Definitions

/** Status returned by every function that can reject its input. */
typedef enum {
    FusionAltitudeComplementaryStatusOk = 0,
    FusionAltitudeComplementaryStatusInvalidAccel,        /**< accel not finite */
    FusionAltitudeComplementaryStatusInvalidBaroAltitude, /**< baro altitude infinite (update) or not finite (reset) */
    FusionAltitudeComplementaryStatusInvalidDt,           /**< dt not finite or <= 0 */
    FusionAltitudeComplementaryStatusInvalidTimeConstant, /**< a time constant not finite or < 0 */
    FusionAltitudeComplementaryStatusInvalidCoefficient,  /**< a per-sample coefficient not finite or outside [0, 1] */
    FusionAltitudeComplementaryStatusInvalidGapPeriod,    /**< gap period NaN or <= 0 (+infinity: never a gap) */
    FusionAltitudeComplementaryStatusInvalidBaroTimeout,  /**< baro timeout NaN or <= 0 (+infinity: never times out) */
} FusionAltitudeComplementaryStatus;

/** Settings. */
typedef struct {
    float accelTimeConstant;    /**< tauA, s, >= 0: accel low-pass (0: none) [rule: finite, >= 0; else InvalidTimeConstant] */
    float baroTimeConstant;     /**< tauB, s, >= 0: baro low-pass (0: none) [rule: finite, >= 0; else InvalidTimeConstant] */
    bool perSampleCoefficients; /**< true: cV, cH are the fixed coefficients below; false: from TV, TH [rule: any] */
    float velocityCoefficient;  /**< cV in [0, 1], per baro sample (used when perSampleCoefficients) [rule: finite, >= 0, <= 1; else InvalidCoefficient] */
    float altitudeCoefficient;  /**< cH in [0, 1], per baro sample (used when perSampleCoefficients) [rule: finite, >= 0, <= 1; else InvalidCoefficient] */
    float velocityTimeConstant; /**< TV, s, >= 0: cV = TV/(TV + D) (used otherwise) [rule: finite, >= 0; else InvalidTimeConstant] */
    float altitudeTimeConstant; /**< TH, s, >= 0: cH = TH/(TH + D) (used otherwise) [rule: finite, >= 0; else InvalidTimeConstant] */
    float gapPeriod;            /**< s: an update whose dt exceeds this is a gap, not integrated (default 0.5 s) [rule: > 0; else InvalidGapPeriod] */
    float baroTimeout;          /**< s: after this long without a baro sample the filter stops dead-reckoning (default 2 s; +infinity: never) [rule: > 0; else InvalidBaroTimeout] */
} FusionAltitudeComplementarySettings;

/** Filter state. Read it through the Get functions. */
typedef struct {
    FusionAltitudeComplementarySettings settings;
    float altitude;          /**< h, m */
    float verticalVelocity;  /**< v, m/s */
    float accelFiltered;     /**< aLp, m/s^2 */
    float baroFiltered;      /**< zLp, m */
    float baroVelocity;      /**< vBaro of the latest baro sample, m/s; NaN on a step without baro */
    float sinceBaro;         /**< s since the latest baro sample, before this step */
    float gapTime;           /**< s since h was last updated while a restart after a gap is pending; 0 otherwise */
    uint32_t gapCount;       /**< updates with dt > gapPeriod so far */
    uint32_t baroTimeouts;   /**< baro timeouts so far: times the time without a baro sample went above baroTimeout */
    bool referenceSet;       /**< false until the first baro sample or reset, and from a gap to the next baro sample */
    bool baroTimedOut;       /**< true from a baro timeout to the next baro sample: the output is not baro-aided */
} FusionAltitudeComplementary;

//------------------------------------------------------------------------------
// Status messages

/** @return a short English description of the status, never NULL. */
static inline const char *FusionAltitudeComplementaryStatusMessage(const FusionAltitudeComplementaryStatus status) {
    static const char *const texts[] = { /* in the enum's order */
        "ok", /* FusionAltitudeComplementaryStatusOk */
        "accel must be finite", /* FusionAltitudeComplementaryStatusInvalidAccel */
        "baro altitude must be finite (or NaN for no sample in update)", /* FusionAltitudeComplementaryStatusInvalidBaroAltitude */
        "dt must be finite and > 0", /* FusionAltitudeComplementaryStatusInvalidDt */
        "time constants must be finite and >= 0", /* FusionAltitudeComplementaryStatusInvalidTimeConstant */
        "per-sample coefficients must be finite and in [0, 1]", /* FusionAltitudeComplementaryStatusInvalidCoefficient */
        "gap period must be > 0 (+infinity: never a gap)", /* FusionAltitudeComplementaryStatusInvalidGapPeriod */
        "baro timeout must be > 0 (+infinity: never times out)", /* FusionAltitudeComplementaryStatusInvalidBaroTimeout */
    };
    return FusionAltitudeStatusText(texts, sizeof(texts) / sizeof(texts[0]), (size_t) status);
}

//------------------------------------------------------------------------------
// Settings

/**
 * @return the default settings: accel low-pass 0.02 s, baro low-pass 0.05 s,
 * time constants TV = 9.99 s and TH = 4.99 s (the write-up's 0.999 and 0.998
 * at 100 Hz, the same behaviour at any other rate), gap period 0.5 s, baro
 * timeout 2 s (FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT, justified there).
 */
static inline FusionAltitudeComplementarySettings FusionAltitudeComplementarySettingsDefault(void) {
    FusionAltitudeComplementarySettings settings;
    settings.accelTimeConstant = 0.02f;
    settings.baroTimeConstant = 0.05f;
    settings.perSampleCoefficients = false;
    settings.velocityCoefficient = 0.999f;
    settings.altitudeCoefficient = 0.998f;
    settings.velocityTimeConstant = 9.99f;
    settings.altitudeTimeConstant = 4.99f;
    settings.gapPeriod = 0.5f;
    settings.baroTimeout = FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT;
    return settings;
}

/** @internal @return true if value is a time constant (s): finite and >= 0. */
static inline bool FusionAltitudeComplementaryIsTimeConstant(const float value) {
    return FusionAltitudeIsFinite(value) && (value >= 0.0f);
}

/** @internal @return true if value is a coefficient: finite and in [0, 1]. */
static inline bool FusionAltitudeComplementaryIsCoefficient(const float value) {
    return FusionAltitudeIsFinite(value) && (value >= 0.0f) && (value <= 1.0f);
}

/**
 * @brief Checks settings: all four time constants finite and >= 0, both
 * coefficients finite and in [0, 1] (checked in both modes, so a settings
 * value is valid whichever mode it is switched to).
 */
static inline FusionAltitudeComplementaryStatus FusionAltitudeComplementarySettingsCheck(
    const FusionAltitudeComplementarySettings *const settings) {
    if (!FusionAltitudeComplementaryIsTimeConstant(settings->accelTimeConstant) ||
        !FusionAltitudeComplementaryIsTimeConstant(settings->baroTimeConstant) ||
        !FusionAltitudeComplementaryIsTimeConstant(settings->velocityTimeConstant) ||
        !FusionAltitudeComplementaryIsTimeConstant(settings->altitudeTimeConstant)) {
        return FusionAltitudeComplementaryStatusInvalidTimeConstant;
    }
    if (!FusionAltitudeComplementaryIsCoefficient(settings->velocityCoefficient) ||
        !FusionAltitudeComplementaryIsCoefficient(settings->altitudeCoefficient)) {
        return FusionAltitudeComplementaryStatusInvalidCoefficient;
    }
    if (!(settings->gapPeriod > 0.0f)) { /* false for NaN */
        return FusionAltitudeComplementaryStatusInvalidGapPeriod;
    }
    if (!(settings->baroTimeout > 0.0f)) { /* false for NaN */
        return FusionAltitudeComplementaryStatusInvalidBaroTimeout;
    }
    return FusionAltitudeComplementaryStatusOk;
}

//------------------------------------------------------------------------------
// Filter

/** @brief Initialises with the default settings; the first baro sample sets the reference. */
static inline void FusionAltitudeComplementaryInitialise(FusionAltitudeComplementary *const filter) {
    filter->settings = FusionAltitudeComplementarySettingsDefault();
    filter->altitude = 0.0f;
    filter->verticalVelocity = 0.0f;
    filter->accelFiltered = 0.0f;
    filter->baroFiltered = 0.0f;
    filter->baroVelocity = 0.0f;
    filter->sinceBaro = 0.0f;
    filter->gapTime = 0.0f;
    filter->gapCount = 0u;
    filter->baroTimeouts = 0u;
    filter->referenceSet = false;
    filter->baroTimedOut = false;
}

/** @brief Replaces the settings, keeping the state. Rejected (state unchanged) if the check fails. */
static inline FusionAltitudeComplementaryStatus FusionAltitudeComplementarySetSettings(
    FusionAltitudeComplementary *const filter, const FusionAltitudeComplementarySettings *const settings) {
    const FusionAltitudeComplementaryStatus status = FusionAltitudeComplementarySettingsCheck(settings);
    if (status == FusionAltitudeComplementaryStatusOk) {
        filter->settings = *settings;
    }
    return status;
}

/**
 * @brief Sets the reference: altitude = filtered baro = baroAltitude (m),
 * velocity 0, baro velocity 0; a baro timeout is cancelled. The accel
 * low-pass state and the counts are kept. Rejected if baroAltitude is not
 * finite.
 */
static inline FusionAltitudeComplementaryStatus FusionAltitudeComplementaryReset(FusionAltitudeComplementary *const filter,
                                                                                  const float baroAltitude) {
    if (!FusionAltitudeIsFinite(baroAltitude)) {
        return FusionAltitudeComplementaryStatusInvalidBaroAltitude;
    }
    filter->altitude = baroAltitude;
    filter->baroFiltered = baroAltitude;
    filter->verticalVelocity = 0.0f;
    filter->baroVelocity = 0.0f;
    filter->sinceBaro = 0.0f;
    filter->gapTime = 0.0f;
    filter->referenceSet = true;
    filter->baroTimedOut = false;
    return FusionAltitudeComplementaryStatusOk;
}

/** @internal
 * @brief The first baro sample z (m) after a gap restarts the
 * filter: v = vBaro = (z - h)/gapTime (the mean velocity over the gap),
 * h = zLp = z, the baro interval restarts; aLp is kept.
 */
static inline void FusionAltitudeComplementaryRestart(FusionAltitudeComplementary *const filter, const float baroAltitude) {
    FUSION_ALTITUDE_COMPLEMENTARY_NO_CONTRACT
    float velocity = (baroAltitude - filter->altitude) / filter->gapTime;
    velocity = FusionAltitudeIsFinite(velocity) ? velocity : 0.0f; /* overflow: a gap of a few ulps */
    filter->altitude = baroAltitude;
    filter->baroFiltered = baroAltitude;
    filter->verticalVelocity = velocity;
    filter->baroVelocity = velocity;
    filter->sinceBaro = 0.0f;
    filter->gapTime = 0.0f;
    filter->referenceSet = true;
    filter->baroTimedOut = false;
}

/** @internal
 * @brief A step while the baro is timed out (no dead reckoning).
 * Without a baro sample v decays, v *= T / (T + dt) with T = baroTimeout (s),
 * and h += v dt (m); a baro sample z (m) ends the timeout: h = zLp = z, the
 * baro velocity takes v (kept), the baro interval restarts.
 */
static inline void FusionAltitudeComplementaryTimedOutStep(FusionAltitudeComplementary *const filter, const float baroAltitude,
                                                           const bool baroSample, const float dt) {
    FUSION_ALTITUDE_COMPLEMENTARY_NO_CONTRACT
    if (baroSample) {
        filter->altitude = baroAltitude;
        filter->baroFiltered = baroAltitude;
        filter->baroVelocity = filter->verticalVelocity;
        filter->sinceBaro = 0.0f;
        filter->baroTimedOut = false;
        return;
    }
    const float timeout = filter->settings.baroTimeout;
    filter->verticalVelocity *= timeout / (timeout + dt);
    filter->altitude += filter->verticalVelocity * dt;
    filter->baroVelocity = FusionAltitudeNaN();
    filter->sinceBaro += dt;
}

/**
 * @brief The input rules of FusionAltitudeComplementaryUpdate: accel finite,
 * baroAltitude finite or NaN (no sample), dt finite and > 0.
 */
static inline FusionAltitudeComplementaryStatus FusionAltitudeComplementaryCheckInputs(const float accel, const float baroAltitude,
                                                                                       const float dt) {
    if (!FusionAltitudeIsFinite(accel)) {
        return FusionAltitudeComplementaryStatusInvalidAccel;
    }
    if ((FusionAltitudeFloatBits(baroAltitude) & 0x7FFFFFFFu) == 0x7F800000u) { /* +-infinity; NaN means no sample */
        return FusionAltitudeComplementaryStatusInvalidBaroAltitude;
    }
    if (!FusionAltitudeIsFinite(dt) || !(dt > 0.0f)) {
        return FusionAltitudeComplementaryStatusInvalidDt;
    }
    return FusionAltitudeComplementaryStatusOk;
}

/**
 * @brief One step (see the file comment for the equations).
 *
 * @param accel vertical acceleration a, m/s^2, earth frame, +up, gravity removed.
 * @param baroAltitude baro altitude z, m; NaN when no baro sample this step.
 * @param dt time since the previous step, s.
 *
 * Until the reference is set a baro sample only sets it (Reset; a and dt
 * unused) and a step without baro changes nothing but the baro velocity (NaN).
 * A dt above gapPeriod is a gap, and more than baroTimeout s without a baro
 * sample a timeout: see the file comment.
 * Inputs are checked first; a rejected call leaves the state unchanged.
 */
static inline FusionAltitudeComplementaryStatus FusionAltitudeComplementaryUpdate(FusionAltitudeComplementary *const filter,
                                                                                   const float accel, const float baroAltitude,
                                                                                   const float dt) {
    FUSION_ALTITUDE_COMPLEMENTARY_NO_CONTRACT
    const FusionAltitudeComplementaryStatus status = FusionAltitudeComplementaryCheckInputs(accel, baroAltitude, dt);
    if (status != FusionAltitudeComplementaryStatusOk) {
        return status;
    }
    const bool baroSample = FusionAltitudeIsFinite(baroAltitude);
    if (filter->referenceSet && (dt > filter->settings.gapPeriod)) { /* a gap: restart from the next baro sample */
        filter->gapCount++;
        filter->referenceSet = false;
        filter->gapTime = dt;
    } else if (!filter->referenceSet && (filter->gapTime > 0.0f)) { /* still waiting for the baro after a gap */
        filter->gapTime += dt;
    }
    if (!baroSample && (filter->referenceSet || (filter->gapTime > 0.0f)) && !filter->baroTimedOut &&
        ((filter->sinceBaro + dt) > filter->settings.baroTimeout)) { /* a baro timeout */
        filter->baroTimeouts++;
        filter->baroTimedOut = true;
    }
    if (!filter->referenceSet) {
        if (baroSample && (filter->gapTime > 0.0f)) {
            FusionAltitudeComplementaryRestart(filter, baroAltitude);
            return FusionAltitudeComplementaryStatusOk;
        }
        if (baroSample) {
            return FusionAltitudeComplementaryReset(filter, baroAltitude);
        }
        if (filter->gapTime > 0.0f) {
            filter->sinceBaro += dt;
        }
        filter->baroVelocity = FusionAltitudeNaN();
        return FusionAltitudeComplementaryStatusOk;
    }
    if (filter->baroTimedOut) { /* no dead reckoning: v decays to 0; the next baro sample restarts h at it */
        FusionAltitudeComplementaryTimedOutStep(filter, baroAltitude, baroSample, dt);
        return FusionAltitudeComplementaryStatusOk;
    }
    const FusionAltitudeComplementarySettings *const s = &filter->settings;
    filter->accelFiltered += (dt / (s->accelTimeConstant + dt)) * (accel - filter->accelFiltered);
    const float aLp = filter->accelFiltered;
    const float velocityPredicted = filter->verticalVelocity + aLp * dt;
    const float altitudePredicted = filter->altitude + velocityPredicted * dt + 0.5f * aLp * dt * dt;
    if (!baroSample) {
        filter->verticalVelocity = velocityPredicted;
        filter->altitude = altitudePredicted;
        filter->baroVelocity = FusionAltitudeNaN();
        filter->sinceBaro += dt;
        return FusionAltitudeComplementaryStatusOk;
    }
    const float interval = filter->sinceBaro + dt; /* D */
    const float baroPrevious = filter->baroFiltered;
    filter->baroFiltered = baroPrevious + (interval / (s->baroTimeConstant + interval)) * (baroAltitude - baroPrevious);
    const float baroVelocity = (filter->baroFiltered - baroPrevious) / interval;
    float cV;
    float cH;
    if (s->perSampleCoefficients) {
        cV = s->velocityCoefficient;
        cH = s->altitudeCoefficient;
    } else {
        cV = s->velocityTimeConstant / (s->velocityTimeConstant + interval);
        cH = s->altitudeTimeConstant / (s->altitudeTimeConstant + interval);
    }
    filter->verticalVelocity = cV * velocityPredicted + (1.0f - cV) * baroVelocity;
    filter->altitude = cH * altitudePredicted + (1.0f - cH) * filter->baroFiltered;
    filter->baroVelocity = baroVelocity;
    filter->sinceBaro = 0.0f;
    return FusionAltitudeComplementaryStatusOk;
}

/** @return the settings in use. */
static inline FusionAltitudeComplementarySettings FusionAltitudeComplementaryGetSettings(const FusionAltitudeComplementary *const filter) {
    return filter->settings;
}

/** @return altitude estimate h, m (0 until the reference is set). */
static inline float FusionAltitudeComplementaryGetAltitude(const FusionAltitudeComplementary *const filter) {
    return filter->altitude;
}

/** @return vertical velocity estimate v, m/s, +up. */
static inline float FusionAltitudeComplementaryGetVerticalVelocity(const FusionAltitudeComplementary *const filter) {
    return filter->verticalVelocity;
}

/** @return low-passed baro altitude zLp, m. */
static inline float FusionAltitudeComplementaryGetBaroFiltered(const FusionAltitudeComplementary *const filter) {
    return filter->baroFiltered;
}

/** @return finite-difference baro velocity of the latest step, m/s; NaN on a step without baro. */
static inline float FusionAltitudeComplementaryGetBaroVelocity(const FusionAltitudeComplementary *const filter) {
    return filter->baroVelocity;
}

/** @return the number of gaps so far: updates with dt > gapPeriod once the reference was set. */
static inline uint32_t FusionAltitudeComplementaryGetGapCount(const FusionAltitudeComplementary *const filter) {
    return filter->gapCount;
}

/** @return the number of baro timeouts so far. */
static inline uint32_t FusionAltitudeComplementaryGetBaroTimeouts(const FusionAltitudeComplementary *const filter) {
    return filter->baroTimeouts;
}

/** @return true from a baro timeout to the next baro sample: the output is not baro-aided. */
static inline bool FusionAltitudeComplementaryIsBaroTimedOut(const FusionAltitudeComplementary *const filter) {
    return filter->baroTimedOut;
}

/** @return true once the reference is set; false from a gap to the next baro sample. */
static inline bool FusionAltitudeComplementaryIsReferenceSet(const FusionAltitudeComplementary *const filter) {
    return filter->referenceSet;
}

#undef FUSION_ALTITUDE_COMPLEMENTARY_NO_CONTRACT

#ifdef FUSION_ALTITUDE_COMPLEMENTARY_GCC_NO_CONTRACT
#pragma GCC pop_options
#undef FUSION_ALTITUDE_COMPLEMENTARY_GCC_NO_CONTRACT
#endif

#ifdef __cplusplus
}
#endif

#endif
