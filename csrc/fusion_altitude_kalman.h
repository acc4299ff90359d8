/**
 * @file fusion_altitude_kalman.h
 * @brief Multi-sensor altitude Kalman filter: barometer, rangefinder and GPS
 * altitude fused with vertical acceleration, with ground-offset states,
 * innovation gating and fault handling.
 *
 * Header-only C99 (also valid C++), float32 only, no malloc, no globals, no
 * libm. Needs fusion_altitude.h (float classification) next to it.
 *
 * Units and frame: heights and altitudes m, vertical velocity m/s,
 * acceleration m/s^2, time s. Vertical is +up; NED users negate.
 *
 * State x (index: quantity, unit):
 *   0 h   height above ground, m
 *   1 v   vertical velocity, m/s
 *   2 ob  baro offset: the baro reads h + ob, m
 *   3 og  GPS offset: GPS altitude reads h + og, m
 *   4 b   accelerometer bias, m/s^2 (subtracted from the accel input)
 *
 * Prediction over dt with the vertical acceleration a as control input
 * (u = a - b):
 *   h += v*dt + u*dt^2/2,   v += u*dt,   ob, og, b constant
 *   F = I + dt*E01 - (dt^2/2)*E04 - dt*E14,   B = (dt^2/2, dt, 0, 0, 0)^T
 *   Q = N_a^2/dt * B*B^T  (accel white noise, density N_a, entering through B)
 *     + dt * diag(0, 0, N_ob^2, N_og^2, N_b^2)   (random walks)
 * Measurements (sequential scalar updates, in this order each step):
 *   baro  z = h + ob + noise   H = (1, 0, 1, 0, 0)
 *   range z = h + noise        H = (1, 0, 0, 0, 0)
 *   GPS   z = h + og + noise   H = (1, 0, 0, 1, 0)
 * Each scalar update: c = P*H^T, S = H*c + R, K = c/S, y = z - H*x,
 *   x += K*y,   P = P - K*c^T - c*K^T + S*K*K^T
 * The last line is the Joseph form (I-KH)P(I-KH)^T + K*R*K^T expanded; it
 * equals it for any K, so errors in K only reach P to second order, and it
 * is evaluated once per (i, j <= j) pair so P stays exactly symmetric.
 *
 * Offsets start unknown (infinite variance). The first sample of a sensor
 * sets its offset exactly as a Kalman update with an infinite prior does:
 * offset = z - h, var = P_hh + R, cov(offset, x_j) = -P_hj. No start-up
 * phase; absolute altitudes of thousands of metres are fine in float32.
 *
 * Gaps and recovery. A step with dt > gapPeriod (default 0.5 s) is a gap and
 * is not predicted with its accel sample (one sample says nothing about the
 * motion over the gap): x is kept, the gap count goes up, rejection streaks
 * end, and the covariance is inflated as if the velocity had taken a random
 * change of sigma V = FUSION_ALTITUDE_KALMAN_RESTART_VELOCITY_SIGMA over the
 * gap T = dt: P_hh += (V*T)^2, P_vv += V^2, plus the offset and bias random
 * walks over T. The samples of that step and the next ones then pass the
 * gate and pull h back within a few samples, and v within a few seconds,
 * while the offsets and the bias, whose variances barely grow, stay.
 * A sensor rejected for longer than rejectionTimeout is reset (offset, or
 * ground for the rangefinder) as before. If no sensor at all was fused
 * during the streak, h and v are first inflated the same way with T = the
 * length of the streak, and the bias variance (when estimated) by
 * accelBiasInitialSigma^2: a streak that nothing else contradicts means the
 * state, not only the sensor, is likely wrong (a velocity error after a gap,
 * a glitch burst the bias partly absorbed, a start in motion). A baro or GPS
 * sample is then fused with the inflated covariance (result Reset, counted
 * in resets) instead of re-basing its offset: a re-based offset absorbs the
 * height error and keeps the wrong velocity, so the next streak starts at
 * once, and on the Hedy rocket log (baro only, a gyro-integrated attitude
 * that is wrong under the drogue) such streaks chained into a velocity of
 * -4 km/s and a 4.1 km error in the descent, depending chaotically on a
 * 1 cm shift of the baro; fused, the same log gives 15.9 m RMS whatever the
 * shift (docs/kalman.md). The rangefinder resets its ground as before. While
 * another sensor is being fused the state is vouched for, and the streak is
 * the sensor's own (a GPS jump, a terrain step): only it is reset.
 *
 * Sensor timeouts. Each sensor has a timeout (baroTimeout 1.5 s, rangeTimeout
 * 0.5 s, gpsTimeout 2 s by default): once a sensor that has had a usable
 * sample has none for longer (T > timeout, T counted over predicted steps;
 * a gap's dt is counted as a gap, not here), it is flagged timed out and its
 * timeout count goes up by one (once per silence, as gaps are counted). A
 * NaN, an out-of-range rangefinder reading or a GPS fix with too few
 * satellites is no sample; a sample the gate rejects is one (the sensor is
 * alive; rejection streaks have their own timeout). The filter carries on
 * with the sensors left: with the baro timed out, GPS and rangefinder go on
 * correcting h and v, the baro offset ob is held with its random walk
 * growing, and the altitude h + ob follows them (the flag says the baro is not
 * in it). A timed-out sensor's next usable sample ends its timeout:
 *   - if another sensor was fused within the last timeout s, the state is
 *     vouched for and the sample is processed as usual: its offset's random
 *     walk has widened the gate over the silence (a 10 s baro dropout: 0.16 m
 *     more sigma), and an offset that jumped meanwhile is caught by the
 *     rejection streak and reset after rejectionTimeout. (PX4's EKF2 re-bases
 *     a height source's bias when it restarts its fusion; here the offset
 *     state carries over, which on a 10 s baro dropout bridged by the
 *     rangefinder keeps the altitude continuous to 5 cm where re-basing on
 *     one noisy sample did not: tests/test_kalman_scenarios.py, (d).)
 *   - otherwise nothing has corrected h for T s: h and v are inflated as
 *     after a gap of T (and b by its initial variance) before the sample is
 *     processed, so it passes the gate and pulls h and v back at once: EKF2
 *     resets the height to the baro and the vertical velocity to zero when
 *     every height source has failed, and ArduPilot's EKF3 resets height
 *     after its height timeout (5 s).
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
 * FusionAltitudeKalman kalman;
 * FusionAltitudeKalmanInitialise(&kalman);            // default settings
 * for (;;) {
 *     FusionAltitudeKalmanMeasurements m = FusionAltitudeKalmanMeasurementsNone();
 *     if (baroReady) m.baroAltitude = baro;            // m
 *     if (rangeReady) m.rangeDistance = range;         // m
 *     if (gpsReady) { m.gpsAltitude = gpsAlt; m.gpsSatellites = satellites; }
 *     if (FusionAltitudeKalmanUpdate(&kalman, accel, 0.01f, &m) != FusionAltitudeKalmanStatusOk) {
 *         // input rejected, state unchanged
 *     }
 *     const float h = FusionAltitudeKalmanGetHeightAboveGround(&kalman);
 * }
 * @endcode
 */

#ifndef FUSION_ALTITUDE_KALMAN_H
#define FUSION_ALTITUDE_KALMAN_H

#include "fusion_altitude.h"

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
#define FUSION_ALTITUDE_KALMAN_GCC_NO_CONTRACT
#pragma GCC push_options
#pragma GCC optimize("fp-contract=off")
#endif

#if defined(__clang__)
#define FUSION_ALTITUDE_KALMAN_NO_CONTRACT _Pragma("clang fp contract(off)")
#else
#define FUSION_ALTITUDE_KALMAN_NO_CONTRACT
#endif

//------------------------------------------------------------------------------
// Definitions

/** Number of states. */
#define FUSION_ALTITUDE_KALMAN_STATES (5)

/**
 * 1: the Joseph-form covariance update is written out entry by entry
 * (constant indices, no loop or index arithmetic: 29 % fewer instructions
 * per three-sensor step on x86-64, docs/performance.md); 0: the loop over
 * the 15 distinct entries. Both give the same bits. Default 1 on 64-bit
 * hosts (x86-64, AArch64) unless optimising for size, 0 elsewhere: on a
 * Cortex-M4F at -O2 the written-out form is 1.3 kB more code. Define it to
 * 0 or 1 before including this header to choose.
 */
#ifndef FUSION_ALTITUDE_KALMAN_UNROLL
#if !defined(__OPTIMIZE_SIZE__) && (defined(__x86_64__) || defined(_M_X64) || defined(__aarch64__) || defined(_M_ARM64))
#define FUSION_ALTITUDE_KALMAN_UNROLL 1
#else
#define FUSION_ALTITUDE_KALMAN_UNROLL 0
#endif
#endif

/*
 * FUSION_ALTITUDE_KALMAN_VECTOR 1 (the default where FUSION_ALTITUDE_KALMAN_UNROLL
 * is 1 and the compiler is gcc or clang): the gain, state and Joseph-form
 * covariance updates run row by row on 4-float vectors (gcc/clang vector
 * extensions: SSE on x86-64, NEON on AArch64), each entry the same
 * operations in the same order as the loop, so the same bits; the
 * prediction's and the gate's 5-entry loops are unrolled and the gate is
 * inlined into each sensor's call. 1203 -> 727 instructions per
 * three-sensor step on x86-64 (docs/performance.md). Define it to 0 to use
 * the written-out form instead.
 */
#ifndef FUSION_ALTITUDE_KALMAN_VECTOR
#if FUSION_ALTITUDE_KALMAN_UNROLL && (defined(__GNUC__) || defined(__clang__))
#define FUSION_ALTITUDE_KALMAN_VECTOR 1
#else
#define FUSION_ALTITUDE_KALMAN_VECTOR 0
#endif
#endif

#if FUSION_ALTITUDE_KALMAN_VECTOR
typedef float FusionAltitudeKalmanVector4 __attribute__((vector_size(16)));
/* inlined into each of its three calls, so that the sensor's offset index is a constant there */
#define FUSION_ALTITUDE_KALMAN_ALWAYS_INLINE __attribute__((always_inline))
#else
#define FUSION_ALTITUDE_KALMAN_ALWAYS_INLINE
#endif

/** Number of altitude sensors (baro, rangefinder, GPS). */
#define FUSION_ALTITUDE_KALMAN_SENSORS (3)

/**
 * Velocity sigma, m/s, of the random velocity change assumed over a gap or a
 * rejection streak longer than the timeout (see the file comment): faster
 * than a multirotor climbs or descends, so the next samples are accepted.
 */
#define FUSION_ALTITUDE_KALMAN_RESTART_VELOCITY_SIGMA (10.0f)

/** Satellite counts above this use its 1/sqrt(n) (the table's last entry). */
#define FUSION_ALTITUDE_KALMAN_MAX_SATELLITES (64)

/** State indices. */
typedef enum {
    FusionAltitudeKalmanStateHeight = 0,  /**< h, m, height above ground */
    FusionAltitudeKalmanStateVelocity,    /**< v, m/s, +up */
    FusionAltitudeKalmanStateBaroOffset,  /**< ob, m: baro reads h + ob */
    FusionAltitudeKalmanStateGpsOffset,   /**< og, m: GPS reads h + og */
    FusionAltitudeKalmanStateAccelBias,   /**< b, m/s^2, +up */
} FusionAltitudeKalmanState;

/** Sensor indices. */
typedef enum {
    FusionAltitudeKalmanSensorBaro = 0,
    FusionAltitudeKalmanSensorRange,
    FusionAltitudeKalmanSensorGps,
} FusionAltitudeKalmanSensorIndex;

/** What the latest update did with a sensor's sample. */
typedef enum {
    FusionAltitudeKalmanResultNoSample = 0, /**< no sample this step (NaN) */
    FusionAltitudeKalmanResultFused,        /**< passed the gate and fused */
    FusionAltitudeKalmanResultRejected,     /**< failed the gate, not fused */
    FusionAltitudeKalmanResultReset,        /**< failed the gate for longer than the timeout: offset (range: ground) reset, or with nothing fused during the streak h, v inflated and the sample fused */
    FusionAltitudeKalmanResultInitialised,  /**< first sample: offset set from it */
    FusionAltitudeKalmanResultUnusable,     /**< range outside [min, max] or too few GPS satellites */
} FusionAltitudeKalmanResult;

/** Status returned by every function that can reject its input. */
typedef enum {
    FusionAltitudeKalmanStatusOk = 0,
    FusionAltitudeKalmanStatusInvalidAccel,         /**< accel not finite */
    FusionAltitudeKalmanStatusInvalidDt,            /**< dt not finite or <= 0 */
    FusionAltitudeKalmanStatusInvalidBaroAltitude,  /**< baro altitude infinite */
    FusionAltitudeKalmanStatusInvalidGpsAltitude,   /**< GPS altitude infinite */
    FusionAltitudeKalmanStatusInvalidGpsAccuracy,   /**< GPS vertical accuracy given (not NaN) but not finite and > 0 */
    FusionAltitudeKalmanStatusInvalidNoise,         /**< a noise, random walk or initial sigma not in [0, 1e6], or 0 where it must be > 0 */
    FusionAltitudeKalmanStatusInvalidRange,         /**< range limits not finite or not 0 <= min < max */
    FusionAltitudeKalmanStatusInvalidGps,           /**< GPS model: base or satellite term not finite or < 0, base + satellite term 0, or min satellites < 0 */
    FusionAltitudeKalmanStatusInvalidGate,          /**< gate not finite or <= 0, or timeout not finite or < 0 */
    FusionAltitudeKalmanStatusInvalidGroundEffect,  /**< ground-effect noise scale not finite or < 1, dead zone not finite or < 0 */
    FusionAltitudeKalmanStatusInvalidGapPeriod,     /**< gap period NaN or <= 0 (+infinity: never a gap) */
    FusionAltitudeKalmanStatusInvalidTimeout,       /**< a sensor timeout not in (0, 1e6] */
} FusionAltitudeKalmanStatus;

/** Settings, all in physical units. */
typedef struct {
    float accelNoise;            /**< N_a, m/s^2/sqrt(Hz): accelerometer white-noise density (with vibration) [rule: finite, >= 0, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; else InvalidNoise] */
    float accelBiasRandomWalk;   /**< N_b, m/s^3/sqrt(Hz): accel bias random walk [rule: finite, >= 0, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; else InvalidNoise] */
    float accelBiasInitialSigma; /**< m/s^2: initial bias uncertainty [rule: finite, >= 0, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; else InvalidNoise] */
    bool estimateAccelBias;      /**< false: bias state held at 0, not estimated [rule: any] */
    float baroNoise;             /**< m, 1 sigma per baro sample (> 0) [rule: finite, > 0, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; else InvalidNoise] */
    float baroOffsetRandomWalk;  /**< N_ob, m/sqrt(s): weather and temperature drift of the baro [rule: finite, >= 0, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; else InvalidNoise] */
    float rangeNoise;            /**< m, 1 sigma per rangefinder sample (> 0) [rule: finite, > 0, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; else InvalidNoise] */
    float rangeMinimum;          /**< m: readings below are "no echo" [rule: finite, >= 0, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; else InvalidRange] */
    float rangeMaximum;          /**< m: readings above are "no echo" [rule: finite, > 0, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING, > rangeMinimum; else InvalidRange] */
    float gpsNoiseBase;          /**< m: GPS sigma = base + satellite / sqrt(n) [rule: finite, >= 0, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; else InvalidGps] */
    float gpsNoiseSatellite;     /**< m: see gpsNoiseBase [rule: finite, >= 0, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; else InvalidGps] */
    int32_t gpsMinimumSatellites; /**< fewer satellites: GPS not fused [rule: >= 0; else InvalidGps] */
    float gpsOffsetRandomWalk;   /**< N_og, m/sqrt(s): GPS altitude wander [rule: finite, >= 0, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; else InvalidNoise] */
    float gate;                  /**< innovation gate, sigmas: rejected if y^2 > gate^2 * S [rule: finite, > 0, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; else InvalidGate] */
    float rejectionTimeout;      /**< s: a sensor rejected for longer is reset [rule: finite, >= 0, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; else InvalidGate] */
    float groundEffectNoiseScale; /**< baro sigma multiplier while the ground-effect flag is set (>= 1) [rule: finite, >= 1, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; else InvalidGroundEffect] */
    float groundEffectDeadZone;  /**< m: negative baro innovations up to this are ignored in ground effect [rule: finite, >= 0, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; else InvalidGroundEffect] */
    float initialHeightSigma;    /**< m: initial height uncertainty (on the ground) [rule: finite, >= 0, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; else InvalidNoise] */
    float initialVelocitySigma;  /**< m/s: initial velocity uncertainty (at rest) [rule: finite, >= 0, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; else InvalidNoise] */
    float gapPeriod;             /**< s: an update whose dt exceeds this is a gap, not integrated (default 0.5 s) [rule: > 0; else InvalidGapPeriod] */
    float baroTimeout;           /**< s, > 0: the baro is timed out after this long without a sample (default 1.5 s) [rule: finite, > 0, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; else InvalidTimeout] */
    float rangeTimeout;          /**< s, > 0: the rangefinder is timed out after this long without a usable reading (default 0.5 s) [rule: finite, > 0, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; else InvalidTimeout] */
    float gpsTimeout;            /**< s, > 0: the GPS is timed out after this long without a usable fix (default 2 s) [rule: finite, > 0, <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; else InvalidTimeout] */
} FusionAltitudeKalmanSettings;

/** One update's samples. NaN means "no sample this step". */
typedef struct {
    float baroAltitude;        /**< m; NaN: none */
    float rangeDistance;       /**< m, height above ground; NaN or outside [min, max]: no echo */
    float gpsAltitude;         /**< m; NaN: none */
    float gpsVerticalAccuracy; /**< m, 1 sigma reported by the receiver; NaN: not reported (satellite model) */
    int32_t gpsSatellites;     /**< satellites used; negative: unknown */
    bool groundEffect;         /**< take-off or landing: widen baro noise, dead zone on negative baro innovations */
} FusionAltitudeKalmanMeasurements;

/** Per-sensor diagnostics. */
typedef struct {
    float innovation;         /**< y = z - H*x of the latest sample before its correction, m (after the ground-effect dead zone); NaN if none tested */
    float innovationVariance; /**< S = H*P*H^T + R, m^2; NaN if none tested (y^2/S: FusionAltitudeKalmanGetNis) */
    float rejectingFor;       /**< s since the first sample of the current rejection streak; 0 when not rejecting */
    float sinceSample;        /**< s since the latest usable sample (predicted steps only) */
    uint32_t rejections;      /**< samples rejected by the gate, in total */
    uint32_t resets;          /**< resets after a rejection streak longer than the timeout, in total */
    uint32_t timeouts;        /**< silences longer than the sensor's timeout, in total (each counted once) */
    uint8_t result;           /**< what the latest update did with this sensor: a FusionAltitudeKalmanResult (one byte: the filter fits in 320) */
    bool rejecting;           /**< a rejection streak is in progress */
    bool sampled;             /**< the sensor has had a usable sample */
    bool timedOut;            /**< no usable sample for longer than the sensor's timeout (until its next one) */
} FusionAltitudeKalmanSensor;

/** Filter state. Read it through the Get functions. */
typedef struct {
    FusionAltitudeKalmanSettings settings;
    float x[FUSION_ALTITUDE_KALMAN_STATES];                               /**< state, see the file comment */
    float P[FUSION_ALTITUDE_KALMAN_STATES][FUSION_ALTITUDE_KALMAN_STATES]; /**< covariance, exactly symmetric */
    FusionAltitudeKalmanSensor sensors[FUSION_ALTITUDE_KALMAN_SENSORS];    /**< baro, range, GPS */
    float sinceFused;         /**< s since any sensor's sample was last fused */
    uint32_t gapCount;        /**< updates with dt > gapPeriod so far */
    bool baroInitialised;     /**< baro offset set (first baro sample seen) */
    bool gpsInitialised;      /**< GPS offset set (first usable GPS sample seen) */
} FusionAltitudeKalman;

//------------------------------------------------------------------------------
// Status messages

/** @return a short English description of the status, never NULL. */
static inline const char *FusionAltitudeKalmanStatusMessage(const FusionAltitudeKalmanStatus status) {
    static const char *const texts[] = { /* in the enum's order */
        "ok", /* FusionAltitudeKalmanStatusOk */
        "accel must be finite", /* FusionAltitudeKalmanStatusInvalidAccel */
        "dt must be finite and > 0", /* FusionAltitudeKalmanStatusInvalidDt */
        "baro altitude must be finite (or NaN for no sample)", /* FusionAltitudeKalmanStatusInvalidBaroAltitude */
        "GPS altitude must be finite (or NaN for no sample)", /* FusionAltitudeKalmanStatusInvalidGpsAltitude */
        "GPS vertical accuracy must be finite and > 0 (or NaN if not reported)", /* FusionAltitudeKalmanStatusInvalidGpsAccuracy */
        "noises, random walks and initial sigmas must be in [0, 1e6] (baro and range noise > 0)", /* FusionAltitudeKalmanStatusInvalidNoise */
        "range limits must satisfy 0 <= minimum < maximum <= 1e6", /* FusionAltitudeKalmanStatusInvalidRange */
        "GPS noise terms must be in [0, 1e6] with a positive sum, minimum satellites >= 0", /* FusionAltitudeKalmanStatusInvalidGps */
        "gate must be in (0, 1e6], rejection timeout in [0, 1e6]", /* FusionAltitudeKalmanStatusInvalidGate */
        "ground-effect noise scale must be >= 1 with baro noise * scale <= 1e6, dead zone in [0, 1e6]", /* FusionAltitudeKalmanStatusInvalidGroundEffect */
        "gap period must be > 0 (+infinity: never a gap)", /* FusionAltitudeKalmanStatusInvalidGapPeriod */
        "sensor timeouts must be in (0, 1e6] s", /* FusionAltitudeKalmanStatusInvalidTimeout */
    };
    return FusionAltitudeStatusText(texts, sizeof(texts) / sizeof(texts[0]), (size_t) status);
}

//------------------------------------------------------------------------------
// Settings

/**
 * @return the default settings (multirotor):
 *   accelNoise 0.035 m/s^2/sqrt(Hz) (0.35 m/s^2 per sample at 100 Hz),
 *   accelBiasRandomWalk 0.003 m/s^3/sqrt(Hz), accelBiasInitialSigma 0.2 m/s^2,
 *   estimateAccelBias true, baroNoise 0.5 m, baroOffsetRandomWalk 0.05 m/sqrt(s),
 *   rangeNoise 0.05 m, range 0.1 .. 8 m, GPS sigma 1 + 1/sqrt(n) m with at
 *   least 4 satellites, gpsOffsetRandomWalk 0.1 m/sqrt(s), gate 5 sigma,
 *   rejectionTimeout 1 s, ground effect x3 baro sigma and 0.5 m dead zone,
 *   initial height sigma 0.1 m, initial velocity sigma 1 m/s (robust to a start in motion),
 *   gap period 0.5 s (50 samples at 100 Hz, 5 at 10 Hz; a 1 Hz log needs a longer one),
 *   sensor timeouts: baro 1.5 s (longer than the 1 s period of a balloon's
 *   1 Hz baro, three periods of a 2 Hz one; PX4's EKF2 drops a baro after
 *   0.4 s, made for its 20+ Hz baros), rangefinder 0.5 s (5 periods at 10 Hz:
 *   a rangefinder above its range stops at once), GPS 2 s (two periods of a
 *   1 Hz receiver, ten of a 5 Hz one).
 */
static inline FusionAltitudeKalmanSettings FusionAltitudeKalmanSettingsDefault(void) {
    FusionAltitudeKalmanSettings settings;
    settings.accelNoise = 0.035f;
    settings.accelBiasRandomWalk = 0.003f;
    settings.accelBiasInitialSigma = 0.2f;
    settings.estimateAccelBias = true;
    settings.baroNoise = 0.5f;
    settings.baroOffsetRandomWalk = 0.05f;
    settings.rangeNoise = 0.05f;
    settings.rangeMinimum = 0.1f;
    settings.rangeMaximum = 8.0f;
    settings.gpsNoiseBase = 1.0f;
    settings.gpsNoiseSatellite = 1.0f;
    settings.gpsMinimumSatellites = 4;
    settings.gpsOffsetRandomWalk = 0.1f;
    settings.gate = 5.0f;
    settings.rejectionTimeout = 1.0f;
    settings.groundEffectNoiseScale = 3.0f;
    settings.groundEffectDeadZone = 0.5f;
    settings.initialHeightSigma = 0.1f;
    settings.initialVelocitySigma = 1.0f;
    settings.gapPeriod = 0.5f;
    settings.baroTimeout = 1.5f;
    settings.rangeTimeout = 0.5f;
    settings.gpsTimeout = 2.0f;
    return settings;
}

/**
 * Largest accepted setting (noise, random walk, sigma, gate, range, time):
 * squared it stays below 1e12, far inside float32, so a finite setting can
 * never overflow the covariance to infinity on its first use.
 */
#define FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING (1e6f)

/** Checks the settings; the statuses name the group of the first bad field. */
static inline FusionAltitudeKalmanStatus FusionAltitudeKalmanSettingsCheck(const FusionAltitudeKalmanSettings *const s) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    const float limit = FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING; /* largest accepted setting */
    if (!FusionAltitudeIsNonNegative(s->accelNoise, limit) || !FusionAltitudeIsNonNegative(s->accelBiasRandomWalk, limit) ||
        !FusionAltitudeIsNonNegative(s->accelBiasInitialSigma, limit) || !FusionAltitudeIsPositive(s->baroNoise, limit) ||
        !FusionAltitudeIsNonNegative(s->baroOffsetRandomWalk, limit) || !FusionAltitudeIsPositive(s->rangeNoise, limit) ||
        !FusionAltitudeIsNonNegative(s->gpsOffsetRandomWalk, limit) || !FusionAltitudeIsNonNegative(s->initialHeightSigma, limit) ||
        !FusionAltitudeIsNonNegative(s->initialVelocitySigma, limit)) {
        return FusionAltitudeKalmanStatusInvalidNoise;
    }
    if (!FusionAltitudeIsNonNegative(s->rangeMinimum, limit) || !FusionAltitudeIsPositive(s->rangeMaximum, limit) ||
        !(s->rangeMaximum > s->rangeMinimum)) {
        return FusionAltitudeKalmanStatusInvalidRange;
    }
    if (!FusionAltitudeIsNonNegative(s->gpsNoiseBase, limit) || !FusionAltitudeIsNonNegative(s->gpsNoiseSatellite, limit) ||
        !(s->gpsNoiseBase + s->gpsNoiseSatellite > 0.0f) || (s->gpsMinimumSatellites < 0)) {
        return FusionAltitudeKalmanStatusInvalidGps;
    }
    if (!FusionAltitudeIsPositive(s->gate, limit) || !FusionAltitudeIsNonNegative(s->rejectionTimeout, limit)) {
        return FusionAltitudeKalmanStatusInvalidGate;
    }
    if (!FusionAltitudeIsPositive(s->groundEffectNoiseScale, limit) || !(s->groundEffectNoiseScale >= 1.0f) ||
        !FusionAltitudeIsNonNegative(s->groundEffectDeadZone, limit) ||
        !(s->baroNoise * s->groundEffectNoiseScale <= FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING)) {
        return FusionAltitudeKalmanStatusInvalidGroundEffect;
    }
    if (!(s->gapPeriod > 0.0f)) { /* false for NaN */
        return FusionAltitudeKalmanStatusInvalidGapPeriod;
    }
    if (!FusionAltitudeIsPositive(s->baroTimeout, limit) || !FusionAltitudeIsPositive(s->rangeTimeout, limit) ||
        !FusionAltitudeIsPositive(s->gpsTimeout, limit)) {
        return FusionAltitudeKalmanStatusInvalidTimeout;
    }
    return FusionAltitudeKalmanStatusOk;
}

/** @return measurements with no sample of any sensor (all NaN, satellites unknown, no ground effect). */
static inline FusionAltitudeKalmanMeasurements FusionAltitudeKalmanMeasurementsNone(void) {
    FusionAltitudeKalmanMeasurements m;
    m.baroAltitude = FusionAltitudeNaN();
    m.rangeDistance = FusionAltitudeNaN();
    m.gpsAltitude = FusionAltitudeNaN();
    m.gpsVerticalAccuracy = FusionAltitudeNaN();
    m.gpsSatellites = -1;
    m.groundEffect = false;
    return m;
}

//------------------------------------------------------------------------------
// Estimator

/**
 * @brief Initialises the filter with the given settings (NULL: defaults;
 * rejected with the filter untouched if they fail the check): on the ground
 * and at rest, h = v = 0 with the initial sigmas, bias 0 with its initial
 * sigma (0 if not estimated), offsets unknown until each sensor's first sample.
 */
static inline FusionAltitudeKalmanStatus FusionAltitudeKalmanInitialiseWith(FusionAltitudeKalman *const kalman,
                                                                            const FusionAltitudeKalmanSettings *const settings) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    const FusionAltitudeKalmanSettings s = (settings == NULL) ? FusionAltitudeKalmanSettingsDefault() : *settings;
    const FusionAltitudeKalmanStatus status = FusionAltitudeKalmanSettingsCheck(&s);
    if (status != FusionAltitudeKalmanStatusOk) {
        return status;
    }
    memset(kalman, 0, sizeof(*kalman));
    kalman->settings = s;
    kalman->P[FusionAltitudeKalmanStateHeight][FusionAltitudeKalmanStateHeight] = s.initialHeightSigma * s.initialHeightSigma;
    kalman->P[FusionAltitudeKalmanStateVelocity][FusionAltitudeKalmanStateVelocity] = s.initialVelocitySigma * s.initialVelocitySigma;
    kalman->P[FusionAltitudeKalmanStateAccelBias][FusionAltitudeKalmanStateAccelBias] = s.estimateAccelBias ? (s.accelBiasInitialSigma * s.accelBiasInitialSigma) : 0.0f;
    for (int i = 0; i < FUSION_ALTITUDE_KALMAN_SENSORS; i++) {
        kalman->sensors[i].innovation = FusionAltitudeNaN();
        kalman->sensors[i].innovationVariance = FusionAltitudeNaN();
        kalman->sensors[i].result = (uint8_t) FusionAltitudeKalmanResultNoSample;
    }
    return FusionAltitudeKalmanStatusOk;
}

/** @brief Initialises the filter with the default settings. */
static inline void FusionAltitudeKalmanInitialise(FusionAltitudeKalman *const kalman) {
    (void) FusionAltitudeKalmanInitialiseWith(kalman, NULL);
}

/**
 * @brief Replaces the settings, keeping the state. Turning bias estimation off
 * sets b = 0 and clears its covariance row; turning it on starts b with its
 * initial sigma, uncorrelated. Rejected (state unchanged) if the check fails.
 */
static inline FusionAltitudeKalmanStatus FusionAltitudeKalmanSetSettings(FusionAltitudeKalman *const kalman,
                                                                         const FusionAltitudeKalmanSettings *const settings) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    const FusionAltitudeKalmanStatus status = FusionAltitudeKalmanSettingsCheck(settings);
    if (status != FusionAltitudeKalmanStatusOk) {
        return status;
    }
    if (settings->estimateAccelBias != kalman->settings.estimateAccelBias) {
        kalman->x[FusionAltitudeKalmanStateAccelBias] = 0.0f;
        for (int i = 0; i < FUSION_ALTITUDE_KALMAN_STATES; i++) {
            kalman->P[i][FusionAltitudeKalmanStateAccelBias] = 0.0f;
            kalman->P[FusionAltitudeKalmanStateAccelBias][i] = 0.0f;
        }
        if (settings->estimateAccelBias) {
            kalman->P[FusionAltitudeKalmanStateAccelBias][FusionAltitudeKalmanStateAccelBias] = settings->accelBiasInitialSigma * settings->accelBiasInitialSigma;
        }
    }
    kalman->settings = *settings;
    return FusionAltitudeKalmanStatusOk;
}

/** @internal @brief Adds the random walks over dt (s): offsets only once they exist, the bias only if estimated. */
static inline void FusionAltitudeKalmanRandomWalks(FusionAltitudeKalman *const k, const float dt) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    if (k->baroInitialised) {
        k->P[FusionAltitudeKalmanStateBaroOffset][FusionAltitudeKalmanStateBaroOffset] += (k->settings.baroOffsetRandomWalk * k->settings.baroOffsetRandomWalk) * dt;
    }
    if (k->gpsInitialised) {
        k->P[FusionAltitudeKalmanStateGpsOffset][FusionAltitudeKalmanStateGpsOffset] += (k->settings.gpsOffsetRandomWalk * k->settings.gpsOffsetRandomWalk) * dt;
    }
    if (k->settings.estimateAccelBias) {
        k->P[FusionAltitudeKalmanStateAccelBias][FusionAltitudeKalmanStateAccelBias] += (k->settings.accelBiasRandomWalk * k->settings.accelBiasRandomWalk) * dt;
    }
}

/** @internal
 * @brief Prediction over dt (s) with vertical acceleration accel (m/s^2):
 * x = F*x + B*accel, P = F*P*F^T + Q (see the file comment). Only rows and
 * columns h and v of P change through F; the 15 distinct entries are formed
 * once and mirrored. Internal: inputs are already checked.
 */
static inline void FusionAltitudeKalmanPredict(FusionAltitudeKalman *const k, const float accel, const float dt) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    float(*const P)[FUSION_ALTITUDE_KALMAN_STATES] = k->P;
    const float halfDt2 = 0.5f * dt * dt;
    // State
    const float u = accel - k->x[FusionAltitudeKalmanStateAccelBias];
    k->x[FusionAltitudeKalmanStateHeight] = k->x[FusionAltitudeKalmanStateHeight] + k->x[FusionAltitudeKalmanStateVelocity] * dt + u * halfDt2;
    k->x[FusionAltitudeKalmanStateVelocity] = k->x[FusionAltitudeKalmanStateVelocity] + u * dt;
    // A = row h of F*P, Bv = row v of F*P (the other rows of F*P are those of P)
    float A[FUSION_ALTITUDE_KALMAN_STATES];
    float Bv[FUSION_ALTITUDE_KALMAN_STATES];
#if FUSION_ALTITUDE_KALMAN_VECTOR
#pragma GCC unroll 5
#endif
    for (int j = 0; j < FUSION_ALTITUDE_KALMAN_STATES; j++) {
        A[j] = P[FusionAltitudeKalmanStateHeight][j] + dt * P[FusionAltitudeKalmanStateVelocity][j] - halfDt2 * P[FusionAltitudeKalmanStateAccelBias][j];
        Bv[j] = P[FusionAltitudeKalmanStateVelocity][j] - dt * P[FusionAltitudeKalmanStateAccelBias][j];
    }
    // (F*P)*F^T: columns h and v change the same way
    const float q = k->settings.accelNoise * k->settings.accelNoise;
    const float qvv = q * dt;                 // N_a^2 dt
    const float qhv = qvv * (0.5f * dt);      // N_a^2 dt^2 / 2
    const float qhh = qhv * (0.5f * dt);      // N_a^2 dt^3 / 4
    const float phh = A[FusionAltitudeKalmanStateHeight] + dt * A[FusionAltitudeKalmanStateVelocity] - halfDt2 * A[FusionAltitudeKalmanStateAccelBias] + qhh;
    const float phv = A[FusionAltitudeKalmanStateVelocity] - dt * A[FusionAltitudeKalmanStateAccelBias] + qhv;
    const float pvv = Bv[FusionAltitudeKalmanStateVelocity] - dt * Bv[FusionAltitudeKalmanStateAccelBias] + qvv;
    P[FusionAltitudeKalmanStateHeight][FusionAltitudeKalmanStateHeight] = phh;
    P[FusionAltitudeKalmanStateHeight][FusionAltitudeKalmanStateVelocity] = phv;
    P[FusionAltitudeKalmanStateVelocity][FusionAltitudeKalmanStateHeight] = phv;
    P[FusionAltitudeKalmanStateVelocity][FusionAltitudeKalmanStateVelocity] = pvv;
    for (int j = 2; j < FUSION_ALTITUDE_KALMAN_STATES; j++) {
        P[FusionAltitudeKalmanStateHeight][j] = A[j];
        P[j][FusionAltitudeKalmanStateHeight] = A[j];
        P[FusionAltitudeKalmanStateVelocity][j] = Bv[j];
        P[j][FusionAltitudeKalmanStateVelocity] = Bv[j];
    }
    FusionAltitudeKalmanRandomWalks(k, dt);
    for (int i = 0; i < FUSION_ALTITUDE_KALMAN_SENSORS; i++) {
        if (k->sensors[i].rejecting) {
            k->sensors[i].rejectingFor += dt;
        }
        k->sensors[i].sinceSample += dt;
    }
    k->sinceFused += dt;
}

/** @internal
 * @brief Inflates the height and velocity variances for a random velocity
 * change of sigma V = FUSION_ALTITUDE_KALMAN_RESTART_VELOCITY_SIGMA over T s:
 * P_hh += (V*T)^2, P_vv += V^2 (adding to the diagonal keeps P symmetric
 * and positive definite). Used after a gap and before a reset.
 */
static inline void FusionAltitudeKalmanInflate(FusionAltitudeKalman *const k, const float T) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    const float heightSigma = FUSION_ALTITUDE_KALMAN_RESTART_VELOCITY_SIGMA * T;
    k->P[FusionAltitudeKalmanStateHeight][FusionAltitudeKalmanStateHeight] += heightSigma * heightSigma;
    k->P[FusionAltitudeKalmanStateVelocity][FusionAltitudeKalmanStateVelocity] += FUSION_ALTITUDE_KALMAN_RESTART_VELOCITY_SIGMA * FUSION_ALTITUDE_KALMAN_RESTART_VELOCITY_SIGMA;
}

/** @internal
 * @brief A gap of dt s (see the file comment): x kept, P inflated, the random
 * walks over dt added, rejection streaks ended, the gap counted.
 */
static inline void FusionAltitudeKalmanGap(FusionAltitudeKalman *const k, const float dt) {
    FusionAltitudeKalmanInflate(k, dt);
    FusionAltitudeKalmanRandomWalks(k, dt);
    for (int i = 0; i < FUSION_ALTITUDE_KALMAN_SENSORS; i++) {
        k->sensors[i].rejecting = false;
        k->sensors[i].rejectingFor = 0.0f;
    }
    k->sinceFused += dt;
    k->gapCount++;
}

#if FUSION_ALTITUDE_KALMAN_VECTOR
/** @internal
 * @brief FusionAltitudeKalmanFuse on 4-float vectors (FUSION_ALTITUDE_KALMAN_VECTOR):
 * K = c / S (as c * (1/S)), x += K y (m, m/s, m/s^2, m, m), P = P - K c^T - c K^T
 * + (S K) K^T, the bits of FusionAltitudeKalmanFuseScalar.
 */
static inline void FusionAltitudeKalmanFuseVector(FusionAltitudeKalman *const k, const float c[FUSION_ALTITUDE_KALMAN_STATES],
                                                  const float S, const float y) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    const float inverseS = 1.0f / S;
    /* K_i = c_i / S (as c_i * (1/S)), S K_i and x_i += K_i y lane by lane,
     * then P row by row: rows i = 0..4, columns 1..4 as one 4-float vector
     * each, lane j holding P_ij - K_i c_j - c_i K_j + (S K_i) K_j, the
     * loop's expression in the loop's order, so the entries with j >= i get
     * the loop's bits; the lanes with j < i are computed but replaced by
     * their mirror P_ji, as in the loop. */
    FusionAltitudeKalmanVector4 cv;
    FusionAltitudeKalmanVector4 xv;
    memcpy(&cv, &c[1], sizeof(cv));
    memcpy(&xv, &k->x[1], sizeof(xv));
    const FusionAltitudeKalmanVector4 inverseSv = {inverseS, inverseS, inverseS, inverseS};
    const FusionAltitudeKalmanVector4 Sv = {S, S, S, S};
    const FusionAltitudeKalmanVector4 yv = {y, y, y, y};
    const FusionAltitudeKalmanVector4 Kv = cv * inverseSv;
    const FusionAltitudeKalmanVector4 sKv = Sv * Kv;
    const float c0 = c[0];
    const float K0 = c0 * inverseS;
    const float sK0 = S * K0;
    k->x[0] += K0 * y;
    xv += Kv * yv;
    memcpy(&k->x[1], &xv, sizeof(xv));
    FusionAltitudeKalmanVector4 rows[FUSION_ALTITUDE_KALMAN_STATES];
#pragma GCC unroll 5
    for (int i = 0; i < FUSION_ALTITUDE_KALMAN_STATES; i++) {
        const float Kis = (i == 0) ? K0 : Kv[i - 1];
        const float cis = (i == 0) ? c0 : cv[i - 1];
        const float sKis = (i == 0) ? sK0 : sKv[i - 1];
        const FusionAltitudeKalmanVector4 Ki = {Kis, Kis, Kis, Kis};
        const FusionAltitudeKalmanVector4 ci = {cis, cis, cis, cis};
        const FusionAltitudeKalmanVector4 sKi = {sKis, sKis, sKis, sKis};
        FusionAltitudeKalmanVector4 row;
        memcpy(&row, &k->P[i][1], sizeof(row));
        rows[i] = row - Ki * cv - ci * Kv + sKi * Kv;
    }
    k->P[0][0] = k->P[0][0] - K0 * c0 - c0 * K0 + sK0 * K0;
#pragma GCC unroll 5
    for (int i = 0; i < FUSION_ALTITUDE_KALMAN_STATES; i++) {
        memcpy(&k->P[i][1], &rows[i], sizeof(rows[i]));
    }
    k->P[1][0] = rows[0][0];
    k->P[2][0] = rows[0][1];
    k->P[3][0] = rows[0][2];
    k->P[4][0] = rows[0][3];
    k->P[2][1] = rows[1][1];
    k->P[3][1] = rows[1][2];
    k->P[4][1] = rows[1][3];
    k->P[3][2] = rows[2][2];
    k->P[4][2] = rows[2][3];
    k->P[4][3] = rows[3][3];
}
#else
/** @internal
 * @brief FusionAltitudeKalmanFuse element by element: K = c / S (as c * (1/S)),
 * x += K y (m, m/s, m/s^2, m, m), P = P - K c^T - c K^T + (S K) K^T.
 */
static inline void FusionAltitudeKalmanFuseScalar(FusionAltitudeKalman *const k, const float c[FUSION_ALTITUDE_KALMAN_STATES],
                                                  const float S, const float y) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    const float inverseS = 1.0f / S;
    float K[FUSION_ALTITUDE_KALMAN_STATES];
    float sK[FUSION_ALTITUDE_KALMAN_STATES];
    for (int i = 0; i < FUSION_ALTITUDE_KALMAN_STATES; i++) {
        K[i] = c[i] * inverseS;
        sK[i] = S * K[i];
        k->x[i] += K[i] * y;
    }
    /* P_ij = P_ij - K_i c_j - c_i K_j + (S K_i) K_j for the 15 entries with
     * j >= i, each mirrored to P_ji, row by row. With
     * FUSION_ALTITUDE_KALMAN_UNROLL (see its definition) the entries are
     * written out one by one: the same operations in the same order as the
     * loop, so the same bits. */
#if !FUSION_ALTITUDE_KALMAN_UNROLL
    for (int i = 0; i < FUSION_ALTITUDE_KALMAN_STATES; i++) {
        for (int j = i; j < FUSION_ALTITUDE_KALMAN_STATES; j++) {
            const float value = k->P[i][j] - K[i] * c[j] - c[i] * K[j] + sK[i] * K[j];
            k->P[i][j] = value;
            k->P[j][i] = value;
        }
    }
#else
#define FUSION_ALTITUDE_KALMAN_JOSEPH(i, j)                                           \
    do {                                                                              \
        const float value = k->P[i][j] - K[i] * c[j] - c[i] * K[j] + sK[i] * K[j];    \
        k->P[i][j] = value;                                                           \
        k->P[j][i] = value;                                                           \
    } while (0)
    FUSION_ALTITUDE_KALMAN_JOSEPH(0, 0);
    FUSION_ALTITUDE_KALMAN_JOSEPH(0, 1);
    FUSION_ALTITUDE_KALMAN_JOSEPH(0, 2);
    FUSION_ALTITUDE_KALMAN_JOSEPH(0, 3);
    FUSION_ALTITUDE_KALMAN_JOSEPH(0, 4);
    FUSION_ALTITUDE_KALMAN_JOSEPH(1, 1);
    FUSION_ALTITUDE_KALMAN_JOSEPH(1, 2);
    FUSION_ALTITUDE_KALMAN_JOSEPH(1, 3);
    FUSION_ALTITUDE_KALMAN_JOSEPH(1, 4);
    FUSION_ALTITUDE_KALMAN_JOSEPH(2, 2);
    FUSION_ALTITUDE_KALMAN_JOSEPH(2, 3);
    FUSION_ALTITUDE_KALMAN_JOSEPH(2, 4);
    FUSION_ALTITUDE_KALMAN_JOSEPH(3, 3);
    FUSION_ALTITUDE_KALMAN_JOSEPH(3, 4);
    FUSION_ALTITUDE_KALMAN_JOSEPH(4, 4);
#undef FUSION_ALTITUDE_KALMAN_JOSEPH
#endif
}
#endif

/** @internal
 * @brief Scalar update with H = e_h + e_offset (offset = 2 or 3) or H = e_h
 * (offset < 0), innovation y, noise variance R, in Joseph form (see the file
 * comment). c and S are passed in (already computed for the gate).
 */
static inline void FusionAltitudeKalmanFuse(FusionAltitudeKalman *const k, const float c[FUSION_ALTITUDE_KALMAN_STATES],
                                            const float S, const float y) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
#if FUSION_ALTITUDE_KALMAN_VECTOR
    FusionAltitudeKalmanFuseVector(k, c, S, y);
#else
    FusionAltitudeKalmanFuseScalar(k, c, S, y);
#endif
}

/** @internal
 * @brief Sets offset state o (2 or 3) from a sample z with noise variance R as
 * an update with an infinite prior on the offset: o = z - h,
 * P_oo = P_hh + R, P_oj = -P_hj (j != o). Used for the first sample and for a
 * reset after a rejection streak: h, v, b and the other offset are unchanged.
 */
static inline void FusionAltitudeKalmanSetOffset(FusionAltitudeKalman *const k, const int o, const float z, const float R) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    k->x[o] = z - k->x[FusionAltitudeKalmanStateHeight];
    for (int j = 0; j < FUSION_ALTITUDE_KALMAN_STATES; j++) {
        if (j != o) {
            const float value = -k->P[FusionAltitudeKalmanStateHeight][j];
            k->P[o][j] = value;
            k->P[j][o] = value;
        }
    }
    k->P[o][o] = k->P[FusionAltitudeKalmanStateHeight][FusionAltitudeKalmanStateHeight] + R;
}

/** @internal
 * @brief Terrain reset from a rangefinder sample z (variance R): the ground
 * moved under the vehicle, not the vehicle. h = z and every existing offset
 * takes up the difference d = z - h (o -= d), so h + o (the altitudes) do not
 * move. Covariance: x' = T*x + g*z with T the identity except row h = 0 and
 * o' = o + h, g = e_h - sum(e_o): P' = T*P*T^T + R*g*g^T.
 */
static inline void FusionAltitudeKalmanResetGround(FusionAltitudeKalman *const k, const float z, const float R) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    float(*const P)[FUSION_ALTITUDE_KALMAN_STATES] = k->P;
    const bool m[FUSION_ALTITUDE_KALMAN_STATES] = {false, false, k->baroInitialised, k->gpsInitialised, false};
    const float d = z - k->x[FusionAltitudeKalmanStateHeight];
    k->x[FusionAltitudeKalmanStateHeight] = z;
    for (int i = FusionAltitudeKalmanStateBaroOffset; i <= FusionAltitudeKalmanStateGpsOffset; i++) {
        if (m[i]) {
            k->x[i] = k->x[i] - d;
        }
    }
    float ph[FUSION_ALTITUDE_KALMAN_STATES];
    for (int j = 0; j < FUSION_ALTITUDE_KALMAN_STATES; j++) {
        ph[j] = P[FusionAltitudeKalmanStateHeight][j];
    }
    for (int i = 1; i < FUSION_ALTITUDE_KALMAN_STATES; i++) {
        for (int j = i; j < FUSION_ALTITUDE_KALMAN_STATES; j++) {
            float value = P[i][j];
            if (m[i]) {
                value = value + ph[j];
            }
            if (m[j]) {
                value = value + ph[i];
            }
            if (m[i] && m[j]) {
                value = value + ph[FusionAltitudeKalmanStateHeight] + R;
            }
            P[i][j] = value;
            P[j][i] = value;
        }
    }
    P[FusionAltitudeKalmanStateHeight][FusionAltitudeKalmanStateHeight] = R;
    for (int j = 1; j < FUSION_ALTITUDE_KALMAN_STATES; j++) {
        const float value = m[j] ? -R : 0.0f;
        P[FusionAltitudeKalmanStateHeight][j] = value;
        P[j][FusionAltitudeKalmanStateHeight] = value;
    }
}

/** @internal
 * @brief Gate, then fuse, reject or reset for one sample: offset o (2, 3, or
 * -1 for the rangefinder), innovation y (m), noise variance R (m^2). Rejected
 * if y^2/S > gate^2; a rejection streak older than the timeout resets
 * instead. If no sensor was fused during the streak, h and v are inflated
 * first (FusionAltitudeKalmanInflate over the streak) and b (its initial
 * variance), and a baro or GPS sample is then fused with that covariance
 * rather than re-basing its offset (result Reset all the same).
 */
static inline FUSION_ALTITUDE_KALMAN_ALWAYS_INLINE void FusionAltitudeKalmanProcess(FusionAltitudeKalman *const k, FusionAltitudeKalmanSensor *const sensor, const int o,
                                               const float z, const float y, const float R) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    float c[FUSION_ALTITUDE_KALMAN_STATES];
#if FUSION_ALTITUDE_KALMAN_VECTOR
#pragma GCC unroll 5
#endif
    for (int i = 0; i < FUSION_ALTITUDE_KALMAN_STATES; i++) {
        c[i] = (o < 0) ? k->P[i][FusionAltitudeKalmanStateHeight] : (k->P[i][FusionAltitudeKalmanStateHeight] + k->P[i][o]);
    }
    float S = ((o < 0) ? c[FusionAltitudeKalmanStateHeight] : (c[FusionAltitudeKalmanStateHeight] + c[o])) + R;
    const float nis = (y * y) / S;
    sensor->innovation = y;
    sensor->innovationVariance = S;
    FusionAltitudeKalmanResult result = FusionAltitudeKalmanResultFused;
    bool fuse = true;
    const float gate = k->settings.gate;
    if (nis > gate * gate) {
        sensor->rejections++;
        if (!sensor->rejecting) {
            sensor->rejecting = true;
            sensor->rejectingFor = 0.0f;
        }
        if (!(sensor->rejectingFor > k->settings.rejectionTimeout)) {
            sensor->result = (uint8_t) FusionAltitudeKalmanResultRejected;
            return;
        }
        result = FusionAltitudeKalmanResultReset;
        sensor->resets++;
        const bool suspect = k->sinceFused >= sensor->rejectingFor; /* nothing fused during the streak */
        if (suspect) {
            FusionAltitudeKalmanInflate(k, sensor->rejectingFor);
            if (k->settings.estimateAccelBias) {
                k->P[FusionAltitudeKalmanStateAccelBias][FusionAltitudeKalmanStateAccelBias] +=
                    k->settings.accelBiasInitialSigma * k->settings.accelBiasInitialSigma;
            }
        }
        if (!suspect || (o < 0)) { /* the sensor's own streak (or the rangefinder): reset it, no fusion */
            if (o < 0) {
                FusionAltitudeKalmanResetGround(k, z, R);
            } else {
                FusionAltitudeKalmanSetOffset(k, o, z, R);
            }
            fuse = false;
        } else {
            /* Suspect, baro or GPS: fused with the inflated P rather than re-basing the offset, which would keep
             * the wrong h and v (see the file comment). The inflation changed P_hh, P_vv and P_bb only, so of c
             * only c_h = P_hh + P_ho changes; c and S are then exactly what a recomputation from P gives. */
            c[FusionAltitudeKalmanStateHeight] = k->P[FusionAltitudeKalmanStateHeight][FusionAltitudeKalmanStateHeight] +
                                                 k->P[FusionAltitudeKalmanStateHeight][o];
            S = (c[FusionAltitudeKalmanStateHeight] + c[o]) + R;
            sensor->innovationVariance = S;
        }
    }
    if (fuse) {
        FusionAltitudeKalmanFuse(k, c, S, y);
        k->sinceFused = 0.0f;
    }
    sensor->rejecting = false;
    sensor->rejectingFor = 0.0f;
    sensor->result = (uint8_t) result;
}

/** @internal Marks a sensor as having no tested sample this step. */
static inline void FusionAltitudeKalmanNoSample(FusionAltitudeKalmanSensor *const sensor, const FusionAltitudeKalmanResult result) {
    sensor->innovation = FusionAltitudeNaN();
    sensor->innovationVariance = FusionAltitudeNaN();
    sensor->result = (uint8_t) result;
}

/** @internal
 * @brief A step without a usable sample of a sensor whose timeout is timeout
 * (s): once it has had one and T = sinceSample > timeout, it is flagged timed
 * out, and counted once per silence. NoSample sets the result.
 */
static inline void FusionAltitudeKalmanSilent(FusionAltitudeKalmanSensor *const sensor, const FusionAltitudeKalmanResult result,
                                              const float timeout) {
    FusionAltitudeKalmanNoSample(sensor, result);
    if (sensor->sampled && (sensor->sinceSample > timeout) && !sensor->timedOut) {
        sensor->timedOut = true;
        sensor->timeouts++;
    }
}

/** @internal
 * @brief A usable sample of a sensor with timeout (s) ends its silence. After
 * a timeout with no sensor fused within the last timeout s (see the file
 * comment), h and v are first inflated over the silence T (b by its initial
 * variance), so that the sample, then processed as usual, pulls them back.
 */
static inline void FusionAltitudeKalmanResume(FusionAltitudeKalman *const k, FusionAltitudeKalmanSensor *const sensor, const float timeout) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    if (sensor->timedOut && (k->sinceFused > timeout)) { /* nothing corrected h for the whole silence */
        FusionAltitudeKalmanInflate(k, sensor->sinceSample);
        if (k->settings.estimateAccelBias) {
            k->P[FusionAltitudeKalmanStateAccelBias][FusionAltitudeKalmanStateAccelBias] +=
                k->settings.accelBiasInitialSigma * k->settings.accelBiasInitialSigma;
        }
    }
    sensor->sampled = true;
    sensor->timedOut = false;
    sensor->sinceSample = 0.0f;
}

/** @internal
 * @return 1/sqrt(n) as float32 for n = 0..FUSION_ALTITUDE_KALMAN_MAX_SATELLITES
 * (n < 1 uses 1, larger n the last entry), from a table (no libm).
 */
static inline float FusionAltitudeKalmanInverseSqrt(const int32_t n) {
    static const float table[FUSION_ALTITUDE_KALMAN_MAX_SATELLITES + 1] = {
        1.0f, 1.0f, 0.70710677f, 0.57735026f, 0.5f, 0.4472136f, 0.4082483f, 0.37796447f,
        0.35355338f, 0.33333334f, 0.31622776f, 0.30151135f, 0.28867513f, 0.2773501f, 0.26726124f, 0.2581989f,
        0.25f, 0.24253562f, 0.23570226f, 0.22941573f, 0.2236068f, 0.2182179f, 0.21320072f, 0.2085144f,
        0.20412415f, 0.2f, 0.19611613f, 0.19245009f, 0.18898223f, 0.18569534f, 0.18257418f, 0.1796053f,
        0.17677669f, 0.17407766f, 0.17149858f, 0.16903085f, 0.16666667f, 0.16439898f, 0.16222142f, 0.16012815f,
        0.15811388f, 0.15617377f, 0.15430336f, 0.15249857f, 0.15075567f, 0.1490712f, 0.14744195f, 0.145865f,
        0.14433756f, 0.14285715f, 0.14142136f, 0.14002801f, 0.13867505f, 0.13736056f, 0.13608277f, 0.13483997f,
        0.13363062f, 0.13245323f, 0.13130644f, 0.13018891f, 0.12909944f, 0.12803689f, 0.12700012f, 0.12598816f,
        0.125f,
    };
    if (n < 1) {
        return 1.0f;
    }
    return table[(n > FUSION_ALTITUDE_KALMAN_MAX_SATELLITES) ? FUSION_ALTITUDE_KALMAN_MAX_SATELLITES : n];
}

/** @internal
 * @brief GPS noise sigma (m) for a sample: the receiver's vertical accuracy
 * when reported (not NaN), else base + satellite / sqrt(n) with n the
 * satellite count (unknown, i.e. negative: the minimum usable count).
 */
static inline float FusionAltitudeKalmanGpsSigma(const FusionAltitudeKalmanSettings *const s, const float verticalAccuracy,
                                                 const int32_t satellites) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    if (!FusionAltitudeIsNaN(verticalAccuracy)) {
        return verticalAccuracy;
    }
    const int32_t n = (satellites < 0) ? s->gpsMinimumSatellites : satellites;
    return s->gpsNoiseBase + s->gpsNoiseSatellite * FusionAltitudeKalmanInverseSqrt(n);
}

/** @internal
 * @brief Whether this step has a usable sample of a sensor with
 * timeout (s): present (not NaN) and usable (within the sensor's limits).
 * Without one the step only counts towards the timeout (FusionAltitudeKalmanSilent),
 * with the result no sample (not present) or unusable.
 */
static inline bool FusionAltitudeKalmanIsUsable(FusionAltitudeKalmanSensor *const sensor, const bool present, const bool usable,
                                                const float timeout) {
    if (present && usable) {
        return true;
    }
    FusionAltitudeKalmanSilent(sensor, present ? FusionAltitudeKalmanResultUnusable : FusionAltitudeKalmanResultNoSample, timeout);
    return false;
}

/** @internal
 * @brief A usable sample z (m) of a sensor with an offset state,
 * z = h + o, o the state at index o: it ends the sensor's silence
 * (FusionAltitudeKalmanResume, timeout s); the first sample after
 * initialisation sets o (*initialised becomes true), later ones are gated and
 * fused with variance R (m^2) and innovation y = z - (h + o), which the
 * ground-effect flag replaces, when negative, by min(y + deadZone, 0) (m; the
 * baro's rule).
 */
static inline void FusionAltitudeKalmanFuseOffsetSensor(FusionAltitudeKalman *const kalman, FusionAltitudeKalmanSensor *const sensor,
                                                        const int o, bool *const initialised, const float z, const float R,
                                                        const float timeout, const bool groundEffect, const float deadZone) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    FusionAltitudeKalmanResume(kalman, sensor, timeout);
    if (!*initialised) {
        FusionAltitudeKalmanSetOffset(kalman, o, z, R);
        *initialised = true;
        FusionAltitudeKalmanNoSample(sensor, FusionAltitudeKalmanResultInitialised);
        return;
    }
    float y = z - (kalman->x[FusionAltitudeKalmanStateHeight] + kalman->x[o]);
    if (groundEffect && (y < 0.0f)) {
        const float shifted = y + deadZone;
        y = (shifted < 0.0f) ? shifted : 0.0f;
    }
    FusionAltitudeKalmanProcess(kalman, sensor, o, z, y, R);
}

/** @internal
 * @brief Barometer, z = h + ob (m): R = baroNoise^2 (m^2), times
 * groundEffectNoiseScale^2 with the ground-effect flag, which also replaces a
 * negative innovation y (m) by min(y + groundEffectDeadZone, 0). The first
 * sample sets ob. baroPresent: m->baroAltitude is not NaN.
 */
static inline void FusionAltitudeKalmanProcessBaro(FusionAltitudeKalman *const kalman, const FusionAltitudeKalmanMeasurements *const m,
                                                   const bool baroPresent) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    const FusionAltitudeKalmanSettings *const s = &kalman->settings;
    FusionAltitudeKalmanSensor *const baro = &kalman->sensors[FusionAltitudeKalmanSensorBaro];
    if (FusionAltitudeKalmanIsUsable(baro, baroPresent, true, s->baroTimeout)) {
        const float sigma = m->groundEffect ? (s->baroNoise * s->groundEffectNoiseScale) : s->baroNoise;
        FusionAltitudeKalmanFuseOffsetSensor(kalman, baro, FusionAltitudeKalmanStateBaroOffset, &kalman->baroInitialised, m->baroAltitude,
                                             sigma * sigma, s->baroTimeout, m->groundEffect, s->groundEffectDeadZone);
    }
}

/** @internal
 * @brief Rangefinder, z = h (m): NaN or outside [rangeMinimum, rangeMaximum]
 * (m) is not fused; R = rangeNoise^2 (m^2).
 */
static inline void FusionAltitudeKalmanProcessRange(FusionAltitudeKalman *const kalman, const FusionAltitudeKalmanMeasurements *const m) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    const FusionAltitudeKalmanSettings *const s = &kalman->settings;
    FusionAltitudeKalmanSensor *const range = &kalman->sensors[FusionAltitudeKalmanSensorRange];
    const float z = m->rangeDistance;
    if (FusionAltitudeKalmanIsUsable(range, !FusionAltitudeIsNaN(z), (z >= s->rangeMinimum) && (z <= s->rangeMaximum), s->rangeTimeout)) {
        FusionAltitudeKalmanResume(kalman, range, s->rangeTimeout);
        FusionAltitudeKalmanProcess(kalman, range, -1, z, z - kalman->x[FusionAltitudeKalmanStateHeight], s->rangeNoise * s->rangeNoise);
    }
}

/** @internal
 * @brief GPS, z = h + og (m): fewer than gpsMinimumSatellites (when known) is
 * not fused; R = sigma^2 (m^2, FusionAltitudeKalmanGpsSigma). The first
 * sample sets og. gpsPresent: m->gpsAltitude is not NaN.
 */
static inline void FusionAltitudeKalmanProcessGps(FusionAltitudeKalman *const kalman, const FusionAltitudeKalmanMeasurements *const m,
                                                  const bool gpsPresent) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    const FusionAltitudeKalmanSettings *const s = &kalman->settings;
    FusionAltitudeKalmanSensor *const gps = &kalman->sensors[FusionAltitudeKalmanSensorGps];
    const bool enoughSatellites = (m->gpsSatellites < 0) || (m->gpsSatellites >= s->gpsMinimumSatellites); /* < 0: unknown */
    if (FusionAltitudeKalmanIsUsable(gps, gpsPresent, enoughSatellites, s->gpsTimeout)) {
        const float sigma = FusionAltitudeKalmanGpsSigma(s, m->gpsVerticalAccuracy, m->gpsSatellites);
        FusionAltitudeKalmanFuseOffsetSensor(kalman, gps, FusionAltitudeKalmanStateGpsOffset, &kalman->gpsInitialised, m->gpsAltitude,
                                             sigma * sigma, s->gpsTimeout, false, 0.0f);
    }
}

/**
 * @brief One filter step: predict over dt with accel, then the baro,
 * rangefinder and GPS samples in m (each NaN: none) as sequential scalar
 * updates.
 *
 * @param accel vertical acceleration, m/s^2, earth frame, +up, gravity removed.
 * @param dt time since the previous step, s.
 * @param measurements this step's samples (NULL: none).
 *
 * Baro: R = baroNoise^2, times groundEffectNoiseScale^2 with the ground-effect
 * flag, which also replaces a negative innovation y by min(y + deadZone, 0).
 * Rangefinder: NaN or outside [rangeMinimum, rangeMaximum] is not fused;
 * R = rangeNoise^2. GPS: fewer than gpsMinimumSatellites (when known) is not
 * fused; R = sigma^2 (FusionAltitudeKalmanGpsSigma). The first baro and GPS
 * samples set their offsets; later samples are gated (FusionAltitudeKalmanProcess).
 *
 * A dt above gapPeriod is a gap: no prediction, the covariance is inflated
 * instead (see the file comment), then the samples are processed as usual.
 *
 * Every call checks all inputs first: accel not finite, dt not finite or
 * <= 0, infinite baro or GPS altitude, or a GPS vertical accuracy (with a GPS
 * sample) that is not NaN and not finite > 0 is rejected with the state
 * unchanged.
 */
static inline FusionAltitudeKalmanStatus FusionAltitudeKalmanUpdate(FusionAltitudeKalman *const kalman, const float accel, const float dt,
                                                                    const FusionAltitudeKalmanMeasurements *const measurements) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    const FusionAltitudeKalmanMeasurements m = (measurements == NULL) ? FusionAltitudeKalmanMeasurementsNone() : *measurements;
    if (!FusionAltitudeIsFinite(accel)) {
        return FusionAltitudeKalmanStatusInvalidAccel;
    }
    if (!FusionAltitudeIsFinite(dt) || !(dt > 0.0f)) {
        return FusionAltitudeKalmanStatusInvalidDt;
    }
    const bool baroPresent = !FusionAltitudeIsNaN(m.baroAltitude);
    if (baroPresent && !FusionAltitudeIsFinite(m.baroAltitude)) {
        return FusionAltitudeKalmanStatusInvalidBaroAltitude;
    }
    const bool gpsPresent = !FusionAltitudeIsNaN(m.gpsAltitude);
    if (gpsPresent && !FusionAltitudeIsFinite(m.gpsAltitude)) {
        return FusionAltitudeKalmanStatusInvalidGpsAltitude;
    }
    if (gpsPresent && !FusionAltitudeIsNaN(m.gpsVerticalAccuracy) &&
        !(FusionAltitudeIsFinite(m.gpsVerticalAccuracy) && (m.gpsVerticalAccuracy > 0.0f))) {
        return FusionAltitudeKalmanStatusInvalidGpsAccuracy;
    }
    if (dt > kalman->settings.gapPeriod) {
        FusionAltitudeKalmanGap(kalman, dt);
    } else {
        FusionAltitudeKalmanPredict(kalman, accel, dt);
    }
    FusionAltitudeKalmanProcessBaro(kalman, &m, baroPresent);
    FusionAltitudeKalmanProcessRange(kalman, &m);
    FusionAltitudeKalmanProcessGps(kalman, &m, gpsPresent);
    return FusionAltitudeKalmanStatusOk;
}

//------------------------------------------------------------------------------
// Getters

/** @return the settings in use. */
static inline FusionAltitudeKalmanSettings FusionAltitudeKalmanGetSettings(const FusionAltitudeKalman *const kalman) {
    return kalman->settings;
}

/** @return height above ground h, m. */
static inline float FusionAltitudeKalmanGetHeightAboveGround(const FusionAltitudeKalman *const kalman) {
    return kalman->x[FusionAltitudeKalmanStateHeight];
}

/**
 * @return baro-referenced altitude h + ob, m: what a noise-free baro would
 * read, comparable to the observer's altitude. Equals h until the first baro
 * sample (ob is 0 then).
 */
static inline float FusionAltitudeKalmanGetAltitude(const FusionAltitudeKalman *const kalman) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    return kalman->x[FusionAltitudeKalmanStateHeight] + kalman->x[FusionAltitudeKalmanStateBaroOffset];
}

/** @return variance of the altitude h + ob, m^2: P_hh + 2*P_h,ob + P_ob,ob. */
static inline float FusionAltitudeKalmanGetAltitudeVariance(const FusionAltitudeKalman *const kalman) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    return kalman->P[FusionAltitudeKalmanStateHeight][FusionAltitudeKalmanStateHeight] + 2.0f * kalman->P[FusionAltitudeKalmanStateHeight][FusionAltitudeKalmanStateBaroOffset] + kalman->P[FusionAltitudeKalmanStateBaroOffset][FusionAltitudeKalmanStateBaroOffset];
}

/** @return vertical velocity v, m/s, +up. */
static inline float FusionAltitudeKalmanGetVerticalVelocity(const FusionAltitudeKalman *const kalman) {
    return kalman->x[FusionAltitudeKalmanStateVelocity];
}

/** @return accelerometer bias b, m/s^2, +up (already subtracted from the input). */
static inline float FusionAltitudeKalmanGetAccelBias(const FusionAltitudeKalman *const kalman) {
    return kalman->x[FusionAltitudeKalmanStateAccelBias];
}

/** @return baro offset ob (baro reads h + ob), m; 0 before the first baro sample. */
static inline float FusionAltitudeKalmanGetBaroOffset(const FusionAltitudeKalman *const kalman) {
    return kalman->x[FusionAltitudeKalmanStateBaroOffset];
}

/** @return GPS offset og (GPS reads h + og), m; 0 before the first usable GPS sample. */
static inline float FusionAltitudeKalmanGetGpsOffset(const FusionAltitudeKalman *const kalman) {
    return kalman->x[FusionAltitudeKalmanStateGpsOffset];
}

/** @return covariance entry P[i][j] (state indices FusionAltitudeKalmanState). */
static inline float FusionAltitudeKalmanGetCovariance(const FusionAltitudeKalman *const kalman, const FusionAltitudeKalmanState i,
                                                      const FusionAltitudeKalmanState j) {
    return kalman->P[i][j];
}

/** @return the number of gaps so far: updates with dt > gapPeriod. */
static inline uint32_t FusionAltitudeKalmanGetGapCount(const FusionAltitudeKalman *const kalman) {
    return kalman->gapCount;
}

/** @return true while the baro is timed out: no sample for longer than baroTimeout (s) since its latest one. */
static inline bool FusionAltitudeKalmanIsBaroTimedOut(const FusionAltitudeKalman *const kalman) {
    return kalman->sensors[FusionAltitudeKalmanSensorBaro].timedOut;
}

/** @return true while the rangefinder is timed out: no usable reading for longer than rangeTimeout (s). */
static inline bool FusionAltitudeKalmanIsRangeTimedOut(const FusionAltitudeKalman *const kalman) {
    return kalman->sensors[FusionAltitudeKalmanSensorRange].timedOut;
}

/** @return true while the GPS is timed out: no usable fix for longer than gpsTimeout (s). */
static inline bool FusionAltitudeKalmanIsGpsTimedOut(const FusionAltitudeKalman *const kalman) {
    return kalman->sensors[FusionAltitudeKalmanSensorGps].timedOut;
}

/**
 * @return the normalized innovation squared y^2/S of a sensor's latest
 * tested sample (dimensionless; NaN if none tested): computed from the
 * stored innovation y and variance S, the same bits as the gate's.
 */
static inline float FusionAltitudeKalmanGetNis(const FusionAltitudeKalman *const kalman, const FusionAltitudeKalmanSensorIndex sensor) {
    FUSION_ALTITUDE_KALMAN_NO_CONTRACT
    const float y = kalman->sensors[sensor].innovation;
    const float S = kalman->sensors[sensor].innovationVariance;
    return FusionAltitudeIsNaN(S) ? FusionAltitudeNaN() : ((y * y) / S);
}

/** @return the diagnostics of one sensor. */
static inline FusionAltitudeKalmanSensor FusionAltitudeKalmanGetSensor(const FusionAltitudeKalman *const kalman,
                                                                       const FusionAltitudeKalmanSensorIndex sensor) {
    return kalman->sensors[sensor];
}

#undef FUSION_ALTITUDE_KALMAN_NO_CONTRACT

#ifdef FUSION_ALTITUDE_KALMAN_GCC_NO_CONTRACT
#pragma GCC pop_options
#undef FUSION_ALTITUDE_KALMAN_GCC_NO_CONTRACT
#endif

#ifdef __cplusplus
}
#endif

#endif
