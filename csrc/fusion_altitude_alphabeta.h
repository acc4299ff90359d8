/**
 * @file fusion_altitude_alphabeta.h
 * @brief Quality-weighted alpha-beta multi-sensor altitude fusion, as
 * published for MatrixPilot multirotors: IMU-integrated altitude, barometer,
 * lidar, sonar and GPS each run their own alpha-beta filter whose depth Q
 * adapts to how well the sensor agrees with the fused output; the output is
 * the mean of the filters weighted by quality x confidence.
 *
 * Header-only C99 (also valid C++), float32 only, no malloc, no globals, no
 * libm. Needs fusion_altitude.h (float classification) next to it.
 *
 * Units and frame: altitudes and thresholds m, vertical velocity m/s,
 * acceleration m/s^2, time s; quality Q (filter depth, samples) and
 * confidence are dimensionless. Vertical is +up. NaN means "no sample this
 * step" for every sensor, the accelerometer (the IMU channel) included.
 *
 * One step, from the previous fused altitude h and velocity v:
 *   1. IMU prediction        hPred = h + v*dt + 0.5*a*dt^2   (hPred = h + v*dt without accel)
 *      The IMU channel's sample is zImu = hPred (NaN when accel is NaN).
 *   2. For each sensor i (IMU, baro, lidar, sonar, GPS, in this order), with
 *      its filter (x_i m, v_i m/s), depth Q_i and T_i = s since its last sample:
 *      - a first sample, one after a silence longer than the sensor's
 *        timeout, one after a sample beyond its gap maximum, or one whose
 *        interval T_i is more than FUSION_ALTITUDE_ALPHABETA_MAX_INTERVAL_RATIO
 *        (4) times the filter's previous interval or less than a quarter of
 *        it, (re)starts the filter:
 *        x_i = z, v_i = v (0 after an irregular interval), Q_i = Qmin_i (a
 *        dropped sensor comes back from its own fresh samples, not from a
 *        filter that followed the fault);
 *      - otherwise the filter predicts every step, x_i += v_i*dt, T_i += dt,
 *        and on a sample z:
 *          Q_i += 1 (at most Qmax_i) if |z - hPred| <= threshold_i, else Q_i -= 1 (at least Qmin_i)
 *          alpha = 2(2Q-1)/(Q(Q+1)),  beta = 6/(Q(Q+1))
 *          r = z - x_i;  x_i += alpha*r;  v_i += beta*r/T_i;  T_i = 0
 *      - each sample sets the sensor's gap g_i = z - hPred (held until its next sample)
 *      - weight w_i = Q_i * confidence_i, zeroed when the sensor is silent
 *        for longer than its timeout, when hPred is outside its altitude band
 *        [altitudeMin_i, altitudeMax_i], or when its gap |g_i| exceeds gapMax_i.
 *      - timeout: once a started sensor has been silent for longer than its
 *        timeout (T_i > timeout_i) its timedOut flag is set and its timeout
 *        count goes up by one (once per silence, as a gap is counted); the
 *        flag holds, through restarts, until the sensor's next sample. The
 *        other channels carry on: when the baro times out, a GPS, lidar or
 *        sonar with weight carries the fused altitude, and the flag says the
 *        baro is not in it (PX4's EKF2 stops fusing a baro that has not been
 *        sampled for 2 x 200 ms and falls back to another height source;
 *        ArduPilot's EKF3 switches to GPS height when the baro is lost).
 *   3. Fused output h = sum(w_i x_i)/sum(w_i), v = sum(w_i v_i)/sum(w_i);
 *      with every weight zero: h = hPred, v += a*dt (dead reckoning).
 * Before the first step with a baro, lidar, sonar or GPS sample the filter
 * waits (accel unused); that step starts every sampled filter and sets h to
 * their Qmin*confidence-weighted mean, v = 0.
 *
 * Gaps and dropouts (gapPeriod, default 1.5 s: the sensor timeouts, longer
 * than the 1 Hz baro of a balloon). Once started, a step with dt > gapPeriod
 * is a gap: nothing is predicted over it, the gap count goes up and the
 * fusion restarts as at the first start, from this step's samples or, if it
 * has none, the next step's that has some (h and v are held meanwhile);
 * after a gap the restart takes v = (h_start - h_before)/T, the mean
 * velocity over the T s since h was last updated, for the fused and every
 * filter's velocity. Dead reckoning is bounded: once no baro, lidar, sonar
 * or GPS channel has weight (the IMU channel alone, or no weight at all) for
 * more than gapPeriod s, the fusion restarts the same way from the next
 * samples (with v = 0; h and v are held until then), so a sensor dropout or
 * a fused altitude that drifted beyond every gap maximum cannot run away;
 * the sensors re-acquire it. The coasting is ended sooner when a sensor
 * still sampling disagrees: once coastingFor * |g_i| > gapPeriod * gapMax_i
 * for a baro, lidar, sonar or GPS channel with a current sample (not timed
 * out), i.e. after gapPeriod * gapMax_i / |g_i| s. On the Hedy rocket log
 * (baro only, a gyro-integrated attitude that is wrong after apogee) the
 * IMU channel alone had dead-reckoned to 286 m/s and 458 m off within the
 * 1.5 s; bounded by the disagreement the worst error is 202 m, in the
 * transonic boost where the baro itself is 180 m off (docs/hobby_estimators.md).
 *
 * Stable steps. The gains are per sample (alpha, and beta over the sample's
 * interval T), so with a steady sample interval the filter is stable at any
 * rate: in x and s = v*T one sample maps (x, s) through
 * [[1-alpha, rho], [-beta(1-alpha), rho(1-beta)]] with rho = T_next/T = 1,
 * whose eigenvalues lie inside the unit circle for every Q >= 2. With
 * irregular intervals rho multiplies the velocity term: a velocity learnt
 * over a 1 ms interval and applied over 1.4 s (rho = 1400) amplified the
 * noise of a 0.5 m baro to 4.1 km (alternating 0.1 ms and 1.4 s steps), and
 * the velocity learnt over the 0.1 ms interval, in the fused velocity, threw
 * the prediction beyond every gap maximum. So a sample whose interval is
 * more than 4 times the previous one, or less than a quarter of it, is not
 * integrated by the filter: it restarts it (above) with v_i = 0, since its
 * velocity was learnt over mismatched intervals. Measured on one filter with
 * log-uniform random intervals from 0.1 ms to 1.5 s and unit noise,
 * Q = 2..120: worst |x| 4.5 with this rule, 4e12 if the restart keeps the
 * velocity, 7e26 without it. A step dt above gapPeriod
 * is a gap of the whole fusion (below); both rules together are the stable-
 * step rule (docs/hobby_estimators.md).
 *
 * Why alpha = 2(2Q-1)/(Q(Q+1)): with beta = 6/(Q(Q+1)) these are the gains
 * of the least-squares straight-line fit to the latest Q samples (the
 * growing-memory polynomial filter; Brookner, "Tracking and Kalman Filtering
 * Made Easy", 1998), which is what "Q is the depth of the filter, the number
 * of samples taken into account" describes. The write-up prints
 * 2(Q-1)/(Q(Q+1)): at Q = 2 a line through two points must pass through the
 * newest (alpha = 1), the printed form gives 1/3; for large Q it is half the
 * least-squares gain with the same beta, so beta > alpha^2/(2 - alpha) and
 * the filter rings (complex poles). The write-up's update also has the sign
 * of the residual reversed (Z - Zi); this uses r = measurement - prediction.
 * The write-up's "Harmo coefficient" column is not used: it never says what
 * it does.
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
 * FusionAltitudeAlphaBeta fusion;
 * FusionAltitudeAlphaBetaInitialise(&fusion);              // the write-up's tables
 * for (;;) {
 *     FusionAltitudeAlphaBetaMeasurements m = FusionAltitudeAlphaBetaMeasurementsNone();
 *     if (baroReady) m.baroAltitude = baro;                  // m
 *     if (lidarReady) m.lidarAltitude = lidar;               // m
 *     if (FusionAltitudeAlphaBetaUpdate(&fusion, accel, 0.01f, &m) != FusionAltitudeAlphaBetaStatusOk) {
 *         // input rejected, state unchanged
 *     }
 *     const float h = FusionAltitudeAlphaBetaGetAltitude(&fusion);
 * }
 * @endcode
 */

#ifndef FUSION_ALTITUDE_ALPHABETA_H
#define FUSION_ALTITUDE_ALPHABETA_H

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
#define FUSION_ALTITUDE_ALPHABETA_GCC_NO_CONTRACT
#pragma GCC push_options
#pragma GCC optimize("fp-contract=off")
#endif

#if defined(__clang__)
#define FUSION_ALTITUDE_ALPHABETA_NO_CONTRACT _Pragma("clang fp contract(off)")
#else
#define FUSION_ALTITUDE_ALPHABETA_NO_CONTRACT
#endif

//------------------------------------------------------------------------------
// Definitions

/** Number of sensor channels. */
#define FUSION_ALTITUDE_ALPHABETA_SENSORS (5)

/**
 * 1: the loop over the five channels is unrolled (gcc and clang), so each
 * channel's settings are at constant offsets and the IMU tests compile
 * away: 15 % fewer instructions per step on x86-64 (docs/performance.md).
 * Both give the same bits. Default 1 on 64-bit hosts (x86-64, AArch64)
 * unless optimising for size, 0 elsewhere (firmware: code size). Define it
 * to 0 or 1 before including this header to choose.
 */
#ifndef FUSION_ALTITUDE_ALPHABETA_UNROLL
#if !defined(__OPTIMIZE_SIZE__) && (defined(__x86_64__) || defined(_M_X64) || defined(__aarch64__) || defined(_M_ARM64))
#define FUSION_ALTITUDE_ALPHABETA_UNROLL 1
#else
#define FUSION_ALTITUDE_ALPHABETA_UNROLL 0
#endif
#endif

/**
 * Largest ratio of a sensor's sample interval to its previous one that its
 * filter integrates; a longer interval restarts the filter (see the file
 * comment, "Stable steps").
 */
#define FUSION_ALTITUDE_ALPHABETA_MAX_INTERVAL_RATIO (4.0f)

/**
 * Largest accepted confidence: a weight Q * confidence stays below 1e10 and
 * the sum of five below 1e11, far inside float32 (fuzz_alphabeta.c found a
 * confidence of 1e36 that made a weight +infinity and the altitude NaN).
 */
#define FUSION_ALTITUDE_ALPHABETA_MAX_CONFIDENCE (1e6f)

/** Largest accepted quality (filter depth), samples. */
#define FUSION_ALTITUDE_ALPHABETA_MAX_QUALITY (10000)

/** Sensor channel indices, also the order of the update. */
typedef enum {
    FusionAltitudeAlphaBetaSensorImu = 0,
    FusionAltitudeAlphaBetaSensorBaro,
    FusionAltitudeAlphaBetaSensorLidar,
    FusionAltitudeAlphaBetaSensorSonar,
    FusionAltitudeAlphaBetaSensorGps,
} FusionAltitudeAlphaBetaSensorIndex;

/** Status returned by every function that can reject its input. */
typedef enum {
    FusionAltitudeAlphaBetaStatusOk = 0,
    FusionAltitudeAlphaBetaStatusInvalidAccel,         /**< accel infinite */
    FusionAltitudeAlphaBetaStatusInvalidDt,            /**< dt not finite or <= 0 */
    FusionAltitudeAlphaBetaStatusInvalidBaroAltitude,  /**< baro altitude infinite */
    FusionAltitudeAlphaBetaStatusInvalidLidarAltitude, /**< lidar altitude infinite */
    FusionAltitudeAlphaBetaStatusInvalidSonarAltitude, /**< sonar altitude infinite */
    FusionAltitudeAlphaBetaStatusInvalidGpsAltitude,   /**< GPS altitude infinite */
    FusionAltitudeAlphaBetaStatusInvalidThreshold,     /**< a threshold not finite or <= 0 */
    FusionAltitudeAlphaBetaStatusInvalidQuality,       /**< not 2 <= qualityMin <= qualityMax <= FUSION_ALTITUDE_ALPHABETA_MAX_QUALITY */
    FusionAltitudeAlphaBetaStatusInvalidConfidence,    /**< a confidence not in [0, FUSION_ALTITUDE_ALPHABETA_MAX_CONFIDENCE] */
    FusionAltitudeAlphaBetaStatusInvalidAltitudeBand,  /**< a band limit NaN or not altitudeMin < altitudeMax */
    FusionAltitudeAlphaBetaStatusInvalidGapMax,        /**< a gap maximum NaN or <= 0 (+infinity: no limit) */
    FusionAltitudeAlphaBetaStatusInvalidTimeout,       /**< a timeout not finite or <= 0 */
    FusionAltitudeAlphaBetaStatusInvalidGapPeriod,     /**< gap period NaN or <= 0 (+infinity: never a gap) */
} FusionAltitudeAlphaBetaStatus;

/** One sensor's settings. */
typedef struct {
    float threshold;     /**< m, > 0: |z - hPred| up to this counts as agreement [rule: finite, > 0; else InvalidThreshold] */
    int32_t qualityMin;  /**< Qmin, samples, >= 2 (Q = 1 gives alpha = 1, beta = 3: unstable) [rule: >= 2; else InvalidQuality] */
    int32_t qualityMax;  /**< Qmax, samples, >= Qmin [rule: >= qualityMin, <= FUSION_ALTITUDE_ALPHABETA_MAX_QUALITY; else InvalidQuality] */
    float confidence;    /**< in [0, 1e6]: weight = Q * confidence [rule: finite, >= 0, <= FUSION_ALTITUDE_ALPHABETA_MAX_CONFIDENCE; else InvalidConfidence] */
    float altitudeMin;   /**< m: weight 0 when hPred < this (may be -infinity) [rule: < altitudeMax; else InvalidAltitudeBand] */
    float altitudeMax;   /**< m: weight 0 when hPred > this (may be +infinity) [rule: > altitudeMin; else InvalidAltitudeBand] */
    float gapMax;        /**< m, > 0: weight 0 while the latest sample's |z - hPred| > this (may be +infinity) [rule: > 0; else InvalidGapMax] */
    float timeout;       /**< s, > 0: weight 0 after this long without a sample; the next sample restarts the filter [rule: finite, > 0; else InvalidTimeout] */
} FusionAltitudeAlphaBetaSensorSettings;

/** Settings: one entry per sensor channel, in FusionAltitudeAlphaBetaSensorIndex order, and the gap period. */
typedef struct {
    FusionAltitudeAlphaBetaSensorSettings sensors[FUSION_ALTITUDE_ALPHABETA_SENSORS]; /**< [rule: checked] */
    float gapPeriod; /**< s: an update whose dt exceeds this is a gap, not integrated; also the longest dead reckoning (default 1.5 s) [rule: > 0; else InvalidGapPeriod] */
} FusionAltitudeAlphaBetaSettings;

/** One step's samples (m). NaN means "no sample this step". */
typedef struct {
    float baroAltitude;
    float lidarAltitude;
    float sonarAltitude;
    float gpsAltitude;
} FusionAltitudeAlphaBetaMeasurements;

/** One sensor's alpha-beta filter. */
typedef struct {
    float altitude;       /**< x, m */
    float velocity;       /**< v, m/s */
    float sinceSample;    /**< T, s since the latest sample */
    float interval;       /**< s: the interval T of the latest sample (0: none since the filter started) */
    float gap;            /**< g = z - hPred of the latest sample, m */
    float weight;         /**< w of the latest step (0: not used) */
    int32_t quality;      /**< Q, samples */
    uint32_t timeouts;    /**< times the sensor fell silent for longer than its timeout, in total (counted like gaps) */
    bool started;         /**< the filter has had a sample */
    bool timedOut;        /**< silent for longer than its timeout since its latest sample (held until its next sample) */
} FusionAltitudeAlphaBetaFilter;

/** Fusion state. Read it through the Get functions. */
typedef struct {
    FusionAltitudeAlphaBetaSettings settings;
    FusionAltitudeAlphaBetaFilter filters[FUSION_ALTITUDE_ALPHABETA_SENSORS];
    float altitude;         /**< fused h, m */
    float verticalVelocity; /**< fused v, m/s */
    float totalWeight;      /**< sum of the weights of the latest step (0: dead reckoning) */
    float coastingFor;      /**< s of dead reckoning so far: steps with no weight on a baro, lidar, sonar or GPS channel */
    float gapTime;          /**< s since h was last updated while a restart after a gap is pending; 0 otherwise */
    uint32_t gapCount;      /**< updates with dt > gapPeriod so far */
    bool started;           /**< false until the first non-IMU sample, and from a gap or a dead-reckoning timeout to the next one */
} FusionAltitudeAlphaBeta;

//------------------------------------------------------------------------------
// Status messages

/** @return a short English description of the status, never NULL. */
static inline const char *FusionAltitudeAlphaBetaStatusMessage(const FusionAltitudeAlphaBetaStatus status) {
    static const char *const texts[] = { /* in the enum's order */
        "ok", /* FusionAltitudeAlphaBetaStatusOk */
        "accel must be finite (or NaN for no sample)", /* FusionAltitudeAlphaBetaStatusInvalidAccel */
        "dt must be finite and > 0", /* FusionAltitudeAlphaBetaStatusInvalidDt */
        "baro altitude must be finite (or NaN for no sample)", /* FusionAltitudeAlphaBetaStatusInvalidBaroAltitude */
        "lidar altitude must be finite (or NaN for no sample)", /* FusionAltitudeAlphaBetaStatusInvalidLidarAltitude */
        "sonar altitude must be finite (or NaN for no sample)", /* FusionAltitudeAlphaBetaStatusInvalidSonarAltitude */
        "GPS altitude must be finite (or NaN for no sample)", /* FusionAltitudeAlphaBetaStatusInvalidGpsAltitude */
        "thresholds must be finite and > 0", /* FusionAltitudeAlphaBetaStatusInvalidThreshold */
        "qualities must satisfy 2 <= minimum <= maximum <= 10000", /* FusionAltitudeAlphaBetaStatusInvalidQuality */
        "confidences must be in [0, 1e6]", /* FusionAltitudeAlphaBetaStatusInvalidConfidence */
        "altitude bands must satisfy minimum < maximum (infinite allowed, NaN not)", /* FusionAltitudeAlphaBetaStatusInvalidAltitudeBand */
        "gap maxima must be > 0 (+infinity: no limit)", /* FusionAltitudeAlphaBetaStatusInvalidGapMax */
        "timeouts must be finite and > 0", /* FusionAltitudeAlphaBetaStatusInvalidTimeout */
        "gap period must be > 0 (+infinity: never a gap)", /* FusionAltitudeAlphaBetaStatusInvalidGapPeriod */
    };
    return FusionAltitudeStatusText(texts, sizeof(texts) / sizeof(texts[0]), (size_t) status);
}

//------------------------------------------------------------------------------
// Settings

/** @internal @return one sensor's settings from its fields, in struct order (for the defaults). */
static inline FusionAltitudeAlphaBetaSensorSettings FusionAltitudeAlphaBetaSensor(const float threshold, const int32_t qualityMin,
                                                                                   const int32_t qualityMax, const float confidence,
                                                                                   const float altitudeMin, const float altitudeMax,
                                                                                   const float gapMax, const float timeout) {
    FusionAltitudeAlphaBetaSensorSettings sensor;
    sensor.threshold = threshold;
    sensor.qualityMin = qualityMin;
    sensor.qualityMax = qualityMax;
    sensor.confidence = confidence;
    sensor.altitudeMin = altitudeMin;
    sensor.altitudeMax = altitudeMax;
    sensor.gapMax = gapMax;
    sensor.timeout = timeout;
    return sensor;
}

/** @internal @return +infinity, built without libm. */
static inline float FusionAltitudeAlphaBetaInfinity(void) {
    return FusionAltitudeInfinity();
}

/**
 * @return the write-up's tables (threshold m, Qmin, Qmax, confidence,
 * altitude min m, gap max m):
 *   IMU    1.0   2    4   5   -1   4
 *   baro   1.0  10   60   2   -4  10
 *   lidar  0.5   2    8  10    0   6
 *   GPS   10.0  10  120   1  -10  20
 * Added where the write-up gives no number: sonar as the lidar (its table
 * row is "lidar or sonar"); altitude max 40 m for the lidar and 5 m for the
 * sonar (their typical ranges; the write-up only says "low" and "very low
 * range"), +infinity for the others; timeout 1.5 s for every sensor (longer
 * than the 1 Hz baro of a balloon), and gap period 1.5 s to match.
 */
static inline FusionAltitudeAlphaBetaSettings FusionAltitudeAlphaBetaSettingsDefault(void) {
    const float infinity = FusionAltitudeAlphaBetaInfinity();
    FusionAltitudeAlphaBetaSettings settings;
    settings.sensors[FusionAltitudeAlphaBetaSensorImu] = FusionAltitudeAlphaBetaSensor(1.0f, 2, 4, 5.0f, -1.0f, infinity, 4.0f, 1.5f);
    settings.sensors[FusionAltitudeAlphaBetaSensorBaro] = FusionAltitudeAlphaBetaSensor(1.0f, 10, 60, 2.0f, -4.0f, infinity, 10.0f, 1.5f);
    settings.sensors[FusionAltitudeAlphaBetaSensorLidar] = FusionAltitudeAlphaBetaSensor(0.5f, 2, 8, 10.0f, 0.0f, 40.0f, 6.0f, 1.5f);
    settings.sensors[FusionAltitudeAlphaBetaSensorSonar] = FusionAltitudeAlphaBetaSensor(0.5f, 2, 8, 10.0f, 0.0f, 5.0f, 6.0f, 1.5f);
    settings.sensors[FusionAltitudeAlphaBetaSensorGps] = FusionAltitudeAlphaBetaSensor(10.0f, 10, 120, 1.0f, -10.0f, infinity, 20.0f, 1.5f);
    settings.gapPeriod = 1.5f;
    return settings;
}

/** @return the status a sensor's settings get, Ok if valid (see the status enum for the rules). */
static inline FusionAltitudeAlphaBetaStatus FusionAltitudeAlphaBetaSensorSettingsCheck(const FusionAltitudeAlphaBetaSensorSettings *const sensor) {
    if (!FusionAltitudeIsFinite(sensor->threshold) || !(sensor->threshold > 0.0f)) {
        return FusionAltitudeAlphaBetaStatusInvalidThreshold;
    }
    if ((sensor->qualityMin < 2) || (sensor->qualityMax < sensor->qualityMin) ||
        (sensor->qualityMax > FUSION_ALTITUDE_ALPHABETA_MAX_QUALITY)) {
        return FusionAltitudeAlphaBetaStatusInvalidQuality;
    }
    if (!FusionAltitudeIsFinite(sensor->confidence) || !(sensor->confidence >= 0.0f) ||
        !(sensor->confidence <= FUSION_ALTITUDE_ALPHABETA_MAX_CONFIDENCE)) {
        return FusionAltitudeAlphaBetaStatusInvalidConfidence;
    }
    if (!(sensor->altitudeMin < sensor->altitudeMax)) { /* false for NaN */
        return FusionAltitudeAlphaBetaStatusInvalidAltitudeBand;
    }
    if (!(sensor->gapMax > 0.0f)) {
        return FusionAltitudeAlphaBetaStatusInvalidGapMax;
    }
    if (!FusionAltitudeIsFinite(sensor->timeout) || !(sensor->timeout > 0.0f)) {
        return FusionAltitudeAlphaBetaStatusInvalidTimeout;
    }
    return FusionAltitudeAlphaBetaStatusOk;
}

/** @brief Checks every sensor's settings, in sensor order (the first failure's status), then the gap period. */
static inline FusionAltitudeAlphaBetaStatus FusionAltitudeAlphaBetaSettingsCheck(const FusionAltitudeAlphaBetaSettings *const settings) {
    for (int i = 0; i < FUSION_ALTITUDE_ALPHABETA_SENSORS; i++) {
        const FusionAltitudeAlphaBetaStatus status = FusionAltitudeAlphaBetaSensorSettingsCheck(&settings->sensors[i]);
        if (status != FusionAltitudeAlphaBetaStatusOk) {
            return status;
        }
    }
    if (!(settings->gapPeriod > 0.0f)) { /* false for NaN */
        return FusionAltitudeAlphaBetaStatusInvalidGapPeriod;
    }
    return FusionAltitudeAlphaBetaStatusOk;
}

/**
 * @brief Gains of the least-squares alpha-beta filter of depth quality (>= 1):
 * alpha = 2(2Q-1)/(Q(Q+1)), beta = 6/(Q(Q+1)) (see the file comment).
 */
static inline void FusionAltitudeAlphaBetaGains(const int32_t quality, float *const alpha, float *const beta) {
    FUSION_ALTITUDE_ALPHABETA_NO_CONTRACT
    const float q = (float) quality;
    const float denominator = q * (q + 1.0f);
    *alpha = (2.0f * (2.0f * q - 1.0f)) / denominator;
    *beta = 6.0f / denominator;
}

//------------------------------------------------------------------------------
// Fusion

/** @return measurements with no sample from any sensor (all NaN). */
static inline FusionAltitudeAlphaBetaMeasurements FusionAltitudeAlphaBetaMeasurementsNone(void) {
    FusionAltitudeAlphaBetaMeasurements m;
    m.baroAltitude = FusionAltitudeNaN();
    m.lidarAltitude = FusionAltitudeNaN();
    m.sonarAltitude = FusionAltitudeNaN();
    m.gpsAltitude = FusionAltitudeNaN();
    return m;
}

/** @internal Clears every sensor's filter state (altitude m, velocity m/s, times s, weight). */
static inline void FusionAltitudeAlphaBetaClear(FusionAltitudeAlphaBeta *const fusion) {
    for (int i = 0; i < FUSION_ALTITUDE_ALPHABETA_SENSORS; i++) {
        FusionAltitudeAlphaBetaFilter *const f = &fusion->filters[i];
        f->altitude = 0.0f;
        f->velocity = 0.0f;
        f->sinceSample = 0.0f;
        f->interval = 0.0f;
        f->gap = 0.0f;
        f->weight = 0.0f;
        f->quality = fusion->settings.sensors[i].qualityMin;
        f->timeouts = 0u;
        f->started = false;
        f->timedOut = false;
    }
    fusion->altitude = 0.0f;
    fusion->verticalVelocity = 0.0f;
    fusion->totalWeight = 0.0f;
    fusion->coastingFor = 0.0f;
    fusion->gapTime = 0.0f;
    fusion->gapCount = 0u;
    fusion->started = false;
}

/** @brief Initialises with the default settings; nothing started. */
static inline void FusionAltitudeAlphaBetaInitialise(FusionAltitudeAlphaBeta *const fusion) {
    fusion->settings = FusionAltitudeAlphaBetaSettingsDefault();
    FusionAltitudeAlphaBetaClear(fusion);
}

/** @brief Initialises with the given settings. Rejected (fusion untouched) if they fail the check. */
static inline FusionAltitudeAlphaBetaStatus FusionAltitudeAlphaBetaInitialiseWith(FusionAltitudeAlphaBeta *const fusion,
                                                                                  const FusionAltitudeAlphaBetaSettings *const settings) {
    const FusionAltitudeAlphaBetaStatus status = FusionAltitudeAlphaBetaSettingsCheck(settings);
    if (status == FusionAltitudeAlphaBetaStatusOk) {
        fusion->settings = *settings;
        FusionAltitudeAlphaBetaClear(fusion);
    }
    return status;
}

/**
 * @brief Replaces the settings, keeping the state; each quality is clamped
 * into its new [Qmin, Qmax]. Rejected (state unchanged) if the check fails.
 */
static inline FusionAltitudeAlphaBetaStatus FusionAltitudeAlphaBetaSetSettings(FusionAltitudeAlphaBeta *const fusion,
                                                                               const FusionAltitudeAlphaBetaSettings *const settings) {
    const FusionAltitudeAlphaBetaStatus status = FusionAltitudeAlphaBetaSettingsCheck(settings);
    if (status != FusionAltitudeAlphaBetaStatusOk) {
        return status;
    }
    fusion->settings = *settings;
    for (int i = 0; i < FUSION_ALTITUDE_ALPHABETA_SENSORS; i++) {
        FusionAltitudeAlphaBetaFilter *const f = &fusion->filters[i];
        const FusionAltitudeAlphaBetaSensorSettings *const s = &settings->sensors[i];
        f->quality = (f->quality < s->qualityMin) ? s->qualityMin : ((f->quality > s->qualityMax) ? s->qualityMax : f->quality);
    }
    return FusionAltitudeAlphaBetaStatusOk;
}

/** @internal @return |value| (NaN stays NaN), without libm: one instruction (andps, vabs.f32, fabs.s) with gcc and clang. */
static inline float FusionAltitudeAlphaBetaAbs(const float value) {
#if defined(__GNUC__) || defined(__clang__)
    return __builtin_fabsf(value);
#else
    const uint32_t bits = FusionAltitudeFloatBits(value) & 0x7FFFFFFFu;
    float result;
    memcpy(&result, &bits, sizeof(result));
    return result;
#endif
}

/** @internal @return true if value is +infinity or -infinity (on its bits, without libm). */
static inline bool FusionAltitudeAlphaBetaIsInfinite(const float value) {
    return (FusionAltitudeFloatBits(value) & 0x7FFFFFFFu) == 0x7F800000u;
}

/** @return the status FusionAltitudeAlphaBetaUpdate gives these inputs: each sample finite or NaN, dt finite and > 0. */
static inline FusionAltitudeAlphaBetaStatus FusionAltitudeAlphaBetaCheckInputs(const float accel, const float dt,
                                                                               const FusionAltitudeAlphaBetaMeasurements *const m) {
    if (FusionAltitudeAlphaBetaIsInfinite(accel)) {
        return FusionAltitudeAlphaBetaStatusInvalidAccel;
    }
    if (!FusionAltitudeIsFinite(dt) || !(dt > 0.0f)) {
        return FusionAltitudeAlphaBetaStatusInvalidDt;
    }
    if (FusionAltitudeAlphaBetaIsInfinite(m->baroAltitude)) {
        return FusionAltitudeAlphaBetaStatusInvalidBaroAltitude;
    }
    if (FusionAltitudeAlphaBetaIsInfinite(m->lidarAltitude)) {
        return FusionAltitudeAlphaBetaStatusInvalidLidarAltitude;
    }
    if (FusionAltitudeAlphaBetaIsInfinite(m->sonarAltitude)) {
        return FusionAltitudeAlphaBetaStatusInvalidSonarAltitude;
    }
    if (FusionAltitudeAlphaBetaIsInfinite(m->gpsAltitude)) {
        return FusionAltitudeAlphaBetaStatusInvalidGpsAltitude;
    }
    return FusionAltitudeAlphaBetaStatusOk;
}

/** @internal
 * @brief The start (or restart) on a step with a non-IMU sample:
 * h = the Qmin*confidence-weighted mean of the samples z, v = 0 or, after a
 * gap, the mean velocity over it; every sampled filter starts there.
 * @return false (nothing changed) if no non-IMU sample has weight.
 */
static inline bool FusionAltitudeAlphaBetaStart(FusionAltitudeAlphaBeta *const fusion, const float z[FUSION_ALTITUDE_ALPHABETA_SENSORS],
                                                const bool imuSample) {
    FUSION_ALTITUDE_ALPHABETA_NO_CONTRACT
    float sumWeight = 0.0f;
    float sumAltitude = 0.0f;
    for (int i = 1; i < FUSION_ALTITUDE_ALPHABETA_SENSORS; i++) {
        if (FusionAltitudeIsFinite(z[i])) {
            const float w = (float) fusion->settings.sensors[i].qualityMin * fusion->settings.sensors[i].confidence;
            sumWeight += w;
            sumAltitude += w * z[i];
        }
    }
    if (!(sumWeight > 0.0f)) {
        return false; /* nothing to start from yet */
    }
    const float altitude = sumAltitude / sumWeight;
    const float velocity = (fusion->gapTime > 0.0f) ? ((altitude - fusion->altitude) / fusion->gapTime) : 0.0f;
    fusion->altitude = altitude;
    fusion->verticalVelocity = velocity;
    fusion->totalWeight = sumWeight;
    for (int i = 0; i < FUSION_ALTITUDE_ALPHABETA_SENSORS; i++) {
        FusionAltitudeAlphaBetaFilter *const f = &fusion->filters[i];
        const FusionAltitudeAlphaBetaSensorSettings *const s = &fusion->settings.sensors[i];
        const bool sampled = (i == FusionAltitudeAlphaBetaSensorImu) ? imuSample : FusionAltitudeIsFinite(z[i]);
        f->altitude = (i == FusionAltitudeAlphaBetaSensorImu) ? fusion->altitude : z[i];
        f->velocity = velocity;
        f->sinceSample = 0.0f;
        f->interval = 0.0f;
        f->gap = sampled ? (f->altitude - fusion->altitude) : 0.0f;
        f->quality = s->qualityMin;
        f->started = sampled;
        f->timedOut = f->timedOut && !sampled; /* a silent sensor stays timed out through the restart */
        f->weight = (sampled && (i != FusionAltitudeAlphaBetaSensorImu)) ? (float) s->qualityMin * s->confidence : 0.0f;
        if (!sampled) {
            f->altitude = 0.0f;
        }
    }
    fusion->coastingFor = 0.0f;
    fusion->gapTime = 0.0f;
    fusion->started = true;
    return true;
}

/** @internal
 * @brief One sensor's alpha-beta filter over dt with its sample z
 * (NaN: none), the predicted fused altitude and the fused velocity before
 * this step (see the file comment, step 2).
 * @return the sensor's weight this step (0: not used).
 */
static inline float FusionAltitudeAlphaBetaFilterStep(FusionAltitudeAlphaBetaFilter *const f, const FusionAltitudeAlphaBetaSensorSettings *const s,
                                                      const float z, const float dt, const float altitudePredicted,
                                                      const float verticalVelocity) {
    FUSION_ALTITUDE_ALPHABETA_NO_CONTRACT
    if (f->started) {
        f->altitude += f->velocity * dt;
        f->sinceSample += dt;
    }
    if (FusionAltitudeIsFinite(z)) {
        const bool wasBeyondGap = !(FusionAltitudeAlphaBetaAbs(f->gap) <= s->gapMax);
        const bool fresh = !f->started || (f->sinceSample > s->timeout);
        const bool irregular = (f->interval > 0.0f) && ((f->sinceSample > FUSION_ALTITUDE_ALPHABETA_MAX_INTERVAL_RATIO * f->interval) ||
                                                        ((FUSION_ALTITUDE_ALPHABETA_MAX_INTERVAL_RATIO * f->sinceSample) < f->interval));
        f->gap = z - altitudePredicted;
        f->interval = fresh ? 0.0f : f->sinceSample;
        if (fresh || wasBeyondGap || irregular) {
            f->altitude = z;
            f->velocity = irregular ? 0.0f : verticalVelocity; /* learnt over mismatched intervals: not kept */
            f->quality = s->qualityMin;
            f->started = true;
        } else {
            if (FusionAltitudeAlphaBetaAbs(f->gap) <= s->threshold) {
                f->quality = (f->quality < s->qualityMax) ? (f->quality + 1) : s->qualityMax;
            } else {
                f->quality = (f->quality > s->qualityMin) ? (f->quality - 1) : s->qualityMin;
            }
            float alpha;
            float beta;
            FusionAltitudeAlphaBetaGains(f->quality, &alpha, &beta);
            const float residual = z - f->altitude;
            f->altitude += alpha * residual;
            f->velocity += (beta * residual) / f->sinceSample;
        }
        f->sinceSample = 0.0f;
    }
    if (FusionAltitudeIsFinite(z)) {
        f->timedOut = false;
    } else if (f->started && (f->sinceSample > s->timeout) && !f->timedOut) {
        f->timedOut = true; /* this silence is counted once */
        f->timeouts++;
    }
    float weight = 0.0f;
    if (f->started && !(f->sinceSample > s->timeout)) {
        const bool inBand = (altitudePredicted >= s->altitudeMin) && (altitudePredicted <= s->altitudeMax);
        const bool close = FusionAltitudeAlphaBetaAbs(f->gap) <= s->gapMax;
        if (inBand && close) {
            weight = (float) f->quality * s->confidence;
        }
    }
    f->weight = weight;
    return weight;
}

/** @internal
 * @brief Steps 1 to 3 of the file comment, for a started fusion:
 * the IMU prediction, every filter, then the weighted mean or, with every
 * weight zero, dead reckoning; after gapPeriod s with no weight on a
 * non-IMU channel the fusion stops, to restart from the next samples.
 */
static inline void FusionAltitudeAlphaBetaStep(FusionAltitudeAlphaBeta *const fusion, const float accel, const float dt,
                                               float z[FUSION_ALTITUDE_ALPHABETA_SENSORS], const bool imuSample) {
    FUSION_ALTITUDE_ALPHABETA_NO_CONTRACT
    float altitudePredicted = fusion->altitude + fusion->verticalVelocity * dt;
    float velocityPredicted = fusion->verticalVelocity;
    if (imuSample) {
        altitudePredicted += 0.5f * accel * dt * dt;
        velocityPredicted += accel * dt;
    }
    z[FusionAltitudeAlphaBetaSensorImu] = imuSample ? altitudePredicted : FusionAltitudeNaN();
    float sumWeight = 0.0f;
    float sumAltitude = 0.0f;
    float sumVelocity = 0.0f;
    bool referenced = false; /* a baro, lidar, sonar or GPS channel has weight */
#if FUSION_ALTITUDE_ALPHABETA_UNROLL && (defined(__GNUC__) || defined(__clang__))
#pragma GCC unroll 5
#endif
    for (int i = 0; i < FUSION_ALTITUDE_ALPHABETA_SENSORS; i++) {
        FusionAltitudeAlphaBetaFilter *const f = &fusion->filters[i];
        const float weight = FusionAltitudeAlphaBetaFilterStep(f, &fusion->settings.sensors[i], z[i], dt, altitudePredicted,
                                                               fusion->verticalVelocity);
        if (weight > 0.0f) {
            sumWeight += weight;
            sumAltitude += weight * f->altitude;
            sumVelocity += weight * f->velocity;
            referenced = referenced || (i != FusionAltitudeAlphaBetaSensorImu);
        }
    }
    if (sumWeight > 0.0f) {
        fusion->altitude = sumAltitude / sumWeight;
        fusion->verticalVelocity = sumVelocity / sumWeight;
    } else {
        fusion->altitude = altitudePredicted;
        fusion->verticalVelocity = velocityPredicted;
    }
    fusion->totalWeight = sumWeight;
    fusion->coastingFor = referenced ? 0.0f : (fusion->coastingFor + dt);
    bool stop = fusion->coastingFor > fusion->settings.gapPeriod;
    /* Coasting is also bounded by the disagreement: a baro, lidar, sonar or GPS channel with a current
     * sample (not timed out) whose gap g is beyond its gapMax ends it once coastingFor * |g| >
     * gapPeriod * gapMax, the sooner the further the dead reckoning has drifted from it. */
    for (int i = 1; (i < FUSION_ALTITUDE_ALPHABETA_SENSORS) && !stop && (fusion->coastingFor > 0.0f); i++) {
        const FusionAltitudeAlphaBetaFilter *const f = &fusion->filters[i];
        const FusionAltitudeAlphaBetaSensorSettings *const s = &fusion->settings.sensors[i];
        const float disagreement = (f->gap < 0.0f) ? -f->gap : f->gap;
        if (f->started && !(f->sinceSample > s->timeout) &&
            ((fusion->coastingFor * disagreement) > (fusion->settings.gapPeriod * s->gapMax))) {
            stop = true;
        }
    }
    if (stop) {
        fusion->started = false; /* bounded coasting: re-acquire from the next samples */
    }
}

/**
 * @brief One step (see the file comment for the equations).
 *
 * @param accel vertical acceleration a, m/s^2, earth frame, +up, gravity
 *        removed; NaN: no IMU sample this step.
 * @param dt time since the previous step, s.
 * @param m this step's samples, NaN where none.
 *
 * A dt above gapPeriod is a gap, and dead reckoning is bounded (see the file
 * comment). Inputs are checked first; a rejected call leaves the state
 * unchanged.
 */
static inline FusionAltitudeAlphaBetaStatus FusionAltitudeAlphaBetaUpdate(FusionAltitudeAlphaBeta *const fusion, const float accel,
                                                                          const float dt,
                                                                          const FusionAltitudeAlphaBetaMeasurements *const m) {
    FUSION_ALTITUDE_ALPHABETA_NO_CONTRACT
    const FusionAltitudeAlphaBetaStatus status = FusionAltitudeAlphaBetaCheckInputs(accel, dt, m);
    if (status != FusionAltitudeAlphaBetaStatusOk) {
        return status;
    }
    const bool imuSample = FusionAltitudeIsFinite(accel);
    float z[FUSION_ALTITUDE_ALPHABETA_SENSORS];
    z[FusionAltitudeAlphaBetaSensorImu] = FusionAltitudeNaN();
    z[FusionAltitudeAlphaBetaSensorBaro] = m->baroAltitude;
    z[FusionAltitudeAlphaBetaSensorLidar] = m->lidarAltitude;
    z[FusionAltitudeAlphaBetaSensorSonar] = m->sonarAltitude;
    z[FusionAltitudeAlphaBetaSensorGps] = m->gpsAltitude;
    if (fusion->started && (dt > fusion->settings.gapPeriod)) { /* a gap: restart from this or the next samples */
        fusion->gapCount++;
        fusion->started = false;
        fusion->gapTime = dt;
    } else if (!fusion->started && (fusion->gapTime > 0.0f)) { /* still waiting for samples after a gap */
        fusion->gapTime += dt;
    }
    if (!fusion->started) {
        (void) FusionAltitudeAlphaBetaStart(fusion, z, imuSample);
        return FusionAltitudeAlphaBetaStatusOk;
    }
    FusionAltitudeAlphaBetaStep(fusion, accel, dt, z, imuSample);
    return FusionAltitudeAlphaBetaStatusOk;
}

/** @return the settings in use. */
static inline FusionAltitudeAlphaBetaSettings FusionAltitudeAlphaBetaGetSettings(const FusionAltitudeAlphaBeta *const fusion) {
    return fusion->settings;
}

/** @return fused altitude h, m (0 until started). */
static inline float FusionAltitudeAlphaBetaGetAltitude(const FusionAltitudeAlphaBeta *const fusion) {
    return fusion->altitude;
}

/** @return fused vertical velocity v, m/s, +up. */
static inline float FusionAltitudeAlphaBetaGetVerticalVelocity(const FusionAltitudeAlphaBeta *const fusion) {
    return fusion->verticalVelocity;
}

/** @return a sensor's weight in the latest step (0: not used). */
static inline float FusionAltitudeAlphaBetaGetWeight(const FusionAltitudeAlphaBeta *const fusion, const FusionAltitudeAlphaBetaSensorIndex sensor) {
    return fusion->filters[sensor].weight;
}

/** @return a sensor's quality Q (filter depth, samples). */
static inline int32_t FusionAltitudeAlphaBetaGetQuality(const FusionAltitudeAlphaBeta *const fusion, const FusionAltitudeAlphaBetaSensorIndex sensor) {
    return fusion->filters[sensor].quality;
}

/** @return true while a sensor is timed out: it had samples, then none for longer than its timeout (until its next sample). */
static inline bool FusionAltitudeAlphaBetaIsTimedOut(const FusionAltitudeAlphaBeta *const fusion, const FusionAltitudeAlphaBetaSensorIndex sensor) {
    return fusion->filters[sensor].timedOut;
}

/** @return the number of times a sensor timed out so far (each silence longer than its timeout counts once). */
static inline uint32_t FusionAltitudeAlphaBetaGetTimeoutCount(const FusionAltitudeAlphaBeta *const fusion,
                                                              const FusionAltitudeAlphaBetaSensorIndex sensor) {
    return fusion->filters[sensor].timeouts;
}

/** @return the number of gaps so far: updates with dt > gapPeriod once started. */
static inline uint32_t FusionAltitudeAlphaBetaGetGapCount(const FusionAltitudeAlphaBeta *const fusion) {
    return fusion->gapCount;
}

/** @return true once the fusion has started (first non-IMU sample); false from a gap or a dead-reckoning timeout to the next sample. */
static inline bool FusionAltitudeAlphaBetaIsStarted(const FusionAltitudeAlphaBeta *const fusion) {
    return fusion->started;
}

#undef FUSION_ALTITUDE_ALPHABETA_NO_CONTRACT

#ifdef FUSION_ALTITUDE_ALPHABETA_GCC_NO_CONTRACT
#pragma GCC pop_options
#undef FUSION_ALTITUDE_ALPHABETA_GCC_NO_CONTRACT
#endif

#ifdef __cplusplus
}
#endif

#endif
