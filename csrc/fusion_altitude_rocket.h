/**
 * @file fusion_altitude_rocket.h
 * @brief Rocket flight computer layer around the altitude observer of
 * fusion_altitude.h: pad calibration, a barometer gate (dynamic-pressure
 * lockout, ejection-spike rejection, gentle re-admission) and the flight
 * phase state machine pad -> boost -> coast -> (apogee) drogue -> main ->
 * landed, with the time and height of each event.
 *
 * Header-only C99 (also valid C++), float32 only, no malloc, no globals, no
 * libm. It uses the observer through its public API, except that a restart
 * after a gap (and a baro launch over one) writes the observer's velocity
 * (and height) fields directly; it includes fusion_altitude.h: copy both files.
 *
 * Units and frame: height m above the pad (+up), vertical velocity m/s (+up),
 * acceleration m/s^2, time s. Inputs at every step:
 *   accel        m/s^2, gravity removed, +up: on a rocket without an INS the
 *                accelerometer axis along the airframe (long axis, nose up)
 *                minus g, taken as vertical until apogee (the cosine error of
 *                a tilted flight is not corrected; see docs/rocket.md). With an
 *                INS, its earth-frame vertical acceleration (see
 *                FusionAltitudeRocketUpdateWithVerticalAccel). NaN: no
 *                accelerometer sample (a baro-only log, a dead or saturated
 *                accelerometer, one that ended): in flight the layer is
 *                baro-led from then on (below).
 *   baroAltitude m, pressure altitude (any datum; the pad is learned), or
 *                FUSION_ALTITUDE_NO_BARO when no sample arrived this step.
 *   dt           s since the previous step.
 *
 * Pad calibration. On the pad, samples are grouped into windows of
 * calibrationWindow s. A window is stationary when every accel sample in it
 * stays within stationaryAccel of the window's first one (and no gap falls in
 * it). Each completed stationary window's mean accel and mean baro altitude
 * are blended into the calibration (running mean of the windows, the newest
 * weighted at least 1/8):
 *   accelBias   += (windowMeanAccel - accelBias) * w,   w = 1/min(n, 8)
 *   padAltitude += (windowMeanBaro  - padAltitude) * w
 * A window that holds any non-stationary sample is discarded, so the launch
 * transient (and anything that shook the rocket) never enters the bias or the
 * pad altitude. Launch is declared when accel - accelBias > launchAccel for
 * launchTime s in a row; its time and height are those of the first sample of
 * that run, and the motion from that sample on is integrated (no baro).
 * Launch is also declared from the baro, when two pad samples in a row are
 * more than baroLaunchHeight m above the pad and rising (the accelerometer
 * showed none: dead, missing, wrong axis): the flight is then baro-led.
 *
 * Baro-led flight (no usable accelerometer: a baro launch, a NaN accel in
 * flight, or a gap in boost or in the lockout, after which the integrated
 * velocity cannot be trusted): the observer is fed its bias (no net
 * acceleration), bias - g in coast (ballistic), boost ends at once (no burnout
 * event), every baro sample that is not a spike is fused whatever the speed,
 * and apogee needs, besides v < -apogeeMargin, a fused sample below the baro's
 * peak and no new peak for FUSION_ALTITUDE_ROCKET_PEAK_AGE s.
 *
 * Baro gate (after launch). Each baro sample is, in this order:
 *   - a spike when |z - (zLast + v * age)| > spikeThreshold + g * age^2 / 2, where zLast is
 *     the last sample not rejected as a spike, age the time since it and v
 *     the velocity estimate; rejected (not fused) unless the rejections have
 *     already lasted spikeTime s, in which case the new level is accepted.
 *     Ejection charges and the transonic shock give spikes of tens to hundreds
 *     of metres lasting a few samples.
 *   - locked out in boost and while |v| > min(lockoutSpeed, FUSION_ALTITUDE_ROCKET_MACH_LOCKOUT):
 *     the static port reads low by roughly k * dynamic pressure, worst
 *     through Mach 1, so the estimator coasts on the accelerometer and the
 *     pad-learned bias;
 *   - otherwise fused. The observer keeps the height it integrated through
 *     the lockout: on re-admission (the first fused sample after a locked-out
 *     one) the disagreement o = z - h is stored as the baro offset and the
 *     observer fuses z - o, so the baro corrects the velocity drift without a
 *     step. The output height is h + oApplied, where oApplied moves towards o
 *     before apogee up by at most offsetRate * |v| * dt per step and down by
 *     at most offsetRate times the observer's own rise in that step (nothing
 *     when h did not rise), so that while climbing the reported height never
 *     falls by absorbing the offset: it rises by at least (1 - offsetRate)
 *     of h's rise. After apogee oApplied moves to o by at most
 *     (offsetRate * (|v| + landedSpeed) + FUSION_ALTITUDE_ROCKET_OFFSET_DECAY * |o - oApplied|) * dt
 *     per step: the height blends into the baro without a step, and the
 *     apogee event reports the baro-corrected height h + o (not h + oApplied):
 *     the reported apogee agrees with the baro, the trace gets there smoothly.
 *     The velocity estimate used for apogee is never dragged by the height
 *     correction. A baro step that outlasts spikeTime is re-admitted the same
 *     way; after a gap see below.
 *
 * Phases and events (the observer's velocity v and height h after the step):
 *   pad -> boost     launch   (above)
 *   boost -> coast   burnout  accel - accelBias < burnoutAccel for burnoutTime s
 *                             (time and height of the first sample of that run)
 *   (boost, coast)   max speed: the step with the largest v so far
 *   coast -> drogue  apogee   v < -apogeeMargin (v crossing zero, past its noise:
 *                             1 m/s = 0.1 s late), never in boost (before
 *                             burnout) and never while the lockout is active;
 *                             or when the baro has stayed more than
 *                             spikeThreshold below its peak for
 *                             FUSION_ALTITUDE_ROCKET_CONTRADICTION_TIME s
 *                             (..._LOCKOUT_TIME in the lockout): height = that peak
 *   drogue -> main   main     h + o <= mainAltitude (the baro-corrected height)
 *   drogue/main -> landed     |v| < landedSpeed for landedTime s in a row
 * After apogee the accelerometer is not vertical (tumbling, under a
 * parachute): without an INS the accel input is ignored (the observer is fed
 * its own bias, so a - b = 0) and the descent is baro-led with the bias frozen
 * (bias gain 0). FusionAltitudeRocketUpdateWithVerticalAccel marks the accel
 * as a trusted earth-frame vertical acceleration (an INS): it is then used in
 * every phase, still with the bias frozen after apogee.
 *
 * Gaps: an update with dt > gapPeriod is counted (gapCount). On the pad it
 * discards the calibration window and any launch candidate. In flight the
 * step is extrapolated (no baro) in equal sub-steps of at most gapPeriod (a
 * power of two, up to 4096: 2048 s at the default gapPeriod), so the observer
 * itself never sees a step longer than gapPeriod: on this step's accel input
 * held over gaps up to FUSION_ALTITUDE_ROCKET_GAP_HOLD s after boost (bias - g
 * in a baro-led coast, stopping at v = 0), at constant velocity in boost and
 * over longer gaps. After a held gap the next baro sample is re-admitted
 * through the offset (the extrapolation's height error must not drag the
 * velocity into an early apogee; the held deceleration already turned the
 * velocity); after a longer or baro-led gap it restarts the velocity as
 * the baro's mean velocity since its previous sample and re-bases the height
 * through the offset before apogee (restarts it at the baro after). A gap in
 * boost or in the lockout makes the flight baro-led. The burnout timer
 * restarts; the landed timer goes on.
 *
 * Bad input (accel infinite, baro infinite, dt not finite or <= 0) returns a
 * status and leaves the state bit-identical.
 */

#ifndef FUSION_ALTITUDE_ROCKET_H
#define FUSION_ALTITUDE_ROCKET_H

#include "fusion_altitude.h"

#include <stdbool.h>
#include <stddef.h>
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
#define FUSION_ALTITUDE_ROCKET_GCC_NO_CONTRACT
#pragma GCC push_options
#pragma GCC optimize("fp-contract=off")
#endif

#if defined(__clang__)
#define FUSION_ALTITUDE_ROCKET_NO_CONTRACT _Pragma("clang fp contract(off)")
#else
#define FUSION_ALTITUDE_ROCKET_NO_CONTRACT
#endif

//------------------------------------------------------------------------------
// Definitions

/**
 * @brief Speed above which the baro is always locked out, m/s, whatever
 * lockoutSpeed says: Mach 0.8 in the coldest layer of the standard atmosphere
 * (295 m/s at -56.5 degC), where transonic shocks start to reach the static
 * ports.
 */
#define FUSION_ALTITUDE_ROCKET_MACH_LOCKOUT (236.0f)

/**
 * @brief s: a coast that the baro contradicts this long (its latest accepted
 * sample more than spikeThreshold below its peak since launch) ends in apogee
 * outside the lockout, whatever the velocity estimate says ...
 */
#define FUSION_ALTITUDE_ROCKET_CONTRADICTION_TIME (1.0f)

/**
 * @brief s: ... and in the lockout after this long: a transonic static-port
 * dip (a Mach transit takes 1-2 s) must not deploy a parachute, but a
 * velocity estimate that runs away above the lockout speed must not hide the
 * descent for minutes either.
 */
#define FUSION_ALTITUDE_ROCKET_CONTRADICTION_LOCKOUT_TIME (5.0f)

/**
 * @brief s: a baro-led flight declares apogee only once the baro has set no
 * new peak for this long (its ballistic input cannot see a burn, so the
 * velocity estimate alone could cross zero while the rocket still climbs).
 */
#define FUSION_ALTITUDE_ROCKET_PEAK_AGE (0.5f)

/**
 * @brief s: the longest gap over which the accel input is held (telemetry
 * gaps are up to about 4 s); a longer gap is extrapolated at constant velocity
 * and, unless the flight is baro-led, the baro re-admitted through the offset.
 */
#define FUSION_ALTITUDE_ROCKET_GAP_HOLD (4.0f)

/**
 * @brief 1/s: in the descent the output height also absorbs this fraction of
 * the remaining baro offset per second (on top of offsetRate * (|v| +
 * landedSpeed)), so that even an offset of kilometres (a long gap extrapolated
 * in the lockout) is gone within tens of seconds, without a step.
 */
#define FUSION_ALTITUDE_ROCKET_OFFSET_DECAY (0.1f)

/** Most sub-steps a gap is split into (see FusionAltitudeRocketUpdate). */
#define FUSION_ALTITUDE_ROCKET_MAX_GAP_STEPS (4096u)

/** Number of completed stationary windows after which the calibration is an exponential mean (weight 1/8). */
#define FUSION_ALTITUDE_ROCKET_CALIBRATION_WINDOWS (8u)

/** Status returned by every function that can reject its input. */
typedef enum {
    FusionAltitudeRocketStatusOk = 0,
    FusionAltitudeRocketStatusInvalidAccel,            /**< accel infinite (NaN: no accelerometer sample) */
    FusionAltitudeRocketStatusInvalidBaroAltitude,     /**< baro altitude infinite */
    FusionAltitudeRocketStatusInvalidDt,               /**< dt not finite or <= 0 */
    FusionAltitudeRocketStatusInvalidObserverSettings, /**< observer gains rejected by FusionAltitudeSettingsCheck */
    FusionAltitudeRocketStatusInvalidStationaryAccel,  /**< not finite or <= 0 */
    FusionAltitudeRocketStatusInvalidCalibrationWindow,/**< not finite or <= 0 */
    FusionAltitudeRocketStatusInvalidLaunchAccel,      /**< not finite or <= 0 */
    FusionAltitudeRocketStatusInvalidLaunchTime,       /**< not finite or < 0 */
    FusionAltitudeRocketStatusInvalidBurnoutAccel,     /**< not finite */
    FusionAltitudeRocketStatusInvalidBurnoutTime,      /**< not finite or < 0 */
    FusionAltitudeRocketStatusInvalidApogeeMargin,     /**< not finite or < 0 */
    FusionAltitudeRocketStatusInvalidLockoutSpeed,     /**< not finite or <= 0 */
    FusionAltitudeRocketStatusInvalidSpikeThreshold,   /**< not finite or <= 0 */
    FusionAltitudeRocketStatusInvalidSpikeTime,        /**< not finite or < 0 */
    FusionAltitudeRocketStatusInvalidOffsetRate,       /**< not finite, <= 0 or > 1 */
    FusionAltitudeRocketStatusInvalidMainAltitude,     /**< not finite or < 0 */
    FusionAltitudeRocketStatusInvalidLandedSpeed,      /**< not finite or <= 0 */
    FusionAltitudeRocketStatusInvalidLandedTime,       /**< not finite or < 0 */
    FusionAltitudeRocketStatusInvalidGapPeriod,        /**< NaN or <= 0 (+infinity: never a gap) */
    FusionAltitudeRocketStatusInvalidBaroLaunchHeight, /**< not finite or <= 0 */
} FusionAltitudeRocketStatus;

/** Flight phases, in the only order they can occur. */
typedef enum {
    FusionAltitudeRocketPhasePad = 0, /**< calibrating, waiting for launch */
    FusionAltitudeRocketPhaseBoost,   /**< motor burning */
    FusionAltitudeRocketPhaseCoast,   /**< after burnout, climbing */
    FusionAltitudeRocketPhaseDrogue,  /**< after apogee, above the main altitude */
    FusionAltitudeRocketPhaseMain,    /**< below the main altitude */
    FusionAltitudeRocketPhaseLanded,  /**< at rest after the descent */
} FusionAltitudeRocketPhase;

/** Events, indices of FusionAltitudeRocket.events. */
typedef enum {
    FusionAltitudeRocketEventLaunch = 0,
    FusionAltitudeRocketEventBurnout,
    FusionAltitudeRocketEventMaxSpeed,
    FusionAltitudeRocketEventApogee,
    FusionAltitudeRocketEventMain,
    FusionAltitudeRocketEventLanded,
} FusionAltitudeRocketEventId;

/** Number of FusionAltitudeRocketEventId values. */
#define FUSION_ALTITUDE_ROCKET_NUMBER_OF_EVENTS (6)

/** What happened to the baro sample of the latest step. */
typedef enum {
    FusionAltitudeRocketBaroNone = 0,   /**< no sample this step (NaN) */
    FusionAltitudeRocketBaroPad,        /**< on the pad: used for calibration only */
    FusionAltitudeRocketBaroFused,      /**< fused into the observer */
    FusionAltitudeRocketBaroLockedOut,  /**< not fused: speed above the lockout */
    FusionAltitudeRocketBaroSpike,      /**< not fused: rejected as a spike */
} FusionAltitudeRocketBaro;

/** One event: whether it occurred, and where. */
typedef struct {
    bool occurred;
    uint32_t sample; /**< index of the step that declared it (0 = first update after initialise) */
    float time;      /**< s since initialise (compensated sum of dt) */
    float height;    /**< m above the pad */
    float velocity;  /**< m/s, +up */
} FusionAltitudeRocketEvent;

/** Settings. Start from FusionAltitudeRocketSettingsDefault(). */
typedef struct {
    FusionAltitudeSettings observer; /**< observer gains in flight (bias gain forced to 0 after apogee) [rule: checked; else InvalidObserverSettings] */
    float stationaryAccel;   /**< m/s^2: pad samples within this of the window's first are stationary [rule: finite, > 0; else InvalidStationaryAccel] */
    float calibrationWindow; /**< s: length of a pad calibration window [rule: finite, > 0; else InvalidCalibrationWindow] */
    float launchAccel;       /**< m/s^2: accel - bias above this ... [rule: finite, > 0; else InvalidLaunchAccel] */
    float launchTime;        /**< s: ... for this long declares launch [rule: finite, >= 0; else InvalidLaunchTime] */
    float burnoutAccel;      /**< m/s^2: accel - bias below this ... [rule: finite; else InvalidBurnoutAccel] */
    float burnoutTime;       /**< s: ... for this long declares burnout [rule: finite, >= 0; else InvalidBurnoutTime] */
    float apogeeMargin;      /**< m/s: apogee when v < -apogeeMargin (the crossing of zero, past the estimate's noise) [rule: finite, >= 0; else InvalidApogeeMargin] */
    float lockoutSpeed;      /**< m/s: baro locked out while |v| is above this (and always above Mach 0.8) [rule: finite, > 0; else InvalidLockoutSpeed] */
    float spikeThreshold;    /**< m: a baro sample this far from the baro's own prediction is a spike [rule: finite, > 0; else InvalidSpikeThreshold] */
    float spikeTime;         /**< s: longest run of spike rejections before the new level is accepted [rule: finite, >= 0; else InvalidSpikeTime] */
    float offsetRate;        /**< 1: the output height absorbs the baro offset at up to offsetRate * |v| m/s [rule: finite, > 0, <= 1; else InvalidOffsetRate] */
    float mainAltitude;      /**< m above the pad: main deployment in the descent [rule: finite, >= 0; else InvalidMainAltitude] */
    float landedSpeed;       /**< m/s: |v| below this ... [rule: finite, > 0; else InvalidLandedSpeed] */
    float landedTime;        /**< s: ... for this long declares landing [rule: finite, >= 0; else InvalidLandedTime] */
    float gapPeriod;         /**< s: an update with dt above this is a gap [rule: > 0; else InvalidGapPeriod] */
    float baroLaunchHeight;  /**< m: launch from the baro when two rising pad samples are this far above the pad [rule: finite, > 0; else InvalidBaroLaunchHeight] */
} FusionAltitudeRocketSettings;

/** State. Read it through the Get functions. */
typedef struct {
    FusionAltitudeRocketSettings settings;
    FusionAltitude observer;          /**< the altitude observer, heights above the pad */
    FusionAltitudeRocketPhase phase;
    FusionAltitudeRocketBaro baro;    /**< fate of the latest baro sample */
    FusionAltitudeRocketEvent events[FUSION_ALTITUDE_ROCKET_NUMBER_OF_EVENTS];
    FusionAltitudeRocketEvent candidate; /**< first step of the current launch/burnout/landed run */
    uint32_t sample;                  /**< steps accepted so far */
    uint32_t gapCount;                /**< updates with dt > gapPeriod */
    uint32_t windows;                 /**< stationary pad windows blended into the calibration */
    uint32_t windowSamples;           /**< accel samples in the current window */
    uint32_t windowBaroSamples;       /**< baro samples in the current window */
    float time;                       /**< s since initialise */
    float timeCompensation;           /**< Kahan compensation of time, s */
    float accelBias;                  /**< pad-learned accel bias, m/s^2 */
    float padAltitude;                /**< pad pressure altitude, m */
    float windowTime;                 /**< s into the current window */
    float windowAccelFirst;           /**< m/s^2, first accel of the window */
    float windowAccelSum;             /**< sum of (accel - windowAccelFirst), m/s^2 */
    float windowBaroFirst;            /**< m, first baro of the window */
    float windowBaroSum;              /**< sum of (baro - windowBaroFirst), m */
    float runTime;                    /**< s: duration of the current launch/burnout/landed condition run */
    float spikeTime;                  /**< s: duration of the current run of spike rejections */
    float lastBaro;                   /**< m above the pad, latest baro not rejected as a spike */
    float lastBaroAge;                /**< s since lastBaro */
    float baroOffset;                 /**< m: baro height minus observer height when the baro was last re-admitted */
    float offsetApplied;              /**< m: the part of baroOffset added to the output height so far */
    float padBaroPrevious;            /**< m above the pad: the previous pad baro sample (baro launch detector) */
    float padBaroAge;                 /**< s since padBaroPrevious */
    float baroPeak;                   /**< m above the pad: highest baro sample not rejected as a spike since launch */
    float contradictionTime;          /**< s: how long the baro has stayed more than spikeThreshold below baroPeak in coast */
    float baroPeakAge;                /**< s since baroPeak was set */
    bool windowStationary;            /**< every sample of the current window stationary so far */
    bool padAltitudeSet;              /**< a baro sample has been seen on the pad */
    bool lastBaroSet;                 /**< lastBaro holds a sample */
    bool baroAdmitted;                /**< the latest baro sample not rejected as a spike was fused */
    bool lockout;                     /**< baro lockout active at the latest step */
    bool accelTrusted;                /**< latest step used the accel input */
    bool padBaroPreviousSet;          /**< padBaroPrevious holds a sample */
    bool baroLed;                     /**< no usable accelerometer since launch or since it was lost: baro-led flight */
    bool gapRestart;                  /**< the next fused baro sample restarts the observer (after an unheld or baro-led gap) */
} FusionAltitudeRocket;

//------------------------------------------------------------------------------
// Status messages

/** @return a short English description of the status, never NULL. */
static inline const char *FusionAltitudeRocketStatusMessage(const FusionAltitudeRocketStatus status) {
    static const char *const texts[] = { /* in the enum's order */
        "ok", /* FusionAltitudeRocketStatusOk */
        "accel must be finite, or NaN for no sample", /* FusionAltitudeRocketStatusInvalidAccel */
        "baro altitude must be finite, or NaN for no sample", /* FusionAltitudeRocketStatusInvalidBaroAltitude */
        "dt must be finite and > 0", /* FusionAltitudeRocketStatusInvalidDt */
        "observer gains are invalid or unstable", /* FusionAltitudeRocketStatusInvalidObserverSettings */
        "stationary accel must be finite and > 0", /* FusionAltitudeRocketStatusInvalidStationaryAccel */
        "calibration window must be finite and > 0", /* FusionAltitudeRocketStatusInvalidCalibrationWindow */
        "launch accel must be finite and > 0", /* FusionAltitudeRocketStatusInvalidLaunchAccel */
        "launch time must be finite and >= 0", /* FusionAltitudeRocketStatusInvalidLaunchTime */
        "burnout accel must be finite", /* FusionAltitudeRocketStatusInvalidBurnoutAccel */
        "burnout time must be finite and >= 0", /* FusionAltitudeRocketStatusInvalidBurnoutTime */
        "apogee margin must be finite and >= 0", /* FusionAltitudeRocketStatusInvalidApogeeMargin */
        "lockout speed must be finite and > 0", /* FusionAltitudeRocketStatusInvalidLockoutSpeed */
        "spike threshold must be finite and > 0", /* FusionAltitudeRocketStatusInvalidSpikeThreshold */
        "spike time must be finite and >= 0", /* FusionAltitudeRocketStatusInvalidSpikeTime */
        "offset rate must be > 0 and <= 1", /* FusionAltitudeRocketStatusInvalidOffsetRate */
        "main altitude must be finite and >= 0", /* FusionAltitudeRocketStatusInvalidMainAltitude */
        "landed speed must be finite and > 0", /* FusionAltitudeRocketStatusInvalidLandedSpeed */
        "landed time must be finite and >= 0", /* FusionAltitudeRocketStatusInvalidLandedTime */
        "gap period must be > 0 (+infinity: never a gap)", /* FusionAltitudeRocketStatusInvalidGapPeriod */
        "baro launch height must be finite and > 0", /* FusionAltitudeRocketStatusInvalidBaroLaunchHeight */
    };
    return FusionAltitudeStatusText(texts, sizeof(texts) / sizeof(texts[0]), (size_t) status);
}

//------------------------------------------------------------------------------
// Settings

/**
 * @brief Rocket observer gains: omega = 1.0 rad/s, zeta = 0.7, omega_b = 0
 * through FusionAltitudeSettingsFromBandwidth's formulas: Kh = 1.4 1/s,
 * Kv = 1.0 1/s^2, Kb = 0 (the bias is learned on the pad and frozen in flight,
 * so static-port and transonic baro errors never enter it). Slower than VTOL (baro noise and static-port errors matter
 * more than manoeuvres the accelerometer already measures well). Any field the
 * observer settings hold beyond the gains keeps its default, but the baro
 * timeout, which is off (+infinity): the rocket estimator locks the baro out in
 * boost and at high speed on purpose and dead-reckons through it.
 */
static inline FusionAltitudeSettings FusionAltitudeRocketObserverSettings(void) {
    FusionAltitudeSettings settings = FusionAltitudeSettingsDefault();
    settings.positionGain = 1.4f;
    settings.velocityGain = 1.0f;
    settings.biasGain = 0.0f;
    settings.baroTimeout = FusionAltitudeInfinity();
    return settings;
}

/**
 * @brief Defaults (justified in docs/rocket.md): stationary 5 m/s^2 over 0.5 s
 * windows; launch at 20 m/s^2 (about 2 g net) for 0.05 s; burnout below
 * 0 m/s^2 for 0.1 s; apogee margin 1 m/s; lockout above 100 m/s; spikes 20 m for at most 0.2 s;
 * offset rate 0.9; main at 250 m; landed below 3 m/s for 2 s; gap 0.5 s;
 * baro launch 30 m above the pad.
 */
static inline FusionAltitudeRocketSettings FusionAltitudeRocketSettingsDefault(void) {
    FusionAltitudeRocketSettings settings;
    settings.observer = FusionAltitudeRocketObserverSettings();
    settings.stationaryAccel = 5.0f;
    settings.calibrationWindow = 0.5f;
    settings.launchAccel = 20.0f;
    settings.launchTime = 0.05f;
    settings.burnoutAccel = 0.0f;
    settings.burnoutTime = 0.1f;
    settings.apogeeMargin = 1.0f;
    settings.lockoutSpeed = 100.0f;
    settings.spikeThreshold = 20.0f;
    settings.spikeTime = 0.2f;
    settings.offsetRate = 0.9f;
    settings.mainAltitude = 250.0f;
    settings.landedSpeed = 3.0f;
    settings.landedTime = 2.0f;
    settings.gapPeriod = 0.5f;
    settings.baroLaunchHeight = 30.0f;
    return settings;
}

/** @internal @return true if value is finite and > 0. */
static inline bool FusionAltitudeRocketPositive(const float value) {
    return FusionAltitudeIsFinite(value) && (value > 0.0f);
}

/** @internal @return true if value is finite and >= 0. */
static inline bool FusionAltitudeRocketNonNegative(const float value) {
    return FusionAltitudeIsFinite(value) && (value >= 0.0f);
}

/** @brief Checks every field, in declaration order; the first bad one is reported. */
static inline FusionAltitudeRocketStatus FusionAltitudeRocketSettingsCheck(const FusionAltitudeRocketSettings *const settings) {
    if (FusionAltitudeSettingsCheck(&settings->observer) != FusionAltitudeStatusOk) {
        return FusionAltitudeRocketStatusInvalidObserverSettings;
    }
    if (!FusionAltitudeRocketPositive(settings->stationaryAccel)) {
        return FusionAltitudeRocketStatusInvalidStationaryAccel;
    }
    if (!FusionAltitudeRocketPositive(settings->calibrationWindow)) {
        return FusionAltitudeRocketStatusInvalidCalibrationWindow;
    }
    if (!FusionAltitudeRocketPositive(settings->launchAccel)) {
        return FusionAltitudeRocketStatusInvalidLaunchAccel;
    }
    if (!FusionAltitudeRocketNonNegative(settings->launchTime)) {
        return FusionAltitudeRocketStatusInvalidLaunchTime;
    }
    if (!FusionAltitudeIsFinite(settings->burnoutAccel)) {
        return FusionAltitudeRocketStatusInvalidBurnoutAccel;
    }
    if (!FusionAltitudeRocketNonNegative(settings->burnoutTime)) {
        return FusionAltitudeRocketStatusInvalidBurnoutTime;
    }
    if (!FusionAltitudeRocketNonNegative(settings->apogeeMargin)) {
        return FusionAltitudeRocketStatusInvalidApogeeMargin;
    }
    if (!FusionAltitudeRocketPositive(settings->lockoutSpeed)) {
        return FusionAltitudeRocketStatusInvalidLockoutSpeed;
    }
    if (!FusionAltitudeRocketPositive(settings->spikeThreshold)) {
        return FusionAltitudeRocketStatusInvalidSpikeThreshold;
    }
    if (!FusionAltitudeRocketNonNegative(settings->spikeTime)) {
        return FusionAltitudeRocketStatusInvalidSpikeTime;
    }
    if (!FusionAltitudeRocketPositive(settings->offsetRate) || (settings->offsetRate > 1.0f)) {
        return FusionAltitudeRocketStatusInvalidOffsetRate;
    }
    if (!FusionAltitudeRocketNonNegative(settings->mainAltitude)) {
        return FusionAltitudeRocketStatusInvalidMainAltitude;
    }
    if (!FusionAltitudeRocketPositive(settings->landedSpeed)) {
        return FusionAltitudeRocketStatusInvalidLandedSpeed;
    }
    if (!FusionAltitudeRocketNonNegative(settings->landedTime)) {
        return FusionAltitudeRocketStatusInvalidLandedTime;
    }
    if (FusionAltitudeIsNaN(settings->gapPeriod) || !(settings->gapPeriod > 0.0f)) {
        return FusionAltitudeRocketStatusInvalidGapPeriod;
    }
    if (!FusionAltitudeRocketPositive(settings->baroLaunchHeight)) {
        return FusionAltitudeRocketStatusInvalidBaroLaunchHeight;
    }
    return FusionAltitudeRocketStatusOk;
}

//------------------------------------------------------------------------------
// Estimator

/** @internal Empties the calibration window (sample counts, time s, sums). */
static inline void FusionAltitudeRocketClearWindow(FusionAltitudeRocket *const rocket) {
    rocket->windowSamples = 0u;
    rocket->windowBaroSamples = 0u;
    rocket->windowTime = 0.0f;
    rocket->windowAccelFirst = 0.0f;
    rocket->windowAccelSum = 0.0f;
    rocket->windowBaroFirst = 0.0f;
    rocket->windowBaroSum = 0.0f;
    rocket->windowStationary = true;
}

/**
 * @brief Initialises with the given settings (FusionAltitudeRocketSettingsDefault()
 * if NULL): phase pad, nothing calibrated, no events, time 0.
 * @return FusionAltitudeRocketStatusOk, or the settings' status (then *rocket
 * is left untouched).
 */
static inline FusionAltitudeRocketStatus FusionAltitudeRocketInitialise(FusionAltitudeRocket *const rocket,
                                                                        const FusionAltitudeRocketSettings *const settings) {
    const FusionAltitudeRocketSettings chosen = (settings == NULL) ? FusionAltitudeRocketSettingsDefault() : *settings;
    const FusionAltitudeRocketStatus status = FusionAltitudeRocketSettingsCheck(&chosen);
    if (status != FusionAltitudeRocketStatusOk) {
        return status;
    }
    memset(rocket, 0, sizeof(*rocket)); /* padding too: two states compare with memcmp */
    rocket->settings = chosen;
    FusionAltitudeInitialise(&rocket->observer);
    (void) FusionAltitudeSetSettings(&rocket->observer, &chosen.observer);
    (void) FusionAltitudeResetWithBias(&rocket->observer, 0.0f, 0.0f);
    rocket->phase = FusionAltitudeRocketPhasePad;
    rocket->baro = FusionAltitudeRocketBaroNone;
    FusionAltitudeRocketClearWindow(rocket);
    return FusionAltitudeRocketStatusOk;
}

/** @brief The input rules of the update functions, on their own. */
static inline FusionAltitudeRocketStatus FusionAltitudeRocketCheckInputs(const float accel, const float baroAltitude, const float dt) {
    /* accel NaN means no accelerometer sample; the observer's rules apply to the rest */
    switch (FusionAltitudeCheckInputs(FusionAltitudeIsNaN(accel) ? 0.0f : accel, baroAltitude, dt)) {
        case FusionAltitudeStatusOk:
            return FusionAltitudeRocketStatusOk;
        case FusionAltitudeStatusInvalidAccel:
            return FusionAltitudeRocketStatusInvalidAccel;
        case FusionAltitudeStatusInvalidBaroAltitude:
            return FusionAltitudeRocketStatusInvalidBaroAltitude;
        default:
            return FusionAltitudeRocketStatusInvalidDt;
    }
}

/** @internal Records an event now: sample, time (s), height (m above the pad), velocity (m/s). */
static inline void FusionAltitudeRocketRecord(const FusionAltitudeRocket *const rocket, FusionAltitudeRocketEvent *const event) {
    event->occurred = true;
    event->sample = rocket->sample;
    event->time = rocket->time;
    event->height = FusionAltitudeGetAltitude(&rocket->observer) + rocket->offsetApplied;
    event->velocity = FusionAltitudeGetVerticalVelocity(&rocket->observer);
}

/** @internal
 * Calibration window on the pad (no gap, no launch candidate): sums of accel
 * (m/s^2; NaN: no sample) and baro altitude (m; hasBaro: a reading) relative
 * to the window's first samples; a window is stationary while accel stays
 * within +-stationaryAccel (m/s^2) of its first sample. After
 * calibrationWindow s (dt, s) a stationary window moves accelBias (if it
 * held an accel sample) and padAltitude to its means with weight 1 / windows
 * (windows <= FUSION_ALTITUDE_ROCKET_CALIBRATION_WINDOWS).
 */
static inline void FusionAltitudeRocketCalibrationStep(FusionAltitudeRocket *const rocket, const float accel, const float baroAltitude,
                                                       const bool hasBaro, const float dt) {
    FUSION_ALTITUDE_ROCKET_NO_CONTRACT
    const FusionAltitudeRocketSettings *const settings = &rocket->settings;
    if (!FusionAltitudeIsNaN(accel)) {
        if (rocket->windowSamples == 0u) {
            rocket->windowAccelFirst = accel;
        }
        const float deviation = accel - rocket->windowAccelFirst;
        if (!(deviation <= settings->stationaryAccel) || !(deviation >= -settings->stationaryAccel)) {
            rocket->windowStationary = false;
        }
        rocket->windowAccelSum += deviation;
        rocket->windowSamples++;
    }
    if (hasBaro) {
        if (rocket->windowBaroSamples == 0u) {
            rocket->windowBaroFirst = baroAltitude;
        }
        rocket->windowBaroSum += baroAltitude - rocket->windowBaroFirst;
        rocket->windowBaroSamples++;
    }
    rocket->windowTime += dt;
    if (rocket->windowTime >= settings->calibrationWindow) {
        if (rocket->windowStationary) {
            if (rocket->windows < FUSION_ALTITUDE_ROCKET_CALIBRATION_WINDOWS) {
                rocket->windows++;
            }
            const float weight = 1.0f / (float) rocket->windows;
            if (rocket->windowSamples > 0u) {
                const float meanAccel = rocket->windowAccelFirst + rocket->windowAccelSum / (float) rocket->windowSamples;
                rocket->accelBias += (meanAccel - rocket->accelBias) * weight;
            }
            if (rocket->windowBaroSamples > 0u) {
                const float meanBaro = rocket->windowBaroFirst + rocket->windowBaroSum / (float) rocket->windowBaroSamples;
                rocket->padAltitude += (meanBaro - rocket->padAltitude) * weight;
            }
            (void) FusionAltitudeResetWithBias(&rocket->observer, 0.0f, rocket->accelBias);
        }
        FusionAltitudeRocketClearWindow(rocket);
    }
}

/** @internal
 * Launch from the baro (pad; baroAltitude m, a sample): the sample and the
 * pad sample before it are both more than baroLaunchHeight m above the pad
 * and it is higher than that one (rising). The accelerometer did not show
 * the launch (dead, missing, wrong axis), so the flight is baro-led from here
 * (baroLed): the observer restarts at the sample's height, with v the mean
 * velocity since the pad sample before if that is more than gapPeriod s old
 * (a telemetry gap over the launch), else 0 (denser samples are too noisy for a
 * difference; the baro pulls v up within a few s). The phase goes straight to
 * coast (no burnout event). Returns true if launched. (baroAltitude, m.)
 */
static inline bool FusionAltitudeRocketBaroLaunchStep(FusionAltitudeRocket *const rocket, const float baroAltitude) {
    FUSION_ALTITUDE_ROCKET_NO_CONTRACT
    const FusionAltitudeRocketSettings *const settings = &rocket->settings;
    const float height = baroAltitude - rocket->padAltitude;
    const float previous = rocket->padBaroPrevious;
    const float age = rocket->padBaroAge;
    const bool launched = rocket->padBaroPreviousSet && (previous > settings->baroLaunchHeight) &&
                          (height > settings->baroLaunchHeight) && (height > previous);
    rocket->padBaroPrevious = height;
    rocket->padBaroAge = 0.0f;
    rocket->padBaroPreviousSet = true;
    if (!launched) {
        return false;
    }
    (void) FusionAltitudeResetWithBias(&rocket->observer, height, rocket->accelBias);
    if (age > settings->gapPeriod) {
        rocket->observer.verticalVelocity = (height - previous) / age; /* no API for it: see FusionAltitudeRocketGate */
    }
    FusionAltitudeRocketRecord(rocket, &rocket->events[FusionAltitudeRocketEventLaunch]);
    rocket->phase = FusionAltitudeRocketPhaseCoast;
    rocket->baroLed = true;
    rocket->baroAdmitted = true;
    rocket->baro = FusionAltitudeRocketBaroFused;
    rocket->lastBaro = height;
    rocket->lastBaroAge = 0.0f;
    rocket->lastBaroSet = true;
    rocket->baroPeak = height;
    rocket->baroPeakAge = 0.0f;
    rocket->runTime = 0.0f;
    FusionAltitudeRocketClearWindow(rocket);
    return true;
}

/** @internal Pad step: calibration windows and the launch detectors (accel; baro). accel: m/s^2 (NaN: none); baroAltitude: m (NaN: none); dt: s. */
static inline void FusionAltitudeRocketPadStep(FusionAltitudeRocket *const rocket, const float accel, const float baroAltitude,
                                               const float dt, const bool gap) {
    FUSION_ALTITUDE_ROCKET_NO_CONTRACT
    const FusionAltitudeRocketSettings *const settings = &rocket->settings;
    const bool hasBaro = !FusionAltitudeIsNaN(baroAltitude);
    rocket->baro = hasBaro ? FusionAltitudeRocketBaroPad : FusionAltitudeRocketBaroNone;
    if (hasBaro && !rocket->padAltitudeSet) {
        rocket->padAltitude = baroAltitude; /* until the first window completes */
        rocket->padAltitudeSet = true;
    }
    rocket->padBaroAge += dt;
    if (hasBaro && FusionAltitudeRocketBaroLaunchStep(rocket, baroAltitude)) {
        return;
    }

    /* Launch detector: accel - bias > launchAccel for launchTime s (no accel sample: no candidate). */
    const float netAccel = accel - rocket->accelBias;
    if (!gap && !FusionAltitudeIsNaN(accel) && (netAccel > settings->launchAccel)) {
        if (rocket->runTime == 0.0f) { /* first sample of a candidate run: start from rest at the pad */
            (void) FusionAltitudeResetWithBias(&rocket->observer, 0.0f, rocket->accelBias);
            (void) FusionAltitudeUpdate(&rocket->observer, accel, FUSION_ALTITUDE_NO_BARO, dt);
            FusionAltitudeRocketRecord(rocket, &rocket->candidate);
        } else {
            (void) FusionAltitudeUpdate(&rocket->observer, accel, FUSION_ALTITUDE_NO_BARO, dt);
        }
        rocket->runTime += dt;
        if (rocket->runTime >= settings->launchTime) {
            rocket->events[FusionAltitudeRocketEventLaunch] = rocket->candidate;
            rocket->phase = FusionAltitudeRocketPhaseBoost;
            rocket->baroAdmitted = true; /* baro fused from launch with offset 0 until the first lockout */
            rocket->runTime = 0.0f;
            FusionAltitudeRocketClearWindow(rocket);
        }
        rocket->windowStationary = false;
        return;
    }
    rocket->runTime = 0.0f;
    (void) FusionAltitudeResetWithBias(&rocket->observer, 0.0f, rocket->accelBias);

    /* Calibration window. */
    if (gap) {
        FusionAltitudeRocketClearWindow(rocket);
        return;
    }
    FusionAltitudeRocketCalibrationStep(rocket, accel, baroAltitude, hasBaro, dt);
}

/** @internal
 * Baro gate after launch: returns the baro value to fuse (height above the pad
 * minus the baro offset, m) or NaN. The spike threshold grows with the age of
 * the last accepted sample (s) as spikeThreshold + g * age^2 / 2 (m): the
 * prediction lastBaro + v * age misses by up to a * age^2 / 2 when the
 * velocity changes at a (about g in coast), which at telemetry rates (0.1-4 s
 * between samples) is tens of metres. A baro-led flight (baroLed) fuses
 * every sample that is not a spike, whatever the speed, and never re-bases
 * the offset: the baro is all it has.
 */
static inline float FusionAltitudeRocketGate(FusionAltitudeRocket *const rocket, const float baroAltitude, const float dt) {
    FUSION_ALTITUDE_ROCKET_NO_CONTRACT
    const FusionAltitudeRocketSettings *const settings = &rocket->settings;
    const float velocity = FusionAltitudeGetVerticalVelocity(&rocket->observer);
    const float lockoutSpeed = (settings->lockoutSpeed < FUSION_ALTITUDE_ROCKET_MACH_LOCKOUT) ? settings->lockoutSpeed
                                                                                            : FUSION_ALTITUDE_ROCKET_MACH_LOCKOUT;
    rocket->lockout = ((rocket->phase == FusionAltitudeRocketPhaseBoost) && !rocket->baroLed) || (velocity > lockoutSpeed) ||
                      (velocity < -lockoutSpeed);
    rocket->lastBaroAge += dt;
    rocket->baroPeakAge += dt;
    if (FusionAltitudeIsNaN(baroAltitude)) {
        rocket->baro = FusionAltitudeRocketBaroNone;
        return FUSION_ALTITUDE_NO_BARO;
    }
    const float height = baroAltitude - rocket->padAltitude;
    const float previousBaro = rocket->lastBaro;
    const float previousAge = rocket->lastBaroAge;
    const bool previousSet = rocket->lastBaroSet;
    if (rocket->lastBaroSet) {
        const float miss = height - (rocket->lastBaro + velocity * rocket->lastBaroAge);
        const float threshold = settings->spikeThreshold + (0.5f * FUSION_ALTITUDE_GRAVITY) * (rocket->lastBaroAge * rocket->lastBaroAge);
        if ((miss > threshold) || (miss < -threshold)) {
            if (rocket->spikeTime < settings->spikeTime) {
                rocket->spikeTime += dt;
                rocket->baro = FusionAltitudeRocketBaroSpike;
                return FUSION_ALTITUDE_NO_BARO;
            }
            if (!rocket->baroLed) {
                rocket->baroAdmitted = false; /* a lasting step: re-admitted through the offset, not the velocity */
            }
        }
    }
    rocket->spikeTime = 0.0f;
    rocket->lastBaro = height;
    rocket->lastBaroAge = 0.0f;
    rocket->lastBaroSet = true;
    if (height > rocket->baroPeak) {
        rocket->baroPeak = height;
        rocket->baroPeakAge = 0.0f;
    }
    if (rocket->lockout && !rocket->baroLed) {
        rocket->baro = FusionAltitudeRocketBaroLockedOut;
        rocket->baroAdmitted = false;
        return FUSION_ALTITUDE_NO_BARO;
    }
    rocket->baro = FusionAltitudeRocketBaroFused;
    if (rocket->gapRestart) {
        /* After a gap that was not extrapolated on a held accel (longer than FUSION_ALTITUDE_ROCKET_GAP_HOLD s, or
         * baro-led) the extrapolated height and velocity are guesses: the velocity restarts as the baro's mean
         * velocity since its previous accepted sample (m/s; kept without one). Before apogee the height is
         * re-admitted through the offset (the output never falls while climbing; the baro reads low by the
         * static-port error there); from apogee on the observer restarts at the baro (height minus the offset
         * kept, m): the output height steps to the baro rather than staying wrong. The only place the flight
         * layer writes observer fields directly: its API has no restart with a given velocity. */
        if (rocket->phase < FusionAltitudeRocketPhaseDrogue) {
            rocket->baroOffset = height - FusionAltitudeGetAltitude(&rocket->observer);
        } else {
            rocket->observer.altitude = height - rocket->baroOffset;
        }
        if (previousSet && (previousAge > 0.0f)) {
            rocket->observer.verticalVelocity = (height - previousBaro) / previousAge;
        }
        rocket->gapRestart = false;
        rocket->baroAdmitted = true;
    } else if (!rocket->baroAdmitted) { /* re-admission: the observer keeps its (inertial) height; the offset goes to the output */
        rocket->baroOffset = height - FusionAltitudeGetAltitude(&rocket->observer);
        rocket->baroAdmitted = true;
    }
    return height - rocket->baroOffset;
}

/** @internal
 * a debounced condition (burnout, landing): while condition holds, runTime
 * (s) grows by dt; the run's first sample is the event's candidate record.
 * Once runTime >= holdTime (s) the candidate becomes the event and the phase
 * moves on. A sample without the condition restarts the run (runTime = 0).
 */
static inline void FusionAltitudeRocketConditionRun(FusionAltitudeRocket *const rocket, const bool condition, const float dt, const float holdTime,
                                                    const FusionAltitudeRocketEventId event, const FusionAltitudeRocketPhase phase) {
    FUSION_ALTITUDE_ROCKET_NO_CONTRACT
    if (condition) {
        if (rocket->runTime == 0.0f) {
            FusionAltitudeRocketRecord(rocket, &rocket->candidate);
        }
        rocket->runTime += dt;
        if (rocket->runTime >= holdTime) {
            rocket->events[event] = rocket->candidate;
            rocket->phase = phase;
            rocket->runTime = 0.0f;
        }
    } else {
        rocket->runTime = 0.0f;
    }
}

/** @internal Landing detector: |v| < landedSpeed for landedTime s (drogue and main phases). */
static inline void FusionAltitudeRocketLandedStep(FusionAltitudeRocket *const rocket, const float velocity, const float dt) {
    FUSION_ALTITUDE_ROCKET_NO_CONTRACT
    const FusionAltitudeRocketSettings *const settings = &rocket->settings;
    const bool still = !rocket->lockout && (velocity < settings->landedSpeed) && (velocity > -settings->landedSpeed);
    FusionAltitudeRocketConditionRun(rocket, still, dt, settings->landedTime, FusionAltitudeRocketEventLanded, FusionAltitudeRocketPhaseLanded);
}

/** @internal
 * Gap in flight (dt > gapPeriod, s): extrapolation over dt in 2^n equal
 * sub-steps no longer than gapPeriod (at most
 * FUSION_ALTITUDE_ROCKET_MAX_GAP_STEPS) with the accel input `input` (m/s^2,
 * see FusionAltitudeRocketInput): this step's accel held over the gap in
 * coast (about -g: a telemetry gap of 4 s at apogee then misses by metres,
 * not the 78 m of a constant velocity), the bias (no net acceleration) in
 * boost. The baro is not re-admitted through the offset after a gap unless it
 * was locked out: the next sample is fused, so that it corrects the
 * extrapolated velocity (re-basing after every gap of a 2 Hz telemetry log
 * hid the descent from the velocity and kept the flight in coast for minutes).
 */
static inline void FusionAltitudeRocketGapStep(FusionAltitudeRocket *const rocket, const float input, const float dt) {
    FUSION_ALTITUDE_ROCKET_NO_CONTRACT
    const FusionAltitudeRocketSettings *const settings = &rocket->settings;
    uint32_t steps = 1u;
    float step = dt;
    while ((step > settings->gapPeriod) && (steps < FUSION_ALTITUDE_ROCKET_MAX_GAP_STEPS)) {
        steps *= 2u;
        step = dt / (float) steps;
    }
    const bool hold = (rocket->phase != FusionAltitudeRocketPhaseBoost) && (dt <= FUSION_ALTITUDE_ROCKET_GAP_HOLD);
    const float gapInput = hold ? input : FusionAltitudeGetAccelBias(&rocket->observer);
    /* a baro-led coast is not extrapolated into a descent the baro has not shown: the ballistic input stops at v <= 0 */
    const bool holdTop = rocket->baroLed && (rocket->phase == FusionAltitudeRocketPhaseCoast);
    for (uint32_t index = 0u; index < steps; index++) {
        const bool top = holdTop && !(FusionAltitudeGetVerticalVelocity(&rocket->observer) > 0.0f);
        (void) FusionAltitudeUpdate(&rocket->observer, top ? FusionAltitudeGetAccelBias(&rocket->observer) : gapInput,
                                    FUSION_ALTITUDE_NO_BARO, step);
    }
    if (rocket->baroLed || !hold) {
        rocket->gapRestart = true; /* the extrapolation is a guess: the next sample restarts the observer (FusionAltitudeRocketGate) */
    } else {
        rocket->baroAdmitted = false; /* held: the height error goes through the offset, not into the velocity */
    }
    rocket->lastBaroAge += dt;
    rocket->baroPeakAge += dt;
    if (rocket->phase == FusionAltitudeRocketPhaseBoost) {
        rocket->runTime = 0.0f; /* the burnout run restarts; a landed run goes on (telemetry gaps every few s) */
    }
    rocket->baro = FusionAltitudeRocketBaroNone;
}

/** @internal
 * offsetApplied (m) -> baroOffset (m) while climbing: up by at most
 * offsetRate * |v| * dt (v: velocity, m/s; dt, s), down by at most offsetRate
 * times the observer's rise in this step (height - heightBefore, m; none if it
 * did not rise), so the output height never falls by absorbing the offset. In
 * the descent it moves by at most (offsetRate * (|v| + landedSpeed) +
 * FUSION_ALTITUDE_ROCKET_OFFSET_DECAY * |baroOffset - offsetApplied|) * dt either
 * way: the height blends into the baro without a step (the apogee event itself
 * reports the baro-corrected height, see FusionAltitudeRocketPhaseStep).
 */
static inline void FusionAltitudeRocketApplyOffset(FusionAltitudeRocket *const rocket, const float velocity, const float heightBefore,
                                                   const float dt) {
    FUSION_ALTITUDE_ROCKET_NO_CONTRACT
    const FusionAltitudeRocketSettings *const settings = &rocket->settings;
    const float speed = (velocity < 0.0f) ? -velocity : velocity;
    const float offsetStep = settings->offsetRate * speed * dt;
    const float rise = FusionAltitudeGetAltitude(&rocket->observer) - heightBefore;
    const float offsetStepDown = (rise > 0.0f) ? (settings->offsetRate * rise) : 0.0f;
    const float offsetLeft = rocket->baroOffset - rocket->offsetApplied;
    if (rocket->phase >= FusionAltitudeRocketPhaseDrogue) {
        const float left = (offsetLeft < 0.0f) ? -offsetLeft : offsetLeft;
        const float descentStep = (settings->offsetRate * (speed + settings->landedSpeed) + FUSION_ALTITUDE_ROCKET_OFFSET_DECAY * left) * dt;
        if (offsetLeft > descentStep) {
            rocket->offsetApplied += descentStep;
        } else if (offsetLeft < -descentStep) {
            rocket->offsetApplied -= descentStep;
        } else {
            rocket->offsetApplied = rocket->baroOffset;
        }
    } else if (offsetLeft > offsetStep) {
        rocket->offsetApplied += offsetStep;
    } else if (offsetLeft < -offsetStepDown) {
        rocket->offsetApplied -= offsetStepDown;
    } else {
        rocket->offsetApplied = rocket->baroOffset;
    }
}

/** @internal Burnout detector (boost): accel - bias < burnoutAccel (m/s^2) for burnoutTime s (dt, s). */
static inline void FusionAltitudeRocketBurnoutStep(FusionAltitudeRocket *const rocket, const float accel, const float dt) {
    FUSION_ALTITUDE_ROCKET_NO_CONTRACT
    const FusionAltitudeRocketSettings *const settings = &rocket->settings;
    const float netAccel = accel - rocket->accelBias;
    FusionAltitudeRocketConditionRun(rocket, netAccel < settings->burnoutAccel, dt, settings->burnoutTime, FusionAltitudeRocketEventBurnout,
                                     FusionAltitudeRocketPhaseCoast);
}

/** @internal
 * Apogee: coast -> drogue, the observer's bias frozen from then on. The
 * reported apogee height is baro-corrected: the observer height plus the whole
 * baro offset found at re-admission (m), i.e. where the baro puts the rocket,
 * not the inertial height the output is still blending from (the output height
 * reaches it in the descent without a step, FusionAltitudeRocketApplyOffset).
 * When the baro contradicted the coast (contradicted), the apogee height is
 * the baro's peak, the velocity estimate (wrong) restarts at 0 m/s at the
 * current height and the baro is re-admitted through the offset.
 */
static inline void FusionAltitudeRocketApogee(FusionAltitudeRocket *const rocket, const bool contradicted) {
    FUSION_ALTITUDE_ROCKET_NO_CONTRACT
    FusionAltitudeRocketEvent *const apogee = &rocket->events[FusionAltitudeRocketEventApogee];
    FusionAltitudeRocketRecord(rocket, apogee);
    apogee->height = contradicted ? rocket->baroPeak : (FusionAltitudeGetAltitude(&rocket->observer) + rocket->baroOffset);
    rocket->phase = FusionAltitudeRocketPhaseDrogue;
    FusionAltitudeSettings descent = rocket->settings.observer;
    descent.biasGain = 0.0f; /* bias frozen from apogee on */
    (void) FusionAltitudeSetSettings(&rocket->observer, &descent);
    if (contradicted) {
        (void) FusionAltitudeResetWithBias(&rocket->observer, FusionAltitudeGetAltitude(&rocket->observer),
                                           FusionAltitudeGetAccelBias(&rocket->observer));
        rocket->baroAdmitted = false;
    }
}

/** @internal
 * Phase transitions after the observer step: burnout (boost), apogee at
 * v < -apogeeMargin (coast; v: velocity, m/s) or when the baro has contradicted
 * the coast for FUSION_ALTITUDE_ROCKET_CONTRADICTION_TIME s, main deployment
 * at the baro-corrected height (observer height + baro offset, m above the pad)
 * <= mainAltitude (drogue) and landing (drogue and main). accel: m/s^2; dt: s.
 */
static inline void FusionAltitudeRocketPhaseStep(FusionAltitudeRocket *const rocket, const float accel, const float velocity, const float dt) {
    FUSION_ALTITUDE_ROCKET_NO_CONTRACT
    const FusionAltitudeRocketSettings *const settings = &rocket->settings;
    const float height = FusionAltitudeGetAltitude(&rocket->observer) + rocket->baroOffset;
    switch (rocket->phase) {
        case FusionAltitudeRocketPhaseBoost:
            FusionAltitudeRocketBurnoutStep(rocket, accel, dt);
            break;
        case FusionAltitudeRocketPhaseCoast: {
            const bool contradicted = rocket->lastBaroSet && (rocket->lastBaro < (rocket->baroPeak - settings->spikeThreshold));
            rocket->contradictionTime = contradicted ? (rocket->contradictionTime + dt) : 0.0f;
            /* baro-led: also this step's baro fused, below the peak, and no new peak for FUSION_ALTITUDE_ROCKET_PEAK_AGE s */
            const bool baroAgrees = !rocket->baroLed || ((rocket->baro == FusionAltitudeRocketBaroFused) &&
                                                         (rocket->lastBaro < rocket->baroPeak) &&
                                                         (rocket->baroPeakAge >= FUSION_ALTITUDE_ROCKET_PEAK_AGE));
            if (!rocket->lockout && (velocity < -settings->apogeeMargin) && baroAgrees) {
                FusionAltitudeRocketApogee(rocket, false);
            } else if (rocket->contradictionTime >= (rocket->lockout ? FUSION_ALTITUDE_ROCKET_CONTRADICTION_LOCKOUT_TIME
                                                                      : FUSION_ALTITUDE_ROCKET_CONTRADICTION_TIME)) {
                FusionAltitudeRocketApogee(rocket, true);
            }
            break;
        }
        case FusionAltitudeRocketPhaseDrogue:
            if (!rocket->lockout && !(height > settings->mainAltitude)) {
                FusionAltitudeRocketRecord(rocket, &rocket->events[FusionAltitudeRocketEventMain]);
                rocket->phase = FusionAltitudeRocketPhaseMain;
                rocket->runTime = 0.0f;
            } else {
                FusionAltitudeRocketLandedStep(rocket, velocity, dt);
            }
            break;
        case FusionAltitudeRocketPhaseMain:
            FusionAltitudeRocketLandedStep(rocket, velocity, dt);
            break;
        default:
            break;
    }
}

/** @internal
 * The observer's accel input (m/s^2) this step: the accel (m/s^2) until apogee,
 * and after it only if accelVertical (an INS); never in a baro-led flight.
 * Otherwise the bias (no net acceleration), except in a baro-led coast:
 * bias - g, ballistic, since the baro alone would lag the deceleration by
 * Kh * g / Kv (14 m/s with the rocket gains) and declare apogee 1.4 s late.
 */
static inline float FusionAltitudeRocketInput(FusionAltitudeRocket *const rocket, const float accel, const bool accelVertical) {
    FUSION_ALTITUDE_ROCKET_NO_CONTRACT
    const bool descending = rocket->phase >= FusionAltitudeRocketPhaseDrogue;
    rocket->accelTrusted = !rocket->baroLed && (!descending || accelVertical);
    if (rocket->accelTrusted) {
        return accel;
    }
    if (rocket->baroLed && (rocket->phase == FusionAltitudeRocketPhaseCoast)) {
        return FusionAltitudeGetAccelBias(&rocket->observer) - FUSION_ALTITUDE_GRAVITY;
    }
    return FusionAltitudeGetAccelBias(&rocket->observer);
}

/** @internal
 * Flight step (boost and later). accel: m/s^2 (NaN: no sample, the
 * accelerometer is lost: baro-led for the rest of the flight, boost -> coast
 * without a burnout event); baroAltitude: m (NaN: none); dt: s.
 */
static inline void FusionAltitudeRocketFlightStep(FusionAltitudeRocket *const rocket, const float accel, const float baroAltitude,
                                                  const float dt, const bool gap, const bool accelVertical) {
    FUSION_ALTITUDE_ROCKET_NO_CONTRACT
    if (FusionAltitudeIsNaN(accel) && !rocket->baroLed) {
        rocket->baroLed = true;
        if (rocket->phase == FusionAltitudeRocketPhaseBoost) {
            rocket->phase = FusionAltitudeRocketPhaseCoast;
            rocket->runTime = 0.0f;
        }
    }
    if (gap && !rocket->baroLed && (rocket->phase < FusionAltitudeRocketPhaseDrogue) &&
        (rocket->lockout || (rocket->phase == FusionAltitudeRocketPhaseBoost))) {
        /* a gap in boost or in the lockout: the integrated velocity is lost and the baro cannot check it yet */
        rocket->baroLed = true;
        if (rocket->phase == FusionAltitudeRocketPhaseBoost) {
            rocket->phase = FusionAltitudeRocketPhaseCoast;
            rocket->runTime = 0.0f;
        }
    }
    const float input = FusionAltitudeRocketInput(rocket, accel, accelVertical);
    if (gap) {
        FusionAltitudeRocketGapStep(rocket, input, dt);
        return;
    }
    const float fused = FusionAltitudeRocketGate(rocket, baroAltitude, dt);
    const float heightBefore = FusionAltitudeGetAltitude(&rocket->observer);
    (void) FusionAltitudeUpdate(&rocket->observer, input, fused, dt);
    const float velocity = FusionAltitudeGetVerticalVelocity(&rocket->observer);
    FusionAltitudeRocketApplyOffset(rocket, velocity, heightBefore, dt);
    FusionAltitudeRocketPhaseStep(rocket, accel, velocity, dt);
    /* maximum speed: the largest v (m/s) of boost and coast */
    if (((rocket->phase == FusionAltitudeRocketPhaseBoost) || (rocket->phase == FusionAltitudeRocketPhaseCoast)) &&
        (!rocket->events[FusionAltitudeRocketEventMaxSpeed].occurred ||
         (velocity > rocket->events[FusionAltitudeRocketEventMaxSpeed].velocity))) {
        FusionAltitudeRocketRecord(rocket, &rocket->events[FusionAltitudeRocketEventMaxSpeed]);
    }
}

/** @internal One step of FusionAltitudeRocketUpdate (accelVertical false) or FusionAltitudeRocketUpdateVertical (true). */
static inline FusionAltitudeRocketStatus FusionAltitudeRocketStep(FusionAltitudeRocket *const rocket, const float accel,
                                                                  const float baroAltitude, const float dt, const bool accelVertical) {
    FUSION_ALTITUDE_ROCKET_NO_CONTRACT
    const FusionAltitudeRocketStatus status = FusionAltitudeRocketCheckInputs(accel, baroAltitude, dt);
    if (status != FusionAltitudeRocketStatusOk) {
        return status;
    }
    /* time += dt, Kahan-compensated so that event times stay within a few ulp over long flights */
    const float increment = dt - rocket->timeCompensation;
    const float sum = rocket->time + increment;
    rocket->timeCompensation = (sum - rocket->time) - increment;
    rocket->time = sum;

    const bool gap = dt > rocket->settings.gapPeriod;
    if (gap) {
        rocket->gapCount++;
    }
    if (rocket->phase == FusionAltitudeRocketPhasePad) {
        rocket->lockout = false;
        rocket->accelTrusted = true;
        FusionAltitudeRocketPadStep(rocket, accel, baroAltitude, dt, gap);
    } else {
        FusionAltitudeRocketFlightStep(rocket, accel, baroAltitude, dt, gap, accelVertical);
    }
    rocket->sample++;
    return FusionAltitudeRocketStatusOk;
}

/**
 * @brief One step, accel from the accelerometer axis along the airframe.
 *
 * @param accel m/s^2, accelerometer along the long axis (nose up, +up on the
 *        pad) minus g: about 0 at rest on the pad. Used as vertical until
 *        apogee, ignored after it.
 * @param baroAltitude m, pressure altitude; FUSION_ALTITUDE_NO_BARO when no
 *        sample arrived this step.
 * @param dt s since the previous step.
 * @return FusionAltitudeRocketStatusOk, or the input's status with the state
 *         bit-identical.
 */
static inline FusionAltitudeRocketStatus FusionAltitudeRocketUpdate(FusionAltitudeRocket *const rocket, const float accel,
                                                                    const float baroAltitude, const float dt) {
    return FusionAltitudeRocketStep(rocket, accel, baroAltitude, dt, false);
}

/**
 * @brief One step, accel a trusted earth-frame vertical acceleration (m/s^2,
 * +up, gravity removed), e.g. from an INS (fusion_altitude_ins.h): used in
 * every phase, including the descent. Otherwise as FusionAltitudeRocketUpdate.
 */
static inline FusionAltitudeRocketStatus FusionAltitudeRocketUpdateWithVerticalAccel(FusionAltitudeRocket *const rocket, const float accel,
                                                                                     const float baroAltitude, const float dt) {
    return FusionAltitudeRocketStep(rocket, accel, baroAltitude, dt, true);
}

/** @return height above the pad, m (0 on the pad while calibrating): observer height + applied baro offset. */
static inline float FusionAltitudeRocketGetHeight(const FusionAltitudeRocket *const rocket) {
    FUSION_ALTITUDE_ROCKET_NO_CONTRACT
    return FusionAltitudeGetAltitude(&rocket->observer) + rocket->offsetApplied;
}

/** @return vertical velocity, m/s, +up. */
static inline float FusionAltitudeRocketGetVerticalVelocity(const FusionAltitudeRocket *const rocket) {
    return FusionAltitudeGetVerticalVelocity(&rocket->observer);
}

/** @return the accel bias in use, m/s^2 (pad-learned; frozen after apogee). */
static inline float FusionAltitudeRocketGetAccelBias(const FusionAltitudeRocket *const rocket) {
    return FusionAltitudeGetAccelBias(&rocket->observer);
}

/** @return the pad's pressure altitude learned on the pad, m (0 before any baro sample). */
static inline float FusionAltitudeRocketGetPadAltitude(const FusionAltitudeRocket *const rocket) {
    return rocket->padAltitude;
}

/** @return the current flight phase. */
static inline FusionAltitudeRocketPhase FusionAltitudeRocketGetPhase(const FusionAltitudeRocket *const rocket) {
    return rocket->phase;
}

/** @return what happened to the latest step's baro sample. */
static inline FusionAltitudeRocketBaro FusionAltitudeRocketGetBaro(const FusionAltitudeRocket *const rocket) {
    return rocket->baro;
}

/** @return true while the baro is locked out by speed (latest step). */
static inline bool FusionAltitudeRocketIsLockedOut(const FusionAltitudeRocket *const rocket) {
    return rocket->lockout;
}

/** @return true once at least one stationary pad window has been blended into the calibration. */
static inline bool FusionAltitudeRocketIsCalibrated(const FusionAltitudeRocket *const rocket) {
    return rocket->windows > 0u;
}

/** @return the event (occurred false if not yet); an unknown id returns an event that has not occurred. */
static inline FusionAltitudeRocketEvent FusionAltitudeRocketGetEvent(const FusionAltitudeRocket *const rocket,
                                                                     const FusionAltitudeRocketEventId event) {
    const unsigned int index = (unsigned int) event; /* an enum may be 1 byte and unsigned (-fshort-enums) */
    if (index >= (unsigned int) FUSION_ALTITUDE_ROCKET_NUMBER_OF_EVENTS) {
        const FusionAltitudeRocketEvent none = {false, 0u, 0.0f, 0.0f, 0.0f};
        return none;
    }
    return rocket->events[index];
}

/** @return updates with dt > gapPeriod so far. */
static inline uint32_t FusionAltitudeRocketGetGapCount(const FusionAltitudeRocket *const rocket) {
    return rocket->gapCount;
}

/** @return s since initialise (compensated sum of the accepted dt). */
static inline float FusionAltitudeRocketGetTime(const FusionAltitudeRocket *const rocket) {
    return rocket->time;
}

#undef FUSION_ALTITUDE_ROCKET_NO_CONTRACT

#ifdef FUSION_ALTITUDE_ROCKET_GCC_NO_CONTRACT
#pragma GCC pop_options
#undef FUSION_ALTITUDE_ROCKET_GCC_NO_CONTRACT
#endif

#ifdef __cplusplus
}
#endif

#endif
