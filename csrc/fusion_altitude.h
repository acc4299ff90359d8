/**
 * @file fusion_altitude.h
 * @brief Altitude and vertical-velocity estimation: a 3rd-order complementary
 * observer that fuses barometric altitude with gravity-compensated vertical
 * acceleration and estimates the accelerometer's vertical bias.
 *
 * Header-only C99 (also valid C++), float32 only, no malloc, no globals, no
 * libm. Copy this one file into a project and include it.
 *
 * Units and frame: altitude m, vertical velocity m/s, acceleration m/s^2,
 * time s, gains 1/s, 1/s^2, 1/s^3. Vertical is +up; NED users negate their
 * down-acceleration and down-position before calling.
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
 * FusionAltitude altitude;
 * FusionAltitudeInitialise(&altitude);            // default (VTOL) gains
 * for (;;) {
 *     const float accel = ...;                    // m/s^2, earth frame, +up, gravity removed
 *     const float baroAltitude = ...;             // m, or FUSION_ALTITUDE_NO_BARO
 *     if (FusionAltitudeUpdate(&altitude, accel, baroAltitude, 0.01f) != FusionAltitudeStatusOk) {
 *         // input rejected, state unchanged
 *     }
 *     const float h = FusionAltitudeGetAltitude(&altitude);          // m
 *     const float v = FusionAltitudeGetVerticalVelocity(&altitude);  // m/s
 * }
 * @endcode
 */

#ifndef FUSION_ALTITUDE_H
#define FUSION_ALTITUDE_H

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

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
#define FUSION_ALTITUDE_GCC_NO_CONTRACT
#pragma GCC push_options
#pragma GCC optimize("fp-contract=off")
#endif

/* Clang contracts a*b + c into an FMA by default; this keeps every operation
 * rounded on its own so that results are identical on every target. It is
 * placed at the top of each function body so it does not leak into user code. */
#if defined(__clang__)
#define FUSION_ALTITUDE_NO_CONTRACT _Pragma("clang fp contract(off)")
#else
#define FUSION_ALTITUDE_NO_CONTRACT
#endif

//------------------------------------------------------------------------------
// Definitions

/** Standard gravity, m/s^2. Multiply an acceleration in g by this. */
#define FUSION_ALTITUDE_GRAVITY (9.80665f)

/* The version of the headers: fusion_altitude/_version.py is its one source,
 * written here (and into the firmware package manifests) by
 * tools/sync_version.py; tests/test_distribution.py checks they agree. */
#define FUSION_ALTITUDE_VERSION_MAJOR (0)
#define FUSION_ALTITUDE_VERSION_MINOR (1)
#define FUSION_ALTITUDE_VERSION_PATCH (0)
#define FUSION_ALTITUDE_VERSION_STRING "0.1.0"

/** Version of this header, major * 10000 + minor * 100 + patch. */
#define FUSION_ALTITUDE_VERSION (100)

/**
 * @brief Pass as the baro altitude of FusionAltitudeUpdate when no baro sample
 * arrived this step (a quiet NaN, built without libm).
 */
#define FUSION_ALTITUDE_NO_BARO (FusionAltitudeNaN())

/** Status returned by every function that can reject its input. */
typedef enum {
    FusionAltitudeStatusOk = 0,
    FusionAltitudeStatusInvalidAccel,          /**< accel not finite */
    FusionAltitudeStatusInvalidBaroAltitude,   /**< baro altitude infinite (update) or not finite (reset) */
    FusionAltitudeStatusInvalidDt,             /**< dt not finite or <= 0 */
    FusionAltitudeStatusInvalidAccelBias,      /**< warm-start accel bias not finite */
    FusionAltitudeStatusInvalidGain,           /**< a gain is not finite, is negative or exceeds FUSION_ALTITUDE_MAXIMUM_GAIN */
    FusionAltitudeStatusUnstableGains,         /**< continuous-time observer not stable (Routh-Hurwitz) */
    FusionAltitudeStatusUnstableDiscrete,      /**< discrete update not stable at this dt (Jury) */
    FusionAltitudeStatusInvalidBandwidth,      /**< omega, zeta or omega_b out of range */
    FusionAltitudeStatusInvalidPreset,         /**< unknown preset */
    FusionAltitudeStatusInvalidGapPeriod,      /**< gap period NaN or <= 0 (+infinity: never a gap) */
    FusionAltitudeStatusInvalidBaroTimeout,    /**< baro timeout NaN or <= 0 (+infinity: never times out) */
} FusionAltitudeStatus;

/** Tuning presets. Each is zeta = 0.7, omega_b = omega / 5 through the formulas of FusionAltitudeSettingsFromBandwidth. */
typedef enum {
    FusionAltitudePresetBalloon = 0,   /**< omega = 0.2 rad/s */
    FusionAltitudePresetFixedWing,     /**< omega = 0.5 rad/s */
    FusionAltitudePresetVtol,          /**< omega = 1.5 rad/s (the default) */
    FusionAltitudePresetRacing,        /**< omega = 5.0 rad/s */
    FusionAltitudePresetRocket,        /**< omega = 1.0 rad/s, omega_b = 0: no bias learning in flight */
} FusionAltitudePreset;

/**
 * Default gap period, s: 0.5 s. An update whose dt exceeds it is a gap (see
 * FusionAltitudeUpdate). 0.5 s is 50 periods at 100 Hz and 5 at 10 Hz, so no
 * scheduler jitter trips it, and it stays below 0.83 s, where the default
 * gains fail Jury's test (Kh*dt < 2): a longer step cannot be integrated
 * stably anyway. Logs slower than 2 Hz (a 1 Hz balloon) need a longer one:
 * the balloon preset uses 5 s (its gains are stable up to 6 s), or set it to
 * about 5x the log's median dt.
 */
#define FUSION_ALTITUDE_DEFAULT_GAP_PERIOD (0.5f)

/**
 * Largest gain FusionAltitudeSettingsCheck accepts (Kh 1/s, Kv 1/s^2, Kb 1/s^3):
 * with every gain <= 1e15 the products the check and the update form (Kh*Kv,
 * Kv*r, Kb*dt^3) stay finite in float32 (max 3.4e38); ω = 10^4 rad/s, far
 * past any stable rate, gives Kb = ω^2 ω_b <= 10^12.
 */
#define FUSION_ALTITUDE_MAXIMUM_GAIN (1e15f)

/**
 * Stability margin of the gap rule: a step that carries a baro sample is a gap
 * unless the update with the gains in force passes Jury's test at
 * FUSION_ALTITUDE_STABILITY_MARGIN times its dt (see FusionAltitudeIsStepStable).
 * 1.5: the step may be 1.5x longer before the update diverges. At the limit
 * the largest discrete eigenvalue of every preset with bias learning has
 * |z| = 0.87 (the rocket's, Kb = 0, has its marginal bias mode z = 1 and the
 * others inside), so a run of such steps still damps every error. With a baro
 * sample every step: default (VTOL) gains, Jury's limit 0.620 s, so steps
 * above 0.413 s are gaps; racing 0.186 s -> 0.124 s; fixed wing
 * 1.86 s -> 1.24 s; balloon 4.65 s -> 3.10 s; rocket 1.04 s -> 0.694 s.
 */
#define FUSION_ALTITUDE_STABILITY_MARGIN (1.5f)

/**
 * Default baro timeout, s: 2 s. Once the reference is set, when no baro
 * sample has arrived for more than baroTimeout s the observer stops
 * dead-reckoning (see FusionAltitudeUpdate). 2 s is 4 baro periods of a 2 Hz
 * baro and 20 of a 10 Hz one, so a slow baro does not trip it; and over 2 s
 * an accel bias error of 0.1 m/s^2 (10 mg, what is left after the bias loop
 * converged on a hobby IMU) already moves the altitude by 0.5*0.1*2^2 = 0.2 m
 * and a velocity error of 0.1 m/s by 0.2 m more, together about the noise of
 * a raw baro: beyond that, dead reckoning is worse than holding still. Slower
 * baros need a longer one: the balloon preset uses 10 s.
 */
#define FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT (2.0f)

/**
 * After a restart following a gap the bias is held (not corrected) while
 * sinceRestart*Kh < FUSION_ALTITUDE_BIAS_HOLD, i.e. for 8/Kh s: about the
 * 2 % settling time 4/(zeta*omega) of the height and velocity loop
 * (Kh = 2*zeta*omega + omega_b), so the error of the restarted velocity is
 * corrected through v and h before it can reach b.
 */
#define FUSION_ALTITUDE_BIAS_HOLD (8.0f)

/**
 * @brief Observer settings. The error dynamics have the characteristic
 * polynomial s^3 + positionGain*s^2 + velocityGain*s + biasGain.
 */
typedef struct {
    float positionGain; /**< Kh, 1/s: baro residual into altitude [rule: finite, >= 0, <= FUSION_ALTITUDE_MAXIMUM_GAIN; else InvalidGain] */
    float velocityGain; /**< Kv, 1/s^2: baro residual into vertical velocity [rule: finite, >= 0, <= FUSION_ALTITUDE_MAXIMUM_GAIN; else InvalidGain] */
    float biasGain;     /**< Kb, 1/s^3: baro residual into accel bias; 0 disables bias estimation [rule: finite, >= 0, <= FUSION_ALTITUDE_MAXIMUM_GAIN; else InvalidGain] */
    float gapPeriod;    /**< s: an update whose dt exceeds this is a gap, not integrated (default FUSION_ALTITUDE_DEFAULT_GAP_PERIOD) [rule: > 0; else InvalidGapPeriod] */
    float baroTimeout;  /**< s: after this long without a baro sample the observer stops dead-reckoning (default FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT; +infinity: never) [rule: > 0; else InvalidBaroTimeout] */
} FusionAltitudeSettings;

/** Observer state. Read it through the Get functions. */
typedef struct {
    FusionAltitudeSettings settings;
    float altitude;         /**< h, m */
    float verticalVelocity; /**< v, m/s, +up */
    float accelBias;        /**< b, m/s^2, +up: subtracted from the accel input */
    float baroResidual;     /**< r = z - h before the correction, m; NaN on a step without baro */
    float gapTime;          /**< s since h was last updated while a restart after a gap is pending; 0 otherwise */
    float sinceRestart;     /**< s since the last restart after a gap or a baro timeout (the bias is held while sinceRestart*Kh < 8); -1 before any */
    float sinceBaro;        /**< s since the latest baro sample (0 on a step with one, and before the reference is first set) */
    uint32_t gapCount;      /**< gaps so far: updates with dt > gapPeriod, or a baro step the gains cannot integrate stably */
    uint32_t baroTimeouts;  /**< baro timeouts so far: times sinceBaro went above baroTimeout */
    bool referenceSet;      /**< false until the first baro sample or reset, and again from a gap to the next baro sample */
    bool baroTimedOut;      /**< true from a baro timeout to the next baro sample: the output is not baro-aided */
} FusionAltitude;

//------------------------------------------------------------------------------
// Float classification without libm (bit patterns of IEEE 754 binary32)

/** @return the IEEE 754 binary32 bit pattern of value (memcpy: no pointer punning, no libm). */
static inline uint32_t FusionAltitudeFloatBits(const float value) {
    uint32_t bits;
    memcpy(&bits, &value, sizeof(bits));
    return bits;
}

/** @return true if value is neither infinite nor NaN. */
static inline bool FusionAltitudeIsFinite(const float value) {
    return (FusionAltitudeFloatBits(value) & 0x7F800000u) != 0x7F800000u;
}

/** @return true if value is a NaN. */
static inline bool FusionAltitudeIsNaN(const float value) {
    const uint32_t bits = FusionAltitudeFloatBits(value);
    return ((bits & 0x7F800000u) == 0x7F800000u) && ((bits & 0x007FFFFFu) != 0u);
}

/** @internal @return true if value is finite and 0 <= value <= maximum (a setting that may be 0). */
static inline bool FusionAltitudeIsNonNegative(const float value, const float maximum) {
    return FusionAltitudeIsFinite(value) && (value >= 0.0f) && (value <= maximum);
}

/** @internal @return true if value is finite and 0 < value <= maximum (a setting that must be > 0). */
static inline bool FusionAltitudeIsPositive(const float value, const float maximum) {
    return FusionAltitudeIsFinite(value) && (value > 0.0f) && (value <= maximum);
}

/** @return a quiet NaN. */
static inline float FusionAltitudeNaN(void) {
    const uint32_t bits = 0x7FC00000u;
    float value;
    memcpy(&value, &bits, sizeof(value));
    return value;
}

//------------------------------------------------------------------------------
// Status messages

/** @internal
 * @return texts[status], the text of a status in an estimator's table
 * (one text a status value, in its enum's order), or "unknown status" for a
 * value outside the table. Each ...StatusMessage function calls it.
 */
static inline const char *FusionAltitudeStatusText(const char *const *const texts, const size_t count, const size_t status) {
    return (status < count) ? texts[status] : "unknown status";
}

/** @return a short English description of the status, never NULL. */
static inline const char *FusionAltitudeStatusMessage(const FusionAltitudeStatus status) {
    static const char *const texts[] = { /* in the enum's order */
        "ok", /* FusionAltitudeStatusOk */
        "accel must be finite", /* FusionAltitudeStatusInvalidAccel */
        "baro altitude must be finite (or NaN for no sample in update)", /* FusionAltitudeStatusInvalidBaroAltitude */
        "dt must be finite and > 0", /* FusionAltitudeStatusInvalidDt */
        "accel bias must be finite", /* FusionAltitudeStatusInvalidAccelBias */
        "gains must be finite, >= 0 and <= 1e15", /* FusionAltitudeStatusInvalidGain */
        "gains are not stable: need position_gain * velocity_gain > bias_gain (and position_gain > 0 when velocity_gain > 0)", /* FusionAltitudeStatusUnstableGains */
        "gains are not stable at this dt: the discrete update diverges", /* FusionAltitudeStatusUnstableDiscrete */
        "omega and zeta must be finite and > 0, omega_b finite and >= 0", /* FusionAltitudeStatusInvalidBandwidth */
        "unknown preset", /* FusionAltitudeStatusInvalidPreset */
        "gap period must be > 0 (+infinity: never a gap)", /* FusionAltitudeStatusInvalidGapPeriod */
        "baro timeout must be > 0 (+infinity: never times out)", /* FusionAltitudeStatusInvalidBaroTimeout */
    };
    return FusionAltitudeStatusText(texts, sizeof(texts) / sizeof(texts[0]), (size_t) status);
}

//------------------------------------------------------------------------------
// Settings

/** @return +infinity (a gap period or baro timeout that never fires), built without libm. */
static inline float FusionAltitudeInfinity(void) {
    const uint32_t bits = 0x7F800000u;
    float value;
    memcpy(&value, &bits, sizeof(value));
    return value;
}

/**
 * @return the default (VTOL multirotor) settings: Kh = 2.40 1/s, Kv = 2.88 1/s^2,
 * Kb = 0.675 1/s^3, gap period FUSION_ALTITUDE_DEFAULT_GAP_PERIOD (0.5 s),
 * baro timeout FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT (2 s).
 */
static inline FusionAltitudeSettings FusionAltitudeSettingsDefault(void) {
    const FusionAltitudeSettings settings = {2.40f, 2.88f, 0.675f, FUSION_ALTITUDE_DEFAULT_GAP_PERIOD,
                                             FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT};
    return settings;
}

/**
 * @brief Checks the settings without a sample period: each gain finite and
 * >= 0, and the continuous-time observer stable. Routh-Hurwitz on
 * s^3 + Kh*s^2 + Kv*s + Kb: Kh*Kv > Kb when Kb > 0; with Kb = 0 (no bias
 * estimation) the remaining s^2 + Kh*s + Kv needs Kh > 0 when Kv > 0.
 * Kh = Kv = Kb = 0 (pure inertial integration) is accepted. The gap period
 * must be > 0 (+infinity turns gap detection off); it is checked after the
 * gains, and the baro timeout (> 0, +infinity: never) after it.
 */
static inline FusionAltitudeStatus FusionAltitudeSettingsCheck(const FusionAltitudeSettings *const settings) {
    FUSION_ALTITUDE_NO_CONTRACT
    const float kh = settings->positionGain;
    const float kv = settings->velocityGain;
    const float kb = settings->biasGain;
    if (!FusionAltitudeIsFinite(kh) || !FusionAltitudeIsFinite(kv) || !FusionAltitudeIsFinite(kb) ||
        (kh < 0.0f) || (kv < 0.0f) || (kb < 0.0f) || (kh > FUSION_ALTITUDE_MAXIMUM_GAIN) ||
        (kv > FUSION_ALTITUDE_MAXIMUM_GAIN) || (kb > FUSION_ALTITUDE_MAXIMUM_GAIN)) {
        return FusionAltitudeStatusInvalidGain;
    }
    if (kb > 0.0f) {
        if (!(kh * kv > kb)) {
            return FusionAltitudeStatusUnstableGains;
        }
    } else if ((kv > 0.0f) && !(kh > 0.0f)) {
        return FusionAltitudeStatusUnstableGains;
    }
    if (!(settings->gapPeriod > 0.0f)) { /* false for NaN */
        return FusionAltitudeStatusInvalidGapPeriod;
    }
    if (!(settings->baroTimeout > 0.0f)) { /* false for NaN */
        return FusionAltitudeStatusInvalidBaroTimeout;
    }
    return FusionAltitudeStatusOk;
}

/** @internal
 * @brief Jury's test of the semi-implicit update with gains Kh, Kv, Kb
 * (1/s, 1/s^2, 1/s^3, already checked) at step dt (s, > 0): true if every
 * discrete eigenvalue is inside the unit circle. See
 * FusionAltitudeSettingsValidate for the polynomial and the conditions.
 */
static inline bool FusionAltitudeIsDiscreteStable(const float kh, const float kv, const float kb, const float dt) {
    FUSION_ALTITUDE_NO_CONTRACT
    const float p = kh * dt;
    const float q = kv * dt * dt;
    const float s = kb * dt * dt * dt;
    if (!FusionAltitudeIsFinite(p) || !FusionAltitudeIsFinite(q) || !FusionAltitudeIsFinite(s)) {
        return false;
    }
    if (kb > 0.0f) {
        const float lhs = p * (2.0f - p);
        const float rhs = p * (p + q - 2.0f) - s;
        return (s > 0.0f) && ((8.0f - 4.0f * p - 2.0f * q + s) > 0.0f) && (p > 0.0f) && (p < 2.0f) && (lhs > rhs) &&
               (lhs > -rhs);
    }
    if (kv > 0.0f) {
        return (p > 0.0f) && (p < 2.0f) && (q > 0.0f) && (q < 4.0f - 2.0f * p);
    }
    return p < 2.0f;
}

/**
 * @brief The stability limit of the gap rule: true if the gains of settings
 * (checked) can integrate a baro step of dt s that ends a baro interval of
 * interval s (the time since the previous baro sample, this step included;
 * interval >= dt > 0). Over one baro interval D the update integrates for D
 * and corrects once with dt; to first order its characteristic polynomial is
 * that of FusionAltitudeSettingsValidate with p = Kh*dt, q = Kv*dt*D and
 * s = Kb*dt*D^2 (exact when D = dt: a baro sample every step). With the
 * margin, T = FUSION_ALTITUDE_STABILITY_MARGIN * dt and
 * TD = FUSION_ALTITUDE_STABILITY_MARGIN * D, p = Kh*T, q = Kv*T*TD,
 * s = Kb*T*TD^2 must pass
 *   Kb > 0:  p < 2,  8 - 4p - 2q + s > 0  and  p(p + q - 2) - s <= p(2 - p)
 *   Kb = 0, Kv > 0:  p < 2  and  q < 4 - 2p
 *   Kv = Kb = 0:  p < 2
 * These are the conditions of Jury's test that bound the step from above
 * (the first two: an eigenvalue leaves the unit circle at z = -1, the
 * oscillating divergence the telemetry log showed), with equality counted as
 * stable. Left out: the positivity ones (s > 0, p > 0, q > 0), which hold for
 * every step and fail only by float32 underflow at a tiny dt, and
 * p(2 - p) > s - p(p + q - 2), which is p*q > s: Kh*Kv*dt > Kb*D, Routh-Hurwitz
 * when D = dt. It fails when gains not scaled to a sparse baro (a baro sample
 * on fewer than one step in Kh*Kv/Kb, about 10 for the presets) correct
 * rarely: a slow divergence (|z| = 1.03 per baro interval for the default
 * gains with a baro every 50th step) that a restart at every baro sample
 * would not help; scale the gains to the baro rate instead
 * (tuning.settings_for_baro_rate, which run and fit do). With a baro sample every step the limit is where
 * 8 - 4p - 2q + s = 0 (an eigenvalue at z = -1): default gains dt < 0.413 s
 * (Jury's limit 0.620 s), racing 0.124 s, fixed wing 1.24 s, balloon 3.10 s,
 * rocket 0.694 s. With gains scaled to the baro rate (Kh*N etc. for a baro
 * on one step in N, tuning.settings_for_baro_rate) p, q, s are those of the
 * observer sampled at the baro period. With the baro timeout off (+infinity,
 * as the rocket estimator runs it: it locks the baro out on purpose and
 * re-admits it gently itself) FusionAltitudeUpdate passes interval = dt: the
 * first sample after a 45 s lockout would otherwise be a gap (q grows with D).
 * With a finite timeout D never exceeds it by more than dt (a timed-out step
 * is not checked).
 */
static inline bool FusionAltitudeIsStepStable(const FusionAltitudeSettings *const settings, const float dt, const float interval) {
    FUSION_ALTITUDE_NO_CONTRACT
    const float t = FUSION_ALTITUDE_STABILITY_MARGIN * dt;
    const float tInterval = FUSION_ALTITUDE_STABILITY_MARGIN * interval;
    const float p = settings->positionGain * t;
    const float q = settings->velocityGain * t * tInterval;
    const float s = settings->biasGain * t * tInterval * tInterval;
    if (!FusionAltitudeIsFinite(p) || !FusionAltitudeIsFinite(q) || !FusionAltitudeIsFinite(s) || !(p < 2.0f)) {
        return false;
    }
    if (settings->biasGain > 0.0f) {
        return ((8.0f - 4.0f * p - 2.0f * q + s) > 0.0f) && !((p * (p + q - 2.0f) - s) > (p * (2.0f - p)));
    }
    if (settings->velocityGain > 0.0f) {
        return q < 4.0f - 2.0f * p;
    }
    return true;
}

/**
 * @brief Checks the gains (FusionAltitudeSettingsCheck) and that the
 * semi-implicit update is stable at sample period dt (s).
 *
 * With p = Kh*dt, q = Kv*dt^2, s = Kb*dt^3 the homogeneous update of
 * (h, v*dt, b*dt^2) is the matrix [[1-p-q, 1, -1], [-q, 1, -1], [s, 0, 1]],
 * whose characteristic polynomial is
 *   z^3 + (p+q-3) z^2 + (3-2p-q+s) z + (p-1).
 * Jury's test for it reduces to: s > 0, 8 - 4p - 2q + s > 0, 0 < p < 2 and
 * p(2-p) > |p(p+q-2) - s|. With Kb = 0 the bias mode is the eigenvalue 1 and
 * the rest is z^2 + (p+q-2) z + (1-p): Kv > 0 needs 0 < p < 2 and q < 4 - 2p;
 * Kv = 0 leaves z = 1-p: p < 2.
 */
static inline FusionAltitudeStatus FusionAltitudeSettingsValidate(const FusionAltitudeSettings *const settings, const float dt) {
    FUSION_ALTITUDE_NO_CONTRACT
    const FusionAltitudeStatus status = FusionAltitudeSettingsCheck(settings);
    if (status != FusionAltitudeStatusOk) {
        return status;
    }
    if (!FusionAltitudeIsFinite(dt) || !(dt > 0.0f)) {
        return FusionAltitudeStatusInvalidDt;
    }
    const bool stable = FusionAltitudeIsDiscreteStable(settings->positionGain, settings->velocityGain, settings->biasGain, dt);
    return stable ? FusionAltitudeStatusOk : FusionAltitudeStatusUnstableDiscrete;
}

/**
 * @brief Gains from a position-loop bandwidth omega (rad/s), damping ratio zeta
 * and bias-loop bandwidth omegaBias (rad/s), in float32 in this order:
 *   Kh = 2*zeta*omega + omegaBias          (1/s)
 *   Kv = omega*omega + 2*zeta*omega*omegaBias  (1/s^2)
 *   Kb = omega*omega*omegaBias             (1/s^3)
 * Typical: zeta = 0.7, omegaBias = omega / 5. The gap period and the baro
 * timeout are set to FUSION_ALTITUDE_DEFAULT_GAP_PERIOD and
 * FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT (assign them afterwards to change them;
 * *settings is not read). The result is checked with
 * FusionAltitudeSettingsCheck; *settings is written only on success.
 */
static inline FusionAltitudeStatus FusionAltitudeSettingsFromBandwidth(FusionAltitudeSettings *const settings, const float omega,
                                                                       const float zeta, const float omegaBias) {
    FUSION_ALTITUDE_NO_CONTRACT
    if (!FusionAltitudeIsFinite(omega) || !FusionAltitudeIsFinite(zeta) || !FusionAltitudeIsFinite(omegaBias) ||
        !(omega > 0.0f) || !(zeta > 0.0f) || (omegaBias < 0.0f)) {
        return FusionAltitudeStatusInvalidBandwidth;
    }
    const float twoZetaOmega = 2.0f * zeta * omega;
    const float omegaSquared = omega * omega;
    FusionAltitudeSettings result;
    result.positionGain = twoZetaOmega + omegaBias;
    result.velocityGain = omegaSquared + twoZetaOmega * omegaBias;
    result.biasGain = omegaSquared * omegaBias;
    result.gapPeriod = FUSION_ALTITUDE_DEFAULT_GAP_PERIOD;
    result.baroTimeout = FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT;
    const FusionAltitudeStatus status = FusionAltitudeSettingsCheck(&result);
    if (status != FusionAltitudeStatusOk) {
        return (status == FusionAltitudeStatusInvalidGain) ? FusionAltitudeStatusInvalidBandwidth : status;
    }
    *settings = result;
    return FusionAltitudeStatusOk;
}

/** @internal
 * @return the settings of a preset: gains Kh (1/s), Kv (1/s^2) and
 * Kb (1/s^3), gap period (s) and baro timeout (s). The presets' numbers stay in
 * code (immediates), not in a table that a small AVR would copy into its RAM.
 */
static inline FusionAltitudeSettings FusionAltitudePresetSettings(const float positionGain, const float velocityGain, const float biasGain,
                                                                  const float gapPeriod, const float baroTimeout) {
    FusionAltitudeSettings settings;
    settings.positionGain = positionGain;
    settings.velocityGain = velocityGain;
    settings.biasGain = biasGain;
    settings.gapPeriod = gapPeriod;
    settings.baroTimeout = baroTimeout;
    return settings;
}

/**
 * @brief Preset gains: the bandwidth formulas with zeta = 0.7 and
 * omega_b = omega / 5, evaluated exactly and rounded to float32 (so the VTOL
 * preset equals the defaults). Kh 1/s, Kv 1/s^2, Kb 1/s^3:
 *   balloon    omega 0.2: 0.32, 0.0512, 0.0016
 *   fixed wing omega 0.5: 0.80, 0.32,   0.025
 *   VTOL       omega 1.5: 2.40, 2.88,   0.675
 *   racing     omega 5.0: 8.00, 32.0,   25.0
 *   rocket     omega 1.0, omega_b = 0: 1.40, 1.00, 0 (static-port and
 *              transonic baro errors would leak into a learned bias: set it
 *              from a pad calibration, as fusion_altitude_rocket.h does)
 * Gap period: 5 s for the balloon (1 Hz baro logs; its gains pass Jury's
 * test up to 6 s), FUSION_ALTITUDE_DEFAULT_GAP_PERIOD for the others. Baro
 * timeout: 10 s for the balloon (10 periods of a 1 Hz baro),
 * FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT for the others.
 * *settings is written only on success.
 */
static inline FusionAltitudeStatus FusionAltitudeSettingsFromPreset(FusionAltitudeSettings *const settings, const FusionAltitudePreset preset) {
    FusionAltitudeSettings result;
    switch (preset) {
        case FusionAltitudePresetBalloon:
            result = FusionAltitudePresetSettings(0.32f, 0.0512f, 0.0016f, 5.0f, 10.0f);
            break;
        case FusionAltitudePresetFixedWing:
            result = FusionAltitudePresetSettings(0.80f, 0.32f, 0.025f, FUSION_ALTITUDE_DEFAULT_GAP_PERIOD, FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT);
            break;
        case FusionAltitudePresetVtol:
            result = FusionAltitudeSettingsDefault();
            break;
        case FusionAltitudePresetRacing:
            result = FusionAltitudePresetSettings(8.0f, 32.0f, 25.0f, FUSION_ALTITUDE_DEFAULT_GAP_PERIOD, FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT);
            break;
        case FusionAltitudePresetRocket:
            result = FusionAltitudePresetSettings(1.4f, 1.0f, 0.0f, FUSION_ALTITUDE_DEFAULT_GAP_PERIOD, FUSION_ALTITUDE_DEFAULT_BARO_TIMEOUT);
            break;
        default:
            return FusionAltitudeStatusInvalidPreset;
    }
    *settings = result;
    return FusionAltitudeStatusOk;
}

//------------------------------------------------------------------------------
// Estimator

/**
 * @brief Initialises the estimator with the default settings. The reference is
 * not set: the first update with a baro sample auto-zeroes on it.
 */
static inline void FusionAltitudeInitialise(FusionAltitude *const altitude) {
    altitude->settings = FusionAltitudeSettingsDefault();
    altitude->altitude = 0.0f;
    altitude->verticalVelocity = 0.0f;
    altitude->accelBias = 0.0f;
    altitude->baroResidual = 0.0f;
    altitude->gapTime = 0.0f;
    altitude->sinceRestart = -1.0f;
    altitude->sinceBaro = 0.0f;
    altitude->gapCount = 0u;
    altitude->baroTimeouts = 0u;
    altitude->referenceSet = false;
    altitude->baroTimedOut = false;
}

/**
 * @brief Replaces the gains, keeping the state. Rejected (state unchanged) if
 * FusionAltitudeSettingsCheck fails.
 */
static inline FusionAltitudeStatus FusionAltitudeSetSettings(FusionAltitude *const altitude, const FusionAltitudeSettings *const settings) {
    const FusionAltitudeStatus status = FusionAltitudeSettingsCheck(settings);
    if (status == FusionAltitudeStatusOk) {
        altitude->settings = *settings;
    }
    return status;
}

/**
 * @brief Sets the reference: altitude = baroAltitude (m), vertical velocity 0,
 * residual 0; a pending restart after a gap, a bias hold and a baro timeout
 * are cancelled. The accel bias estimate and the gap and timeout counts are
 * kept. Rejected if baroAltitude is not finite.
 */
static inline FusionAltitudeStatus FusionAltitudeReset(FusionAltitude *const altitude, const float baroAltitude) {
    if (!FusionAltitudeIsFinite(baroAltitude)) {
        return FusionAltitudeStatusInvalidBaroAltitude;
    }
    altitude->altitude = baroAltitude;
    altitude->verticalVelocity = 0.0f;
    altitude->baroResidual = 0.0f;
    altitude->gapTime = 0.0f;
    altitude->sinceRestart = -1.0f;
    altitude->sinceBaro = 0.0f;
    altitude->referenceSet = true;
    altitude->baroTimedOut = false;
    return FusionAltitudeStatusOk;
}

/** @internal
 * @brief The first baro sample z (m) after initialisation or after a
 * gap sets the reference: h = z, residual 0. After initialisation v = 0 (as
 * FusionAltitudeReset); after a gap v = (z - h)/gapTime, the mean vertical
 * velocity over the gap (h is the last altitude before it, gapTime the time
 * since, s; 0 if that overflows), and the bias hold starts (sinceRestart = 0).
 * The bias is kept.
 */
static inline void FusionAltitudeRestart(FusionAltitude *const altitude, const float baroAltitude) {
    FUSION_ALTITUDE_NO_CONTRACT
    float velocity = 0.0f;
    if (altitude->gapTime > 0.0f) {
        altitude->sinceRestart = 0.0f;
        velocity = (baroAltitude - altitude->altitude) / altitude->gapTime;
        velocity = FusionAltitudeIsFinite(velocity) ? velocity : 0.0f; /* overflow: a gap of a few ulps */
    }
    altitude->verticalVelocity = velocity;
    altitude->altitude = baroAltitude;
    altitude->baroResidual = 0.0f;
    altitude->gapTime = 0.0f;
    altitude->referenceSet = true;
    altitude->baroTimedOut = false;
}

/**
 * @brief Warm start: FusionAltitudeReset and accel bias = accelBias (m/s^2,
 * +up), e.g. from a stationary ground calibration. Rejected, state unchanged,
 * if either argument is not finite.
 */
static inline FusionAltitudeStatus FusionAltitudeResetWithBias(FusionAltitude *const altitude, const float baroAltitude, const float accelBias) {
    if (!FusionAltitudeIsFinite(baroAltitude)) {
        return FusionAltitudeStatusInvalidBaroAltitude;
    }
    if (!FusionAltitudeIsFinite(accelBias)) {
        return FusionAltitudeStatusInvalidAccelBias;
    }
    altitude->accelBias = accelBias;
    return FusionAltitudeReset(altitude, baroAltitude);
}

/**
 * @brief The input rules of FusionAltitudeUpdate, on their own: accel (m/s^2)
 * finite; baroAltitude (m) finite or NaN (no sample); dt (s) finite and > 0.
 * @return the status FusionAltitudeUpdate would return for these inputs.
 */
static inline FusionAltitudeStatus FusionAltitudeCheckInputs(const float accel, const float baroAltitude, const float dt) {
    if (!FusionAltitudeIsFinite(accel)) {
        return FusionAltitudeStatusInvalidAccel;
    }
    if ((FusionAltitudeFloatBits(baroAltitude) & 0x7FFFFFFFu) == 0x7F800000u) { /* +-infinity; NaN means no sample */
        return FusionAltitudeStatusInvalidBaroAltitude;
    }
    if (!FusionAltitudeIsFinite(dt) || !(dt > 0.0f)) {
        return FusionAltitudeStatusInvalidDt;
    }
    return FusionAltitudeStatusOk;
}

/** @internal
 * @brief The restart of a gap by the stability rule, at the baro
 * sample z (m) of a step of dt s that ends a baro interval of D = interval s.
 * h (m) is the estimate before the step: it moved with v over the D - dt s of
 * the interval before this step and not over this one, so the mean velocity
 * since the previous baro sample is vMean = ((z - h) + v*(D - dt))/D. The
 * velocity moves toward it by the weight D/(D + Kh/Kv):
 *   v += (vMean - v) * D/(D + Kh/Kv);  h = z;  r = 0
 * Kh/Kv (s) is the time over which the velocity loop trusts its velocity
 * against the baro (0.83 s for the presets' ratio): a short interval keeps
 * mostly v (a mean over it would be baro noise / D: 1 m/s for 0.15 m of noise
 * over 0.16 s), a long one takes mostly vMean (v is stale after a run of such
 * steps). Kv = 0 keeps v; vMean or the weight not finite keeps v.
 */
static inline void FusionAltitudeStabilityRestart(float *const h, float *const v, float *const r, const float kh, const float kv,
                                                  const float z, const float dt, const float interval) {
    FUSION_ALTITUDE_NO_CONTRACT
    if (kv > 0.0f) {
        const float mean = ((z - *h) + *v * (interval - dt)) / interval;
        const float weight = interval / (interval + kh / kv);
        const float velocity = *v + (mean - *v) * weight;
        *v = FusionAltitudeIsFinite(velocity) ? velocity : *v;
    }
    *h = z;
    *r = 0.0f;
}

/** @internal
 * @brief The timing part of FusionAltitudeUpdate (inputs checked),
 * before the state update. A gap (dt > gapPeriod) releases the reference; a
 * stability gap (unstable: a baro step the gains cannot integrate stably) is
 * counted and starts the bias hold (FusionAltitudeUpdate restarts h at this
 * step's sample); a pending restart adds dt to gapTime; after a restart dt is
 * added to sinceRestart.
 * Then the baro timeout: a baro sample sets sinceBaro = 0; once the reference
 * was set (or a restart is pending), a step without one adds dt to it, and
 * going above baroTimeout counts a timeout and sets baroTimedOut.
 */
static inline void FusionAltitudeTiming(FusionAltitude *const altitude, const float dt, const bool baroSample, const bool unstable) {
    FUSION_ALTITUDE_NO_CONTRACT
    if (altitude->referenceSet && (dt > altitude->settings.gapPeriod)) { /* a gap: restart from the next baro sample */
        altitude->gapCount++;
        altitude->referenceSet = false;
        altitude->gapTime = dt;
    } else if (altitude->referenceSet && unstable) { /* a stability gap: restart at this step's baro sample */
        altitude->gapCount++;
        altitude->sinceRestart = 0.0f;
    } else if (!altitude->referenceSet && (altitude->gapTime > 0.0f)) { /* still waiting for the baro after a gap */
        altitude->gapTime += dt;
    } else if (altitude->referenceSet && (altitude->sinceRestart >= 0.0f)) { /* time since the restart */
        altitude->sinceRestart += dt;
    }
    if (baroSample) {
        altitude->sinceBaro = 0.0f;
    } else if (altitude->referenceSet || (altitude->gapTime > 0.0f)) {
        altitude->sinceBaro += dt;
        if (!altitude->baroTimedOut && (altitude->sinceBaro > altitude->settings.baroTimeout)) {
            altitude->baroTimeouts++;
            altitude->baroTimedOut = true;
        }
    }
}

/**
 * @brief One step of the observer (semi-implicit Euler).
 *
 * @param accel vertical acceleration a, m/s^2, earth frame, +up, gravity removed.
 * @param baroAltitude barometric altitude z, m; NaN (FUSION_ALTITUDE_NO_BARO)
 *        when no baro sample arrived this step.
 * @param dt time since the previous step, s.
 *
 * With a baro sample, r = z - h and
 *   v += ((a - b) + Kv*r) * dt
 *   h += (v + Kh*r) * dt        (the new v)
 *   b -= (Kb*r) * dt
 * Without one (z NaN) it integrates only: v += (a - b)*dt; h += v*dt; b is
 * kept and the stored residual is the quiet NaN 0x7FC00000.
 *
 * Until the reference is set, a baro sample only sets it (h = z, v = 0,
 * residual 0, as FusionAltitudeReset; a and dt unused) and a step without baro
 * changes nothing but the residual (NaN).
 *
 * Gaps: once the reference is set, an update is a gap (a logging gap, a
 * brown-out, a scheduler stall) and is not integrated when dt > gapPeriod, or
 * when it carries a baro sample and the gains cannot integrate it stably:
 * FusionAltitudeIsStepStable(settings, dt, D) false, D = sinceBaro + dt the
 * baro interval it ends (not when timed out: the timeout's restart applies), i.e. Jury's test fails at FUSION_ALTITUDE_STABILITY_MARGIN
 * times the step (default gains with a baro every step: dt > 0.413 s). One
 * accel sample says nothing about the motion over a gap, and a correction the
 * gains cannot integrate stably grows the error at every such step (a
 * telemetry log of 0.5-1 s steps ran the default gains to infinity). The gap
 * count goes up. A gap by the stability rule restarts at once
 * (FusionAltitudeStabilityRestart): h = z, v moves toward the mean velocity
 * over the baro interval D by D/(D + Kh/Kv), residual 0, and the bias hold
 * below starts. A gap by dt > gapPeriod releases the
 * reference (FusionAltitudeIsReferenceSet is false): the bias b is held, h
 * and v are frozen, and the next baro sample, this step's if it has one,
 * restarts h = z and v = (z - h_before)/T, the mean velocity over the T s
 * since h_before was last updated (the gap and any steps without baro after
 * it), with residual 0. The mean velocity is used rather than the
 * held or a zero velocity because it is the only one the data support after
 * a gap in motion, and the velocity loop removes its error (at most the
 * velocity change over half the gap) within a few 1/omega. Meanwhile the
 * bias is held: after the restart every update adds its dt to sinceRestart,
 * and the bias correction is skipped while sinceRestart*Kh < 8 (see
 * FUSION_ALTITUDE_BIAS_HOLD), so that error does not leak into b.
 *
 * Baro timeout: once the reference is set, every step without a baro sample
 * adds its dt to sinceBaro (a baro sample sets it to 0). When sinceBaro goes
 * above baroTimeout the timeout count goes up and the observer is timed out
 * (FusionAltitudeIsBaroTimedOut: the output is not baro-aided) until the next
 * baro sample. Timed out, it no longer integrates the acceleration: the bias
 * is held and the velocity decays to 0 with time constant T = baroTimeout,
 *   v *= T/(T + dt);  h += v*dt
 * (first order, stable at every dt), so h moves at most |v|*T further and
 * stays finite however long the baro is missing, instead of dead-reckoning
 * an accel error into an altitude error growing with the square of time.
 * Decay, not hold: a held velocity would still move h without bound, and
 * with no height source the best guess of a vehicle's vertical velocity over
 * a long outage is 0. The next baro sample restarts cleanly: h = z, v is
 * kept (the decayed velocity), residual 0 and the bias is held for 8/Kh s as
 * after a gap. A gap pending while timed out stays a gap (h and v frozen;
 * its restart as above).
 *
 * Every call checks all inputs first: non-finite accel, infinite
 * baroAltitude, or dt not finite or <= 0 is rejected with the state unchanged.
 */
static inline FusionAltitudeStatus FusionAltitudeUpdate(FusionAltitude *const altitude, const float accel, const float baroAltitude,
                                                        const float dt) {
    FUSION_ALTITUDE_NO_CONTRACT
    const FusionAltitudeStatus status = FusionAltitudeCheckInputs(accel, baroAltitude, dt);
    if (status != FusionAltitudeStatusOk) {
        return status;
    }
    const bool baroSample = FusionAltitudeIsFinite(baroAltitude);
    /* D: the baro interval this step ends, s (dt alone with the timeout off: see FusionAltitudeIsStepStable) */
    const float interval = FusionAltitudeIsFinite(altitude->settings.baroTimeout) ? (altitude->sinceBaro + dt) : dt;
    const bool unstable = baroSample && altitude->referenceSet && !altitude->baroTimedOut &&
                          !FusionAltitudeIsStepStable(&altitude->settings, dt, interval);
    FusionAltitudeTiming(altitude, dt, baroSample, unstable);
    if (!baroSample) { /* NaN, as the inputs are checked: no baro sample this step */
        if (altitude->referenceSet) {
            if (altitude->baroTimedOut) { /* no dead reckoning beyond the timeout: v decays to 0 */
                const float timeout = altitude->settings.baroTimeout;
                altitude->verticalVelocity *= timeout / (timeout + dt);
            } else {
                altitude->verticalVelocity += (accel - altitude->accelBias) * dt;
            }
            altitude->altitude += altitude->verticalVelocity * dt;
        }
        altitude->baroResidual = FusionAltitudeNaN();
        return FusionAltitudeStatusOk;
    }
    if (!altitude->referenceSet) {
        FusionAltitudeRestart(altitude, baroAltitude);
        return FusionAltitudeStatusOk;
    }
    if (unstable) { /* a stability gap: restart at this sample (the bias hold started in the timing) */
        FusionAltitudeStabilityRestart(&altitude->altitude, &altitude->verticalVelocity, &altitude->baroResidual,
                                       altitude->settings.positionGain, altitude->settings.velocityGain, baroAltitude, dt,
                                       interval);
        return FusionAltitudeStatusOk;
    }
    if (altitude->baroTimedOut) { /* the first baro sample after a timeout: restart at it, v kept */
        altitude->altitude = baroAltitude;
        altitude->baroResidual = 0.0f;
        altitude->sinceRestart = 0.0f;
        altitude->baroTimedOut = false;
        return FusionAltitudeStatusOk;
    }
    const float residual = baroAltitude - altitude->altitude;
    altitude->verticalVelocity += ((accel - altitude->accelBias) + altitude->settings.velocityGain * residual) * dt;
    altitude->altitude += (altitude->verticalVelocity + altitude->settings.positionGain * residual) * dt;
    if (!((altitude->sinceRestart >= 0.0f) && (altitude->sinceRestart * altitude->settings.positionGain < FUSION_ALTITUDE_BIAS_HOLD))) {
        altitude->accelBias -= (altitude->settings.biasGain * residual) * dt;
    }
    altitude->baroResidual = residual;
    return FusionAltitudeStatusOk;
}

/** @return the gains in use. */
static inline FusionAltitudeSettings FusionAltitudeGetSettings(const FusionAltitude *const altitude) {
    return altitude->settings;
}

/** @return altitude estimate h, m (0 until the reference is set). */
static inline float FusionAltitudeGetAltitude(const FusionAltitude *const altitude) {
    return altitude->altitude;
}

/** @return vertical velocity estimate v, m/s, +up. */
static inline float FusionAltitudeGetVerticalVelocity(const FusionAltitude *const altitude) {
    return altitude->verticalVelocity;
}

/** @return accelerometer bias estimate b, m/s^2, +up (already subtracted from the accel input). */
static inline float FusionAltitudeGetAccelBias(const FusionAltitude *const altitude) {
    return altitude->accelBias;
}

/**
 * @return baro residual r = z - h of the latest update, m, before that update's
 * correction: 0 after initialise and reset, NaN after a step without baro.
 * A sustained large residual points at a stuck baro, prop-wash or divergence.
 */
static inline float FusionAltitudeGetBaroResidual(const FusionAltitude *const altitude) {
    return altitude->baroResidual;
}

/** @return the number of gaps so far: updates with dt > gapPeriod, or baro steps the gains cannot integrate stably, once the reference was set. */
static inline uint32_t FusionAltitudeGetGapCount(const FusionAltitude *const altitude) {
    return altitude->gapCount;
}

/** @return the number of baro timeouts so far: times the time since the latest baro sample went above baroTimeout. */
static inline uint32_t FusionAltitudeGetBaroTimeouts(const FusionAltitude *const altitude) {
    return altitude->baroTimeouts;
}

/** @return true from a baro timeout to the next baro sample: the output is not baro-aided (v decays, a is not integrated). */
static inline bool FusionAltitudeIsBaroTimedOut(const FusionAltitude *const altitude) {
    return altitude->baroTimedOut;
}

/** @return true once the reference is set (first baro sample or reset); false again from a gap to the next baro sample. */
static inline bool FusionAltitudeIsReferenceSet(const FusionAltitude *const altitude) {
    return altitude->referenceSet;
}

#undef FUSION_ALTITUDE_NO_CONTRACT

#ifdef FUSION_ALTITUDE_GCC_NO_CONTRACT
#pragma GCC pop_options
#undef FUSION_ALTITUDE_GCC_NO_CONTRACT
#endif

#ifdef __cplusplus
}
#endif

#endif
