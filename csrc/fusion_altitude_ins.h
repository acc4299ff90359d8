/**
 * @file fusion_altitude_ins.h
 * @brief Inertial navigation filter: attitude, gyroscope bias, height and
 * vertical velocity from a raw gyroscope and accelerometer, a barometer and
 * (optionally) a magnetometer. An error-state extended Kalman filter.
 *
 * Header-only C99 (also valid C++), float32 only, no malloc, no globals. The
 * only math library call is sqrtf (one instruction on FPU microcontrollers);
 * no trigonometry anywhere. Needs fusion_altitude.h next to it.
 *
 * Units and frames
 *   gyro     rad/s, body frame          accel  m/s^2 specific force, body frame
 *   mag      any unit, body frame       baro   m (baro altitude), +up
 *   dt       s                          outputs m, m/s, +up
 * Body axes are any right-handed set; the earth frame is NWU (x north, y
 * west, z UP), the imufusion/Fusion default: a level IMU at rest reads
 * accel = (0, 0, +9.81). NED users: negate distance and velocity.
 *
 * Nominal state (kept as values, not in the filter vector)
 *   q      local attitude, unit quaternion body -> local earth; the local
 *          yaw starts at 0 and is integrated, it never sees the magnetometer
 *   b      gyroscope bias, rad/s, body frame
 *   d      vertical distance above the reference, m, +up
 *   v      vertical velocity, m/s, +up
 * Error state x (index: quantity), the EKF's vector, zero after each step:
 *   0..2 dtheta  attitude error angle-axis, body frame: q_true = q (x) (1, dtheta/2)
 *   3..5 db      gyroscope bias error, rad/s
 *   6    dd      distance error, m
 *   7    dv      velocity error, m/s
 * Separate complementary filters (not EKF states):
 *   yaw offset local -> global (cos, sin), from the magnetometer only
 *   baro bias (the baro altitude at d = 0), learned while stationary
 *   accel z bias (body z), learned while stationary
 *
 * Prediction at the IMU rate, with w = gyro - b and f = accel - (0, 0, bz):
 *   q <- normalise(q (x) (1, w*dt/2))
 *   a = (R(q) f)_z - g        vertical acceleration, m/s^2, +up
 *   d <- d + v*dt + a*dt^2/2,   v <- v + a*dt
 *   F: dtheta <- (I - [w dt]x) dtheta - dt*db,   dv <- dv + dt*c.dtheta,
 *      dd <- dd + dt*dv + dt^2/2*c.dtheta   with c = f x r, r = R^T e_z
 *   P <- F P F^T + Q,  Q = dt*diag(Ng^2 I, Nb^2 I, 0, 0) + Na^2*dt*(dt^2/4, dt/2; dt/2, 1) on (d, v);
 *   a variance of d or v above FUSION_ALTITUDE_INS_VARIANCE_LIMIT: its row
 *   and column are zeroed and the variance held at the limit
 * Corrections, sequential scalar updates on the error state:
 *   accel   u = f/|f| measures the body gravity direction r: u = r + [r]x dtheta;
 *           the two rows of [r]x with the smallest |r_k| are used (the third
 *           is their combination), noise sigma accelAttitudeNoise (rad).
 *           Acceleration rejection (the Fusion AHRS idea): skipped when
 *           | |f| - g | > accelNormRejection, or when |u - r|^2 (the squared
 *           chord of the angle between measured and predicted gravity,
 *           ~ angle^2) > accelRejection^2, unless rejected for longer than
 *           recoveryTriggerPeriod (then the angle gate is lifted until a
 *           sample is fused).
 *   yaw     if r^T P_theta r > FUSION_ALTITUDE_INS_YAW_VARIANCE_LIMIT: r.dtheta = 0
 *           with that variance (caps the unobservable local yaw variance).
 *   stationary  zero rate (gyro = b, sigma zeroRateNoise) and zero velocity
 *           (v = 0, sigma zeroVelocityNoise).
 *   baro    z = baro - baroBias measures d (sigma baroNoise); not while
 *           stationary, when every baro reading goes to the baro bias.
 *           Innovation gate: rejected when y^2 > baroGate^2 * S (a glitch,
 *           a pyro or transonic spike: the INS coasts on the IMU); a
 *           rejection streak longer than baroRejectionTimeout (s) means the
 *           INS height is what is wrong (it drifted, or the vehicle moved
 *           during the streak): d is decorrelated with the variance
 *           FUSION_ALTITUDE_INS_VARIANCE_LIMIT, the velocity variance raised
 *           to at least initialVelocitySigma^2, and the reading fused (it
 *           sets d; baroResets += 1). The streak's clock runs by dt; a gap ends it.
 *   Each: c = P h^T, S = h c + R, K = c/S, y = z - h (x_nominal + dx),
 *   dx += K y, P <- P - c c^T / S, entry by entry P_ij - (c_i c_j)(1/S), so
 *   that entry (i, j) and entry (j, i) round identically: P stays exactly
 *   symmetric. With the optimal gain K = c/S this equals the Joseph form
 *   (I-Kh)P(I-Kh)^T + K R K^T in exact arithmetic; in float32 neither keeps P
 *   positive semi-definite by itself (the conditioning below does the repair).
 *   Once per step, after the prediction and the corrections, P is conditioned:
 *   an attitude variance above FUSION_ALTITUDE_INS_ATTITUDE_VARIANCE_LIMIT is
 *   decorrelated and held there, negative variances are floored at 0 and covariances clipped to
 *   |P_ij| <= sqrt(P_ii P_jj) (see FusionAltitudeInsConditionCovariance).
 *   At the end of the step dx is injected: q <- normalise(q (x) (1, dtheta/2)),
 *   b += db, d += dd, v += dv (reset Jacobian I - [dtheta/2]x taken as I).
 * Stationary detection: stationary once |gyro| < stationaryGyroThreshold and
 *   | |accel| - g | < stationaryAccelThreshold have held on every sample for
 *   stationaryWindow s (a timer that restarts on any failing sample or gap)
 *   and the baro holds still: the means of its readings over consecutive half
 *   windows differ by at most stationaryBaroRate * stationaryWindow / 2 (m)
 *   (a constant-velocity climb is still to the IMU; no baro: no veto).
 *   While stationary: baroBias += k (baro - d - baroBias), k = e/(tau_b + e)
 *   with e the time since the previous baro sample; accelZBias += k (f_z -
 *   g r_z - accelZBias) with the raw accel z and k = dt/(tau_a + dt).
 * Magnetometer: m_l = R(q) m (the field in the local frame); its horizontal
 *   part sets the target yaw offset (c, s) = (m_lx, -m_ly)/|.|, filtered
 *   with k = e/(tau_m + e) and renormalised. The global attitude is
 *   q_g = (yaw offset about z) (x) q; the local q never depends on the mag.
 * Alignment: the first sample with | |accel| - g | <= accelNormRejection
 *   sets q to the shortest rotation taking accel to +z (yaw 0); samples
 *   before it are ignored (Ok, nothing changes).
 * Baro timeout and the dead-reckoning horizon (the baro is the INS's only
 *   height source). t = baroElapsed, the time since the latest baro reading
 *   (a reading the gate rejects counts: the baro is alive). Once t >
 *   baroTimeout (default 1.5 s) the INS is not baro-aided: the flag
 *   (FusionAltitudeInsIsBaroTimedOut) is set and baroTimeouts += 1, once
 *   per silence; d and v are dead-reckoned from the IMU as before. A step
 *   that starts with t > deadReckoningHorizon (default 5 s) stops the dead
 *   reckoning (FusionAltitudeInsIsHeightHeld): the accelerometer no longer
 *   moves d and v; v decays to 0, v <- v - k v with k = dt/(horizon + dt)
 *   (time constant horizon s), d <- d + v dt (so d moves at most |v| *
 *   horizon further), d and v are decorrelated from the attitude and bias,
 *   the velocity variance is held at least initialVelocitySigma^2 and the
 *   height sigma grows by sigma_v per second, sqrt(P_dd) <- sqrt(P_dd) +
 *   sqrt(P_vv) dt (up to FUSION_ALTITUDE_INS_VARIANCE_LIMIT). Why decayed,
 *   not held: integrated for longer, an unaided vertical channel drifts
 *   as the square of time (0.1 m/s^2 of accel or attitude error: 1.25 m
 *   after 5 s, 125 m after 50 s; on a rocket's boost and coast, kilometres);
 *   a held velocity still runs away linearly, without bound; a decayed one
 *   bounds the height to |v| * horizon beyond the horizon while the variance
 *   says the height is no longer known. Why 5 s: ArduPilot's EKF3 resets
 *   its height after 5 s without height data, and PX4's EKF2 stops
 *   dead-reckoning after its 5 s no-aiding timeout. The next reading passes
 *   the gate (P_dd has grown) and sets d again.
 * Gaps: a dt > gapPeriod is not integrated: gapCount += 1, the prediction is
 *   skipped, the stationary timer restarts, the attitude and velocity
 *   variances are raised to at least their initial values (so the next
 *   corrections pull hard), and d is decorrelated with the variance
 *   FUSION_ALTITUDE_INS_VARIANCE_LIMIT (the next baro reading sets the
 *   height), a baro rejection streak ends; the step's corrections still run.
 *
 * Bit-exact results across compilers and targets need IEEE float32 without
 * fused multiply-add contraction; the header turns contraction off for gcc
 * (push_options / optimize) and clang (fp contract pragma) around its
 * functions, so -std=gnu11 -O2 gives the same bits as -std=c99.
 *
 * Usage:
 * @code
 * FusionAltitudeIns ins;
 * FusionAltitudeInsInitialise(&ins);                      // default settings
 * for (;;) {                                              // IMU rate
 *     const FusionAltitudeInsVector gyro = {gx, gy, gz};  // rad/s
 *     const FusionAltitudeInsVector accel = {ax, ay, az}; // m/s^2
 *     const float baro = baroReady ? baroAltitude : FUSION_ALTITUDE_NO_BARO;
 *     if (FusionAltitudeInsUpdate(&ins, gyro, accel, FusionAltitudeInsNoMag(), baro, dt) != FusionAltitudeInsStatusOk) {
 *         // input rejected, state unchanged
 *     }
 *     const float h = FusionAltitudeInsGetAltitude(&ins);  // m above the reference, +up
 * }
 * @endcode
 */

#ifndef FUSION_ALTITUDE_INS_H
#define FUSION_ALTITUDE_INS_H

#include "fusion_altitude.h"

#include <math.h> /* sqrtf only */
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__clang__)
#define FUSION_ALTITUDE_INS_NO_CONTRACT _Pragma("clang fp contract(off)")
#else
#define FUSION_ALTITUDE_INS_NO_CONTRACT
#endif

/* Small fixed loops of the covariance code fully unrolled by gcc and clang on PCs with SIMD (SSE2, NEON), where
 * each row is two vector operations and a loop of 8 rows costs as much in counting and branching as in
 * arithmetic; not under -Os, and not on microcontrollers (M4F -O2: the update grew to 16.3 kB of code). */
#if defined(__GNUC__) && !defined(__OPTIMIZE_SIZE__) && (defined(__SSE2__) || defined(__ARM_NEON))
#define FUSION_ALTITUDE_INS_UNROLL _Pragma("GCC unroll 8")
#else
#define FUSION_ALTITUDE_INS_UNROLL
#endif

/* The helpers that FusionAltitudeInsUpdate and FusionAltitudeInsPredict call once (split for reading, one job
 * each) are forced inline where the compiler allows it, so that the update compiles as the single function it was
 * before the split: gcc -Os and -O2 for Cortex-M and RISC-V otherwise keep some out of line (more instructions per
 * step, and the size tables of docs/embedded.md would miss them). */
#if defined(__GNUC__) || defined(__clang__)
#define FUSION_ALTITUDE_INS_ONCE __attribute__((always_inline))
#else
#define FUSION_ALTITUDE_INS_ONCE
#endif

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC push_options
#pragma GCC optimize("fp-contract=off")
#endif

//------------------------------------------------------------------------------
// Definitions

/** Number of error states. */
#define FUSION_ALTITUDE_INS_STATES (8)

/** Largest accepted setting and input magnitude, so that squares stay finite in float32. */
#define FUSION_ALTITUDE_INS_MAXIMUM (1e6f)

/** Largest |1 - |q|^2| normalised without a square root (see FusionAltitudeInsNormalise). */
#define FUSION_ALTITUDE_INS_NEWTON_NORM (1e-4f)

/** The bits of FUSION_ALTITUDE_INS_MAXIMUM (IEEE 754 binary32; the input check compares magnitude bits). */
#define FUSION_ALTITUDE_INS_MAXIMUM_BITS (0x49742400u)

/**
 * Largest variance of d (m^2) and v (m^2/s^2), 100 m and 100 m/s sigma. A
 * state unobserved for that long (no baro, never at rest) is decorrelated
 * from the others and held there: P stays positive semi-definite in float32
 * (a decorrelated row leaves a principal submatrix and a positive diagonal).
 */
#define FUSION_ALTITUDE_INS_VARIANCE_LIMIT (1e4f)

/**
 * Largest variance of each attitude error component (rad^2, 10 rad sigma: an
 * attitude known that poorly is not known at all). Applied at the end of
 * every step (FusionAltitudeInsConditionCovariance): a larger one has its row
 * and column zeroed and is held at the limit. Never reached in normal
 * operation; it bounds the float32 failure the fuzzer found
 * (csrc/fuzz/findings/ins_attitude_variance_growth.bin): once round-off makes
 * the attitude block indefinite, each correction deepens the negative
 * direction and P grows about 100-fold per step to infinity; decorrelating
 * the row leaves a positive diagonal from which P recovers.
 */
#define FUSION_ALTITUDE_INS_ATTITUDE_VARIANCE_LIMIT (1e2f)

/**
 * Largest variance of the local yaw error r.dtheta (rad^2, 0.57 deg sigma):
 * the local yaw is unobservable by design (no magnetometer), so its variance
 * would grow without end and float32 round-off would make P indefinite.
 * Above it, a pseudo-measurement r.dtheta = 0 with this variance is fused.
 * The local yaw is arbitrary, so this changes no estimate beyond round-off.
 */
#define FUSION_ALTITUDE_INS_YAW_VARIANCE_LIMIT (1e-4f)

/** Three-axis vector. */
typedef struct {
    float x;
    float y;
    float z;
} FusionAltitudeInsVector;

/** Quaternion (w, x, y, z). */
typedef struct {
    float w;
    float x;
    float y;
    float z;
} FusionAltitudeInsQuaternion;

/** Status returned by every function that can reject its input. */
typedef enum {
    FusionAltitudeInsStatusOk = 0,
    FusionAltitudeInsStatusInvalidGyro,         /**< a gyro component not finite or |.| > 1e6 */
    FusionAltitudeInsStatusInvalidAccel,        /**< an accel component not finite or |.| > 1e6 */
    FusionAltitudeInsStatusInvalidMag,          /**< mag not all NaN (no sample) and not all finite with |.| <= 1e6 */
    FusionAltitudeInsStatusInvalidBaroAltitude, /**< baro altitude infinite or |.| > 1e6 (NaN: no sample) */
    FusionAltitudeInsStatusInvalidDt,           /**< dt not finite or <= 0 */
    FusionAltitudeInsStatusInvalidSettings,     /**< a setting out of its range (see FusionAltitudeInsSettingsCheck) */
} FusionAltitudeInsStatus;

/** Settings, all in physical units. */
typedef struct {
    float gyroNoise;               /**< Ng, rad/s/sqrt(Hz): gyro white-noise density [rule: finite, >= 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float gyroBiasRandomWalk;      /**< Nb, rad/s^2/sqrt(Hz): gyro bias random walk [rule: finite, >= 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float accelNoise;              /**< Na, m/s^2/sqrt(Hz): vertical acceleration noise density (vibration included) [rule: finite, >= 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float accelAttitudeNoise;      /**< rad: 1 sigma of the gravity direction per sample (> 0) [rule: finite, > 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float accelNormRejection;      /**< m/s^2: accel not used for attitude when ||f| - g| exceeds it [rule: finite, >= 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float accelRejection;          /**< rad: accel not used for attitude when its direction is further from the prediction [rule: finite, >= 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float recoveryTriggerPeriod;   /**< s: rejected for longer lifts the angle gate [rule: finite, >= 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float baroNoise;               /**< m: 1 sigma per baro sample (> 0) [rule: finite, > 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float stationaryGyroThreshold; /**< rad/s: |gyro| below it counts as still [rule: finite, >= 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float stationaryAccelThreshold; /**< m/s^2: ||accel| - g| below it counts as still [rule: finite, >= 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float stationaryWindow;        /**< s: still for this long = stationary [rule: finite, >= 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float zeroRateNoise;           /**< rad/s: 1 sigma of the zero-rate update while stationary (> 0) [rule: finite, > 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float zeroVelocityNoise;       /**< m/s: 1 sigma of the zero-velocity update while stationary (> 0) [rule: finite, > 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float baroBiasTimeConstant;    /**< s: baro bias filter while stationary (> 0) [rule: finite, > 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float accelBiasTimeConstant;   /**< s: accel z bias filter while stationary (> 0) [rule: finite, > 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float magTimeConstant;         /**< s: local-to-global yaw filter (> 0) [rule: finite, > 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float initialAttitudeSigma;    /**< rad: attitude uncertainty after alignment [rule: finite, >= 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float initialGyroBiasSigma;    /**< rad/s: initial gyro bias uncertainty [rule: finite, >= 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float initialVelocitySigma;    /**< m/s: initial velocity uncertainty [rule: finite, >= 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float gapPeriod;               /**< s: a dt above it is a gap, not integrated (> 0) [rule: finite, > 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float stationaryBaroRate;      /**< m/s: the baro moving faster than this (half-window means) vetoes stationary [rule: finite, >= 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float baroGate;                /**< sigmas: a baro reading with innovation y^2 > baroGate^2 S is rejected (> 0) [rule: finite, > 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float baroRejectionTimeout;    /**< s: baro rejected for longer: d reset from the next reading [rule: finite, >= 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float baroTimeout;             /**< s: no baro reading for longer: not baro-aided (flag, counted) (> 0) [rule: finite, > 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
    float deadReckoningHorizon;    /**< s: no baro reading for longer: dead reckoning stops, v decays with this time constant (> 0) [rule: finite, > 0, <= FUSION_ALTITUDE_INS_MAXIMUM; else InvalidSettings] */
} FusionAltitudeInsSettings;

/** Filter state. Read it through the Get functions. */
typedef struct {
    FusionAltitudeInsSettings settings;
    float q[4];                /**< local attitude body -> local earth (w, x, y, z) */
    float gyroBias[3];         /**< rad/s, body */
    float distance;            /**< d, m, +up */
    float velocity;            /**< v, m/s, +up */
    float P[FUSION_ALTITUDE_INS_STATES][FUSION_ALTITUDE_INS_STATES]; /**< error covariance, exactly symmetric */
    float accelZBias;          /**< m/s^2, body z, subtracted from accel z */
    float baroBias;            /**< m: baro altitude at d = 0 */
    float yawCos;              /**< local -> global yaw offset, cos */
    float yawSin;              /**< local -> global yaw offset, sin */
    float stationaryTime;      /**< s still so far (capped at the window) */
    float rejectionTime;       /**< s of consecutive accel rejections */
    float baroElapsed;         /**< s since the previous baro sample */
    float magElapsed;          /**< s since the previous mag sample */
    float stationaryHalfTime;  /**< s into the current half of the stationary window */
    float stationaryBaroSum;   /**< m: sum of the baro readings of the current half window */
    float stationaryBaroCount; /**< baro readings in the current half window */
    float stationaryBaroPrevious; /**< m: mean baro of the previous half window */
    float baroRejectingFor;    /**< s since the first reading of the current baro rejection streak; 0 when none */
    uint32_t gapCount;         /**< steps with dt > gapPeriod, not integrated */
    uint32_t baroRejections;   /**< baro readings rejected by the gate, in total */
    uint32_t baroResets;       /**< d reset from the baro after a rejection streak longer than the timeout, in total */
    uint32_t baroTimeouts;     /**< silences of the baro longer than baroTimeout, in total (each counted once) */
    bool aligned;              /**< attitude set from the first usable accel sample */
    bool baroInitialised;      /**< baro bias set from the first baro sample */
    bool magInitialised;       /**< yaw offset set from the first usable mag sample */
    bool stationary;           /**< stationary detected this step */
    bool stationaryHalfDone;   /**< a half window completed since still began */
    bool stationaryHasPrevious; /**< the previous half window had a baro reading */
    bool stationaryBaroStill;  /**< no baro veto: the latest half-window test found the baro still (or no readings) */
    bool accelRejected;        /**< the latest step did not use the accel for attitude */
    bool baroRejecting;        /**< a baro rejection streak is in progress */
} FusionAltitudeIns;

//------------------------------------------------------------------------------
// Status messages

/** @return a short English description of the status, never NULL. */
static inline const char *FusionAltitudeInsStatusMessage(const FusionAltitudeInsStatus status) {
    static const char *const texts[] = { /* in the enum's order */
        "ok", /* FusionAltitudeInsStatusOk */
        "gyro components must be finite with magnitude <= 1e6 rad/s", /* FusionAltitudeInsStatusInvalidGyro */
        "accel components must be finite with magnitude <= 1e6 m/s^2", /* FusionAltitudeInsStatusInvalidAccel */
        "mag components must be all NaN (no sample) or all finite with magnitude <= 1e6", /* FusionAltitudeInsStatusInvalidMag */
        "baro altitude must be finite with magnitude <= 1e6 m (or NaN for no sample)", /* FusionAltitudeInsStatusInvalidBaroAltitude */
        "dt must be finite and > 0", /* FusionAltitudeInsStatusInvalidDt */
        "settings must be finite, >= 0 and <= 1e6 (noises, time constants and gap period > 0)", /* FusionAltitudeInsStatusInvalidSettings */
    };
    return FusionAltitudeStatusText(texts, sizeof(texts) / sizeof(texts[0]), (size_t) status);
}

//------------------------------------------------------------------------------
// Settings

/**
 * @return the default settings (MEMS IMU at 100-500 Hz on a multirotor):
 *   gyroNoise 3e-4 rad/s/sqrt(Hz), gyroBiasRandomWalk 1e-5 rad/s^2/sqrt(Hz),
 *   accelNoise 0.05 m/s^2/sqrt(Hz), accelAttitudeNoise 0.05 rad,
 *   accelNormRejection 2 m/s^2, accelRejection 0.17 rad (~10 deg),
 *   recoveryTriggerPeriod 5 s, baroNoise 0.3 m, stationary below 0.05 rad/s
 *   and 0.5 m/s^2 for 1 s, zeroRateNoise 0.01 rad/s, zeroVelocityNoise
 *   0.05 m/s, baroBiasTimeConstant 5 s, accelBiasTimeConstant 2 s, magTimeConstant 2 s, initial sigmas
 *   0.05 rad, 0.01 rad/s, 0.5 m/s, gapPeriod 0.1 s, stationaryBaroRate 0.5 m/s,
 *   baroGate 5 sigma, baroRejectionTimeout 1 s (as the Kalman filter's gate),
 *   baroTimeout 1.5 s (three periods of a 2 Hz baro, longer than a 1 Hz
 *   one's period; as the Kalman filter's and the alpha-beta fusion's),
 *   deadReckoningHorizon 5 s (see the file comment).
 */
static inline FusionAltitudeInsSettings FusionAltitudeInsSettingsDefault(void) {
    FusionAltitudeInsSettings s;
    s.gyroNoise = 3e-4f;
    s.gyroBiasRandomWalk = 1e-5f;
    s.accelNoise = 0.05f;
    s.accelAttitudeNoise = 0.05f;
    s.accelNormRejection = 2.0f;
    s.accelRejection = 0.17f;
    s.recoveryTriggerPeriod = 5.0f;
    s.baroNoise = 0.3f;
    s.stationaryGyroThreshold = 0.05f;
    s.stationaryAccelThreshold = 0.5f;
    s.stationaryWindow = 1.0f;
    s.zeroRateNoise = 0.01f;
    s.zeroVelocityNoise = 0.05f;
    s.baroBiasTimeConstant = 5.0f;
    s.accelBiasTimeConstant = 2.0f;
    s.magTimeConstant = 2.0f;
    s.initialAttitudeSigma = 0.05f;
    s.initialGyroBiasSigma = 0.01f;
    s.initialVelocitySigma = 0.5f;
    s.gapPeriod = 0.1f;
    s.stationaryBaroRate = 0.5f;
    s.baroGate = 5.0f;
    s.baroRejectionTimeout = 1.0f;
    s.baroTimeout = 1.5f;
    s.deadReckoningHorizon = 5.0f;
    return s;
}

/**
 * Checks the settings: every field finite in [0, 1e6]; accelAttitudeNoise,
 * baroNoise, zeroRateNoise, zeroVelocityNoise, the three time constants,
 * gapPeriod, baroGate, baroTimeout and deadReckoningHorizon > 0.
 */
static inline FusionAltitudeInsStatus FusionAltitudeInsSettingsCheck(const FusionAltitudeInsSettings *const s) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    const float limit = FUSION_ALTITUDE_INS_MAXIMUM; /* largest accepted setting */
    const bool nonNegative = FusionAltitudeIsNonNegative(s->gyroNoise, limit) && FusionAltitudeIsNonNegative(s->gyroBiasRandomWalk, limit) &&
                             FusionAltitudeIsNonNegative(s->accelNoise, limit) && FusionAltitudeIsNonNegative(s->accelNormRejection, limit) &&
                             FusionAltitudeIsNonNegative(s->accelRejection, limit) && FusionAltitudeIsNonNegative(s->recoveryTriggerPeriod, limit) &&
                             FusionAltitudeIsNonNegative(s->stationaryGyroThreshold, limit) &&
                             FusionAltitudeIsNonNegative(s->stationaryAccelThreshold, limit) &&
                             FusionAltitudeIsNonNegative(s->stationaryWindow, limit) && FusionAltitudeIsNonNegative(s->initialAttitudeSigma, limit) &&
                             FusionAltitudeIsNonNegative(s->initialGyroBiasSigma, limit) &&
                             FusionAltitudeIsNonNegative(s->initialVelocitySigma, limit) &&
                             FusionAltitudeIsNonNegative(s->stationaryBaroRate, limit) && FusionAltitudeIsNonNegative(s->baroRejectionTimeout, limit);
    const bool positive = FusionAltitudeIsPositive(s->accelAttitudeNoise, limit) && FusionAltitudeIsPositive(s->baroNoise, limit) &&
                          FusionAltitudeIsPositive(s->zeroRateNoise, limit) && FusionAltitudeIsPositive(s->zeroVelocityNoise, limit) &&
                          FusionAltitudeIsPositive(s->baroBiasTimeConstant, limit) && FusionAltitudeIsPositive(s->accelBiasTimeConstant, limit) &&
                          FusionAltitudeIsPositive(s->magTimeConstant, limit) && FusionAltitudeIsPositive(s->gapPeriod, limit) &&
                          FusionAltitudeIsPositive(s->baroGate, limit) && FusionAltitudeIsPositive(s->baroTimeout, limit) &&
                          FusionAltitudeIsPositive(s->deadReckoningHorizon, limit);
    return (nonNegative && positive) ? FusionAltitudeInsStatusOk : FusionAltitudeInsStatusInvalidSettings;
}

/** @return a magnetometer sample meaning "no sample this step" (all NaN). */
static inline FusionAltitudeInsVector FusionAltitudeInsNoMag(void) {
    FusionAltitudeInsVector m;
    m.x = FusionAltitudeNaN();
    m.y = FusionAltitudeNaN();
    m.z = FusionAltitudeNaN();
    return m;
}

//------------------------------------------------------------------------------
// Estimator

/** @internal Sets the covariance to its initial value: diag(sa^2 I, sb^2 I, 0, sv^2). */
static inline void FusionAltitudeInsResetCovariance(FusionAltitudeIns *const ins) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    const FusionAltitudeInsSettings *const s = &ins->settings;
    memset(ins->P, 0, sizeof(ins->P));
    const float attitude = s->initialAttitudeSigma * s->initialAttitudeSigma;
    const float bias = s->initialGyroBiasSigma * s->initialGyroBiasSigma;
    for (int i = 0; i < 3; i++) {
        ins->P[i][i] = attitude;
        ins->P[3 + i][3 + i] = bias;
    }
    ins->P[7][7] = s->initialVelocitySigma * s->initialVelocitySigma;
}

/** @internal Restarts stationary detection: the still timer (s) and the baro half-window test. */
static inline void FusionAltitudeInsRestartStationary(FusionAltitudeIns *const ins) {
    ins->stationaryTime = 0.0f;
    ins->stationaryHalfTime = 0.0f;
    ins->stationaryBaroSum = 0.0f;
    ins->stationaryBaroCount = 0.0f;
    ins->stationaryBaroPrevious = 0.0f;
    ins->stationaryHalfDone = false;
    ins->stationaryHasPrevious = false;
    ins->stationaryBaroStill = true; /* no baro reading yet: no veto */
}

/**
 * @brief Initialises the INS with the given settings (NULL: defaults;
 * rejected with the INS untouched if they fail the check): not aligned,
 * identity attitude, zero biases, d = v = 0, yaw offset 0.
 */
static inline FusionAltitudeInsStatus FusionAltitudeInsInitialiseWith(FusionAltitudeIns *const ins, const FusionAltitudeInsSettings *const settings) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    const FusionAltitudeInsSettings s = (settings == NULL) ? FusionAltitudeInsSettingsDefault() : *settings;
    if (FusionAltitudeInsSettingsCheck(&s) != FusionAltitudeInsStatusOk) {
        return FusionAltitudeInsStatusInvalidSettings;
    }
    memset(ins, 0, sizeof(*ins));
    ins->settings = s;
    ins->q[0] = 1.0f;
    ins->yawCos = 1.0f;
    FusionAltitudeInsRestartStationary(ins);
    FusionAltitudeInsResetCovariance(ins);
    return FusionAltitudeInsStatusOk;
}

/** @brief Initialises the INS with the default settings. */
static inline void FusionAltitudeInsInitialise(FusionAltitudeIns *const ins) {
    (void) FusionAltitudeInsInitialiseWith(ins, NULL);
}

/** @brief Replaces the settings, keeping the state. Rejected (state unchanged) if the check fails. */
static inline FusionAltitudeInsStatus FusionAltitudeInsSetSettings(FusionAltitudeIns *const ins, const FusionAltitudeInsSettings *const settings) {
    if (FusionAltitudeInsSettingsCheck(settings) != FusionAltitudeInsStatusOk) {
        return FusionAltitudeInsStatusInvalidSettings;
    }
    ins->settings = *settings;
    return FusionAltitudeInsStatusOk;
}

/** @internal |value| <= FUSION_ALTITUDE_INS_MAXIMUM and finite: on the magnitude bits, ordered as
   the magnitudes are for finite floats, with infinities and NaNs above every finite one (one integer compare;
   holds under -ffast-math too) */
static inline bool FusionAltitudeInsIsBounded(const float value) {
    return (FusionAltitudeFloatBits(value) & 0x7FFFFFFFu) <= FUSION_ALTITUDE_INS_MAXIMUM_BITS;
}

/** @internal @return true if every component of v is bounded (FusionAltitudeInsIsBounded). */
static inline bool FusionAltitudeInsIsBoundedVector(const FusionAltitudeInsVector v) {
    return FusionAltitudeInsIsBounded(v.x) && FusionAltitudeInsIsBounded(v.y) && FusionAltitudeInsIsBounded(v.z);
}

/** @return true if every component of the magnetometer sample is NaN (no sample). */
static inline bool FusionAltitudeInsIsNoMag(const FusionAltitudeInsVector m) {
    return FusionAltitudeIsNaN(m.x) && FusionAltitudeIsNaN(m.y) && FusionAltitudeIsNaN(m.z);
}

/** Checks the inputs of FusionAltitudeInsUpdate; the first bad one decides the status. */
static inline FusionAltitudeInsStatus FusionAltitudeInsCheckInputs(const FusionAltitudeInsVector gyro, const FusionAltitudeInsVector accel,
                                                                   const FusionAltitudeInsVector mag, const float baroAltitude, const float dt) {
    if (!FusionAltitudeInsIsBoundedVector(gyro)) {
        return FusionAltitudeInsStatusInvalidGyro;
    }
    if (!FusionAltitudeInsIsBoundedVector(accel)) {
        return FusionAltitudeInsStatusInvalidAccel;
    }
    if (!FusionAltitudeInsIsNoMag(mag) && !FusionAltitudeInsIsBoundedVector(mag)) {
        return FusionAltitudeInsStatusInvalidMag;
    }
    if (!FusionAltitudeIsNaN(baroAltitude) && !FusionAltitudeInsIsBounded(baroAltitude)) {
        return FusionAltitudeInsStatusInvalidBaroAltitude;
    }
    if (!FusionAltitudeIsFinite(dt) || !(dt > 0.0f)) {
        return FusionAltitudeInsStatusInvalidDt;
    }
    return FusionAltitudeInsStatusOk;
}

/** @internal
 * Normalises q in place (q is never near zero: it is a unit quaternion times a
 * factor >= 1). With n^2 = |q|^2 = 1 + e: 1/|q| = 1 - e/2 + 3e^2/8 - ..., so
 * for |e| < FUSION_ALTITUDE_INS_NEWTON_NORM (every step of a rotation under
 * 0.02 rad, 10 rad/s at 500 Hz) the factor is 1 - e/2 (one Newton step of
 * 1/sqrt from 1; error < 3e^2/8 < 4e-9, under half an ulp of 1) instead of
 * sqrtf and a division: the longest latency of the step on a PC and 28 cycles
 * on an M4F. Larger e (alignment, fast rotations): 1/sqrtf(n^2).
 */
static inline void FusionAltitudeInsNormalise(float q[4]) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    const float norm2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    const float excess = norm2 - 1.0f;
    const bool near = (excess < FUSION_ALTITUDE_INS_NEWTON_NORM) && (excess > -FUSION_ALTITUDE_INS_NEWTON_NORM);
    const float inverse = near ? (1.0f - 0.5f * excess) : (1.0f / sqrtf(norm2));
    q[0] = q[0] * inverse;
    q[1] = q[1] * inverse;
    q[2] = q[2] * inverse;
    q[3] = q[3] * inverse;
}

/** @internal q <- normalise(q (x) (1, h)) for a rotation vector half-angle h = theta/2 (body frame). */
static inline void FusionAltitudeInsRotate(float q[4], const float hx, const float hy, const float hz) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    const float w = q[0], x = q[1], y = q[2], z = q[3];
    q[0] = w - x * hx - y * hy - z * hz;
    q[1] = x + w * hx + y * hz - z * hy;
    q[2] = y + w * hy - x * hz + z * hx;
    q[3] = z + w * hz + x * hy - y * hx;
    FusionAltitudeInsNormalise(q);
}

/** @internal Third row of R(q) (body -> earth): r = R^T e_z, the up direction (gravity direction) in the body frame. */
static inline void FusionAltitudeInsUpInBody(const float q[4], float r[3]) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    const float w = q[0], x = q[1], y = q[2], z = q[3];
    r[0] = 2.0f * (x * z - w * y);
    r[1] = 2.0f * (y * z + w * x);
    r[2] = 1.0f - 2.0f * (x * x + y * y);
}

/** @internal
 * Decorrelates state k: row and column k of P zeroed, P[k][k] =
 * variance (a principal submatrix and a positive diagonal remain).
 */
static inline void FusionAltitudeInsDecorrelate(float P[FUSION_ALTITUDE_INS_STATES][FUSION_ALTITUDE_INS_STATES], const int k,
                                                const float variance) {
    for (int j = 0; j < FUSION_ALTITUDE_INS_STATES; j++) {
        P[k][j] = 0.0f;
        P[j][k] = 0.0f;
    }
    P[k][k] = variance;
}

/** @internal A variance P[k][k] above limit: state k decorrelated and its variance held at limit. */
static inline void FusionAltitudeInsHoldVariance(float P[FUSION_ALTITUDE_INS_STATES][FUSION_ALTITUDE_INS_STATES], const int k,
                                                 const float limit) {
    if (P[k][k] > limit) {
        FusionAltitudeInsDecorrelate(P, k, limit);
    }
}

/** @internal
 * Keeps P a covariance in float32 (called once per step, after the prediction
 * and all the corrections: once per update rather than after each scalar
 * update keeps the M4F step under its cycle budget): an attitude variance above
 * FUSION_ALTITUDE_INS_ATTITUDE_VARIANCE_LIMIT (rad^2) is decorrelated and held
 * there, a variance below 0 is set to 0 (the floor), and a
 * covariance beyond |P_ij| <= sqrt(P_ii P_jj) (|correlation| > 1) is clipped
 * to that bound with its sign kept (sqrtf only when clipping). Why: the
 * scalar update keeps P symmetric but, in float32, not positive
 * semi-definite once P's condition number nears 1/eps (1e7): a strongly
 * observed direction then rounds below zero. The fuzzer reached that
 * (csrc/fuzz/findings/ins_negative_attitude_variance.bin, default settings:
 * 1e5 m baro jumps pull large corrections through the cross-covariances, the
 * gyro bias estimate grows, F = I - [w dt]x stops being a near-rotation and
 * spreads P's eigenvalues from 7e-7 to 61 before a -1e-7 one appears; at
 * step 243 P[0][0] = -9.1e-6). This is the cheapest repair a microcontroller
 * EKF uses (8 compares, 28 products, no factorisation): it guarantees a
 * non-negative diagonal and every 2x2 principal minor >= 0, and it changes
 * nothing while P is well conditioned (no clip fires). It does not by itself
 * guarantee that the whole 8x8 P is positive semi-definite (a UD or square-
 * root filter would, at several times the cost).
 */
static inline void FusionAltitudeInsConditionCovariance(float P[FUSION_ALTITUDE_INS_STATES][FUSION_ALTITUDE_INS_STATES]) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    for (int i = 0; i < 3; i++) {
        FusionAltitudeInsHoldVariance(P, i, FUSION_ALTITUDE_INS_ATTITUDE_VARIANCE_LIMIT);
    }
    for (int i = 0; i < FUSION_ALTITUDE_INS_STATES; i++) {
        if (P[i][i] < 0.0f) {
            P[i][i] = 0.0f;
        }
    }
    /* the diagonal as one initialiser (built in registers on a PC: no vector load of eight scalar stores) */
    const float d[FUSION_ALTITUDE_INS_STATES] = {P[0][0], P[1][1], P[2][2], P[3][3], P[4][4], P[5][5], P[6][6], P[7][7]};
    /* Whether any covariance needs the clip: whole rows, no branch (vectorises on a PC). The diagonal never
       does (P_ii * P_ii > P_ii * P_ii is false), and clipping one entry changes no bound: the same set of
       entries as the loop below, which runs only then (rarely: only while P is ill-conditioned). */
    int32_t clip[4] = {0, 0, 0, 0};
    FUSION_ALTITUDE_INS_UNROLL
    for (int i = 0; i < FUSION_ALTITUDE_INS_STATES; i++) {
        for (int j = 0; j < 4; j++) {
            clip[j] |= -(int32_t) (P[i][j] * P[i][j] > d[i] * d[j]); /* a compare mask, OR-ed as it is */
            clip[j] |= -(int32_t) (P[i][4 + j] * P[i][4 + j] > d[i] * d[4 + j]);
        }
    }
    if ((clip[0] | clip[1] | clip[2] | clip[3]) == 0) {
        return;
    }
    for (int i = 0; i < FUSION_ALTITUDE_INS_STATES; i++) {
        for (int j = i + 1; j < FUSION_ALTITUDE_INS_STATES; j++) {
            const float bound2 = P[i][i] * P[j][j];
            if (P[i][j] * P[i][j] > bound2) {
                const float bound = sqrtf(bound2);
                const float clipped = (P[i][j] < 0.0f) ? -bound : bound;
                P[i][j] = clipped;
                P[j][i] = clipped;
            }
        }
    }
}

/** @internal
 * Scalar update given c = P h^T, S = h c + R and the innovation (z minus h
 * applied to the nominal state plus dx): K = c/S (c times 1/S),
 * dx += K*innovation, P <- P - (c c^T)/S, each entry P_ij - (c_i c_j)(1/S):
 * c_i c_j = c_j c_i exactly, so P stays bit-symmetric. With the optimal gain
 * this is the Joseph form (P - K c^T - c K^T + K K^T S) term for term in exact
 * arithmetic, at 2 products and 1 subtraction per entry instead of 4 and 3.
 */
static inline void FusionAltitudeInsFuseGain(FusionAltitudeIns *const ins, float dx[FUSION_ALTITUDE_INS_STATES], const float c[FUSION_ALTITUDE_INS_STATES],
                                             const float S, const float innovation) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    float(*const P)[FUSION_ALTITUDE_INS_STATES] = ins->P;
    const float inverseS = 1.0f / S;
    for (int i = 0; i < FUSION_ALTITUDE_INS_STATES; i++) {
        dx[i] = dx[i] + (c[i] * inverseS) * innovation;
    }
    /* every entry; (c_i c_j)(1/S) is symmetric in i and j (a*b = b*a exactly), so P stays bit-symmetric.
       Each row in two halves of four (one vector operation each on a PC, no inner loop). */
    FUSION_ALTITUDE_INS_UNROLL
    for (int i = 0; i < FUSION_ALTITUDE_INS_STATES; i++) {
        float *const row = P[i];
        const float ci = c[i];
        for (int j = 0; j < 4; j++) {
            row[j] = row[j] - (ci * c[j]) * inverseS;
        }
        for (int j = 4; j < FUSION_ALTITUDE_INS_STATES; j++) {
            row[j] = row[j] - (ci * c[j]) * inverseS;
        }
    }
}

/** @internal
 * Scalar update with a measurement row h that is non-zero only at indices
 * i0 (value h0) and i1 (value h1; i1 < 0: single index). Accumulates the
 * error state dx; y is the residual against the nominal state (the function
 * subtracts h dx itself). R: noise variance.
 */
static inline void FusionAltitudeInsFuse(FusionAltitudeIns *const ins, float dx[FUSION_ALTITUDE_INS_STATES], const int i0, const float h0,
                                         const int i1, const float h1, const float y, const float R) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    float(*const P)[FUSION_ALTITUDE_INS_STATES] = ins->P;
    /* c = P h^T; column i0 of P read as row i0 (P is exactly symmetric: the same bits, contiguous) */
    float c[FUSION_ALTITUDE_INS_STATES];
    if (i1 < 0) {
        for (int i = 0; i < FUSION_ALTITUDE_INS_STATES; i++) {
            c[i] = P[i0][i] * h0;
        }
    } else {
        for (int i = 0; i < FUSION_ALTITUDE_INS_STATES; i++) {
            c[i] = P[i0][i] * h0 + P[i1][i] * h1;
        }
    }
    const float hc = (i1 < 0) ? (h0 * c[i0]) : (h0 * c[i0] + h1 * c[i1]);
    const float hdx = (i1 < 0) ? (h0 * dx[i0]) : (h0 * dx[i0] + h1 * dx[i1]);
    FusionAltitudeInsFuseGain(ins, dx, c, hc + R, y - hdx);
}

/** @internal Caps the local yaw error variance r^T P r (see FUSION_ALTITUDE_INS_YAW_VARIANCE_LIMIT). */
static inline void FusionAltitudeInsLimitYaw(FusionAltitudeIns *const ins, float dx[FUSION_ALTITUDE_INS_STATES], const float r[3]) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    float(*const P)[FUSION_ALTITUDE_INS_STATES] = ins->P;
    float c[FUSION_ALTITUDE_INS_STATES];
    for (int i = 0; i < FUSION_ALTITUDE_INS_STATES; i++) {
        c[i] = P[0][i] * r[0] + P[1][i] * r[1] + P[2][i] * r[2]; /* rows 0..2 = columns 0..2 (P symmetric) */
    }
    const float hc = r[0] * c[0] + r[1] * c[1] + r[2] * c[2];
    if (hc > FUSION_ALTITUDE_INS_YAW_VARIANCE_LIMIT) {
        const float hdx = r[0] * dx[0] + r[1] * dx[1] + r[2] * dx[2];
        FusionAltitudeInsFuseGain(ins, dx, c, hc + FUSION_ALTITUDE_INS_YAW_VARIANCE_LIMIT, 0.0f - hdx);
    }
}

/** @internal
 * Sets q to the shortest rotation taking the body vector f to +z: yaw 0.
 * @return false (nothing changed) if |f| is 0 in float32: no direction (an
 * accelNormRejection of g or more lets a zero accel through the norm test;
 * fuzz_ins.c found the NaN attitude it made).
 */
static inline bool FusionAltitudeInsAlign(FusionAltitudeIns *const ins, const FusionAltitudeInsVector f) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    const float norm = sqrtf(f.x * f.x + f.y * f.y + f.z * f.z);
    if (!(norm > 0.0f)) {
        return false;
    }
    const float ux = f.x / norm, uy = f.y / norm, uz = f.z / norm;
    /* q = normalise(1 + u.e_z, u x e_z) = normalise(1 + uz, uy, -ux, 0); u = -e_z: 180 deg about x */
    if (uz > -0.999999f) {
        ins->q[0] = 1.0f + uz;
        ins->q[1] = uy;
        ins->q[2] = -ux;
        ins->q[3] = 0.0f;
        FusionAltitudeInsNormalise(ins->q);
    } else {
        ins->q[0] = 0.0f;
        ins->q[1] = 1.0f;
        ins->q[2] = 0.0f;
        ins->q[3] = 0.0f;
    }
    ins->aligned = true;
    return true;
}

/** @internal
 * Covariance prediction P = F P F^T (Q added by the caller) with the Jacobian
 * pieces of the file comment: A = I - [w dt]x (a = w dt, rad), row v of F on
 * dtheta v = dt (f x r) (m/s per rad), row d of F on dtheta h = dt^2/2 (f x r)
 * (m per rad); dt: s.
 */
static inline FUSION_ALTITUDE_INS_ONCE void FusionAltitudeInsPredictCovariance(float P[FUSION_ALTITUDE_INS_STATES][FUSION_ALTITUDE_INS_STATES],
                                                                               const float ax, const float ay, const float az, const float vx,
                                                                               const float vy, const float vz, const float hx, const float hy,
                                                                               const float hz, const float dt) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    /* G = F P: rows theta, d and v change; rows b are those of P (copied: P is overwritten below). Whole rows,
       combined element-wise over the columns (vectorises on a PC). */
    float G[FUSION_ALTITUDE_INS_STATES][FUSION_ALTITUDE_INS_STATES];
    for (int j = 0; j < FUSION_ALTITUDE_INS_STATES; j++) {
        G[0][j] = P[0][j] + az * P[1][j] - ay * P[2][j] - dt * P[3][j];
        G[1][j] = P[1][j] - az * P[0][j] + ax * P[2][j] - dt * P[4][j];
        G[2][j] = P[2][j] + ay * P[0][j] - ax * P[1][j] - dt * P[5][j];
        G[3][j] = P[3][j];
        G[4][j] = P[4][j];
        G[5][j] = P[5][j];
        G[6][j] = P[6][j] + dt * P[7][j] + hx * P[0][j] + hy * P[1][j] + hz * P[2][j];
        G[7][j] = P[7][j] + vx * P[0][j] + vy * P[1][j] + vz * P[2][j];
    }
    /* P = G F^T, the upper triangle only (j >= i), mirrored: entry (i, j) is row j of F applied to row i of G.
       Rows 3..5 of F are those of I (copies); column by column, from the last (every row) to the first (row 0). */
    FUSION_ALTITUDE_INS_UNROLL
    for (int i = 0; i < FUSION_ALTITUDE_INS_STATES; i++) {
        const float m = G[i][7] + vx * G[i][0] + vy * G[i][1] + vz * G[i][2];
        P[i][7] = m;
        P[7][i] = m;
    }
    FUSION_ALTITUDE_INS_UNROLL
    for (int i = 0; i < 7; i++) {
        const float m = G[i][6] + dt * G[i][7] + hx * G[i][0] + hy * G[i][1] + hz * G[i][2];
        P[i][6] = m;
        P[6][i] = m;
    }
    FUSION_ALTITUDE_INS_UNROLL
    for (int j = 5; j >= 3; j--) {
        FUSION_ALTITUDE_INS_UNROLL
        for (int i = 0; i <= j; i++) {
            P[i][j] = G[i][j];
            P[j][i] = G[i][j];
        }
    }
    FUSION_ALTITUDE_INS_UNROLL
    for (int i = 0; i < 3; i++) {
        const float m = G[i][2] + ay * G[i][0] - ax * G[i][1] - dt * G[i][5];
        P[i][2] = m;
        P[2][i] = m;
    }
    FUSION_ALTITUDE_INS_UNROLL
    for (int i = 0; i < 2; i++) {
        const float m = G[i][1] - az * G[i][0] + ax * G[i][2] - dt * G[i][4];
        P[i][1] = m;
        P[1][i] = m;
    }
    P[0][0] = G[0][0] + az * G[0][1] - ay * G[0][2] - dt * G[0][3];
}

/** @internal
 * Process noise over dt (s): gyroNoise^2 dt (rad^2) on the attitude,
 * gyroBiasRandomWalk^2 dt ((rad/s)^2) on the gyro bias, and accelNoise^2 dt
 * times [dt^2/4, dt/2; dt/2, 1] on (d, v) (m^2, m^2/s, m^2/s^2). d and v
 * unobserved for long (no baro, never at rest): a variance above
 * FUSION_ALTITUDE_INS_VARIANCE_LIMIT is decorrelated and held at the limit.
 */
static inline FUSION_ALTITUDE_INS_ONCE void FusionAltitudeInsAddProcessNoise(FusionAltitudeIns *const ins, const float dt) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    float(*const P)[FUSION_ALTITUDE_INS_STATES] = ins->P;
    const FusionAltitudeInsSettings *const s = &ins->settings;
    const float halfDt = 0.5f * dt;
    const float qTheta = s->gyroNoise * s->gyroNoise * dt;
    const float qBias = s->gyroBiasRandomWalk * s->gyroBiasRandomWalk * dt;
    const float qAccel = s->accelNoise * s->accelNoise * dt;
    for (int i = 0; i < 3; i++) {
        P[i][i] = P[i][i] + qTheta;
        P[3 + i][3 + i] = P[3 + i][3 + i] + qBias;
    }
    P[6][6] = P[6][6] + qAccel * (0.25f * dt * dt);
    P[6][7] = P[6][7] + qAccel * halfDt;
    P[7][6] = P[6][7];
    P[7][7] = P[7][7] + qAccel;
    for (int k = 6; k < FUSION_ALTITUDE_INS_STATES; k++) {
        FusionAltitudeInsHoldVariance(P, k, FUSION_ALTITUDE_INS_VARIANCE_LIMIT);
    }
}

/** @internal
 * Prediction over dt (see the file comment). Internal: inputs checked.
 * w: bias-corrected rate (rad/s); f: bias-corrected specific force (m/s^2).
 * d += v dt + a dt^2/2, v += a dt with a = r . f - g (m/s^2, r: up in the body
 * at the start of the step); q = q (x) [1, w dt/2]; then P = F P F^T + Q.
 */
static inline void FusionAltitudeInsPredict(FusionAltitudeIns *const ins, const float w[3], const float f[3], const float dt) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    const float halfDt = 0.5f * dt;
    const float halfDt2 = halfDt * dt;
    /* vertical acceleration with the attitude at the start of the step */
    float r[3];
    FusionAltitudeInsUpInBody(ins->q, r);
    const float accel = (r[0] * f[0] + r[1] * f[1] + r[2] * f[2]) - FUSION_ALTITUDE_GRAVITY;
    ins->distance = ins->distance + ins->velocity * dt + accel * halfDt2;
    ins->velocity = ins->velocity + accel * dt;
    FusionAltitudeInsRotate(ins->q, w[0] * halfDt, w[1] * halfDt, w[2] * halfDt);
    /* Jacobian pieces: A = I - [w dt]x, c = f x r */
    const float ax = w[0] * dt, ay = w[1] * dt, az = w[2] * dt;
    const float cx = f[1] * r[2] - f[2] * r[1];
    const float cy = f[2] * r[0] - f[0] * r[2];
    const float cz = f[0] * r[1] - f[1] * r[0];
    const float vx = dt * cx, vy = dt * cy, vz = dt * cz;             /* row v of F on dtheta */
    const float hx = halfDt2 * cx, hy = halfDt2 * cy, hz = halfDt2 * cz; /* row d of F on dtheta */
    FusionAltitudeInsPredictCovariance(ins->P, ax, ay, az, vx, vy, vz, hx, hy, hz, dt);
    FusionAltitudeInsAddProcessNoise(ins, dt);
}

/** @internal
 * The height is unknown (after a gap, or a baro rejection streak
 * longer than its timeout): the velocity variance ((m/s)^2) is raised to at
 * least initialVelocitySigma^2 and d is decorrelated with the variance
 * FUSION_ALTITUDE_INS_VARIANCE_LIMIT (m^2), so the next baro reading sets d
 * instead of pulling the velocity.
 */
static inline void FusionAltitudeInsForgetHeight(FusionAltitudeIns *const ins) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    const float velocity = ins->settings.initialVelocitySigma * ins->settings.initialVelocitySigma;
    ins->P[7][7] = (ins->P[7][7] > velocity) ? ins->P[7][7] : velocity;
    FusionAltitudeInsDecorrelate(ins->P, 6, FUSION_ALTITUDE_INS_VARIANCE_LIMIT);
}

/** @internal
 * True once the baro has had a reading and none for longer than
 * timeout (s) since: baroElapsed > timeout.
 */
static inline bool FusionAltitudeInsIsBaroSilentFor(const FusionAltitudeIns *const ins, const float timeout) {
    return ins->baroInitialised && (ins->baroElapsed > timeout);
}

/** @internal
 * A step beyond the dead-reckoning horizon (see the file comment),
 * after the prediction from d0 (m) and v0 (m/s) over dt (s): the accelerometer
 * no longer moves d and v; v decays, v = v0 - k v0 with k = dt/(horizon + dt),
 * d = d0 + v dt; d and v are decorrelated, P_vv (m^2/s^2) held at least
 * initialVelocitySigma^2 and the height sigma grown by sqrt(P_vv) dt (m),
 * P_dd (m^2) at most FUSION_ALTITUDE_INS_VARIANCE_LIMIT.
 */
static inline FUSION_ALTITUDE_INS_ONCE void FusionAltitudeInsHoldHeight(FusionAltitudeIns *const ins, const float d0, const float v0,
                                                                        const float dt) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    const FusionAltitudeInsSettings *const s = &ins->settings;
    const float k = dt / (s->deadReckoningHorizon + dt);
    ins->velocity = v0 - k * v0;
    ins->distance = d0 + ins->velocity * dt;
    const float velocityFloor = s->initialVelocitySigma * s->initialVelocitySigma;
    const float pvv = (ins->P[7][7] > velocityFloor) ? ins->P[7][7] : velocityFloor;
    const float pdd = (ins->P[6][6] > 0.0f) ? ins->P[6][6] : 0.0f;
    const float sigma = sqrtf(pdd) + sqrtf(pvv) * dt;
    const float grown = sigma * sigma;
    FusionAltitudeInsDecorrelate(ins->P, 6, (grown < FUSION_ALTITUDE_INS_VARIANCE_LIMIT) ? grown : FUSION_ALTITUDE_INS_VARIANCE_LIMIT);
    FusionAltitudeInsDecorrelate(ins->P, 7, pvv);
}

/** @internal
 * Gap (dt > gapPeriod, s): the step is not integrated; the attitude variances
 * (rad^2) are raised to at least initialAttitudeSigma^2 and the velocity
 * variance ((m/s)^2) to at least initialVelocitySigma^2; the height is
 * unknown (the vehicle moved during the gap): d is decorrelated with the
 * variance FUSION_ALTITUDE_INS_VARIANCE_LIMIT (m^2), so the next baro reading
 * sets it instead of pulling the velocity; and stationary detection restarts
 * (stationaryTime = 0 s).
 */
static inline FUSION_ALTITUDE_INS_ONCE void FusionAltitudeInsGap(FusionAltitudeIns *const ins) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    const FusionAltitudeInsSettings *const s = &ins->settings;
    ins->gapCount++;
    const float attitude = s->initialAttitudeSigma * s->initialAttitudeSigma;
    for (int i = 0; i < 3; i++) {
        ins->P[i][i] = (ins->P[i][i] > attitude) ? ins->P[i][i] : attitude;
    }
    FusionAltitudeInsForgetHeight(ins);
    FusionAltitudeInsRestartStationary(ins);
    ins->baroRejecting = false; /* the gap ends a baro rejection streak */
    ins->baroRejectingFor = 0.0f;
}

/** @internal
 * Stationary detection on the raw samples: still when |gyro|^2 <
 * stationaryGyroThreshold^2 ((rad/s)^2) and the accel norm error
 * ||accel| - g| < stationaryAccelThreshold (m/s^2); stationaryTime (s) grows by
 * dt (s) while still, held at stationaryWindow (s), and restarts otherwise.
 * A climb or descent at constant velocity is still to the IMU, so the baro
 * (baroAltitude, m; NaN: none) may veto: while still, its readings are averaged
 * over half windows (stationaryWindow / 2, s); at the end of each half after
 * the first, the baro is still unless both halves have readings and their
 * means differ by more than stationaryBaroRate * stationaryWindow / 2 (m).
 * Readings in the first half veto until that first comparison; with no
 * reading the IMU alone decides, as without this test.
 */
static inline FUSION_ALTITUDE_INS_ONCE void FusionAltitudeInsDetectStationary(FusionAltitudeIns *const ins, const FusionAltitudeInsVector gyro,
                                                                              const float normError, const float baroAltitude, const float dt) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    const FusionAltitudeInsSettings *const s = &ins->settings;
    const float gyroSquared = gyro.x * gyro.x + gyro.y * gyro.y + gyro.z * gyro.z;
    const bool still = (gyroSquared < s->stationaryGyroThreshold * s->stationaryGyroThreshold) && (normError < s->stationaryAccelThreshold);
    if (!still) {
        FusionAltitudeInsRestartStationary(ins);
        return;
    }
    const float time = ins->stationaryTime + dt;
    ins->stationaryTime = (time < s->stationaryWindow) ? time : s->stationaryWindow;
    if (!FusionAltitudeIsNaN(baroAltitude)) {
        ins->stationaryBaroSum = ins->stationaryBaroSum + baroAltitude;
        ins->stationaryBaroCount = ins->stationaryBaroCount + 1.0f;
    }
    ins->stationaryHalfTime = ins->stationaryHalfTime + dt;
    const float half = 0.5f * s->stationaryWindow;
    if (ins->stationaryHalfTime >= half) {
        const bool hasMean = ins->stationaryBaroCount > 0.0f;
        const float mean = hasMean ? (ins->stationaryBaroSum / ins->stationaryBaroCount) : 0.0f;
        if (ins->stationaryHalfDone) {
            const float change = mean - ins->stationaryBaroPrevious;
            const float magnitude = (change < 0.0f) ? -change : change;
            ins->stationaryBaroStill = !(hasMean && ins->stationaryHasPrevious && (magnitude > s->stationaryBaroRate * half));
        } else {
            ins->stationaryBaroStill = !hasMean; /* readings in the first half: wait for the comparison */
        }
        ins->stationaryHalfDone = true;
        ins->stationaryHasPrevious = hasMean;
        ins->stationaryBaroPrevious = mean;
        ins->stationaryHalfTime = 0.0f;
        ins->stationaryBaroSum = 0.0f;
        ins->stationaryBaroCount = 0.0f;
    }
}

/** @internal
 * Time step of the nominal state: alignment on the first usable gravity
 * direction (normError = ||accel| - g| <= accelNormRejection, m/s^2), a gap,
 * or the prediction over dt (s) with the bias-corrected rate w = gyro - b_g
 * (rad/s) and specific force f = accel - (0, 0, b_az) (m/s^2) followed by
 * stationary detection (with the baro altitude, m, NaN: none). @return false while not aligned (the step ends).
 */
static inline FUSION_ALTITUDE_INS_ONCE bool FusionAltitudeInsPropagate(FusionAltitudeIns *const ins, const FusionAltitudeInsVector gyro,
                                                                       const FusionAltitudeInsVector accel, const float normError,
                                                                       const float baroAltitude, const float dt) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    const FusionAltitudeInsSettings *const s = &ins->settings;
    if (!ins->aligned) {
        if (!(normError <= s->accelNormRejection) || !FusionAltitudeInsAlign(ins, accel)) {
            return false; /* wait for a usable gravity direction */
        }
    } else if (dt > s->gapPeriod) {
        FusionAltitudeInsGap(ins);
    } else {
        const float w[3] = {gyro.x - ins->gyroBias[0], gyro.y - ins->gyroBias[1], gyro.z - ins->gyroBias[2]};
        const float f[3] = {accel.x, accel.y, accel.z - ins->accelZBias};
        const float d0 = ins->distance;
        const float v0 = ins->velocity;
        FusionAltitudeInsPredict(ins, w, f, dt);
        if (FusionAltitudeInsIsBaroSilentFor(ins, s->deadReckoningHorizon)) {
            FusionAltitudeInsHoldHeight(ins, d0, v0, dt); /* beyond the horizon: dead reckoning stops */
        }
        FusionAltitudeInsDetectStationary(ins, gyro, normError, baroAltitude, dt);
    }
    return true;
}

/** @internal
 * Accel update of the gravity direction: u = f / |f| with f = accel - (0, 0,
 * b_az) (m/s^2) against the predicted up direction r (body, unit); residual
 * e = u - r (chord, unitless), measurement rows those of [r]x but the one of
 * the largest |r_k|, noise R = accelAttitudeNoise^2. Rejected when the norm
 * error ||accel| - g| > accelNormRejection (m/s^2) or |e| > accelRejection
 * (unless recovering: rejectionTime > recoveryTriggerPeriod, s);
 * rejectionTime (s) grows by dt (s) while rejected.
 */
static inline FUSION_ALTITUDE_INS_ONCE void FusionAltitudeInsFuseGravity(FusionAltitudeIns *const ins, float dx[FUSION_ALTITUDE_INS_STATES],
                                                                         const FusionAltitudeInsVector accel, const float r[3], const float normError,
                                                                         const float dt) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    const FusionAltitudeInsSettings *const s = &ins->settings;
    const float fz = accel.z - ins->accelZBias;
    const float fNorm = sqrtf(accel.x * accel.x + accel.y * accel.y + fz * fz);
    bool rejected = !(normError <= s->accelNormRejection) || !(fNorm > 0.0f); /* |f| = 0: no direction */
    if (!rejected) {
        const float u[3] = {accel.x / fNorm, accel.y / fNorm, fz / fNorm};
        const float e[3] = {u[0] - r[0], u[1] - r[1], u[2] - r[2]};
        const float chord2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
        const bool recovering = ins->rejectionTime > s->recoveryTriggerPeriod;
        if ((chord2 > s->accelRejection * s->accelRejection) && !recovering) {
            rejected = true;
        } else {
            /* rows of [r]x: 0: (0, -r2, r1), 1: (r2, 0, -r0), 2: (-r1, r0, 0); skip the row of the largest |r_k| */
            const float a0 = (r[0] < 0.0f) ? -r[0] : r[0];
            const float a1 = (r[1] < 0.0f) ? -r[1] : r[1];
            const float a2 = (r[2] < 0.0f) ? -r[2] : r[2];
            const int skip = (a2 >= a0 && a2 >= a1) ? 2 : ((a1 >= a0) ? 1 : 0);
            const float R = s->accelAttitudeNoise * s->accelAttitudeNoise;
            if (skip != 0) {
                FusionAltitudeInsFuse(ins, dx, 1, -r[2], 2, r[1], e[0], R);
            }
            if (skip != 1) {
                FusionAltitudeInsFuse(ins, dx, 0, r[2], 2, -r[0], e[1], R);
            }
            if (skip != 2) {
                FusionAltitudeInsFuse(ins, dx, 0, -r[1], 1, r[0], e[2], R);
            }
        }
    }
    ins->rejectionTime = rejected ? (ins->rejectionTime + dt) : 0.0f;
    ins->accelRejected = rejected;
}

/** @internal
 * Stationary updates: zero rate (residual gyro - b_g, rad/s; noise
 * zeroRateNoise^2), zero velocity (residual -v, m/s; noise
 * zeroVelocityNoise^2), and the accel z bias low-passed towards
 * accel.z - g r_z (m/s^2) with k = dt / (accelBiasTimeConstant + dt) (dt, s).
 */
static inline FUSION_ALTITUDE_INS_ONCE void FusionAltitudeInsFuseStationary(FusionAltitudeIns *const ins, float dx[FUSION_ALTITUDE_INS_STATES],
                                                                            const FusionAltitudeInsVector gyro, const FusionAltitudeInsVector accel,
                                                                            const float r[3], const float dt) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    const FusionAltitudeInsSettings *const s = &ins->settings;
    const float R = s->zeroRateNoise * s->zeroRateNoise;
    FusionAltitudeInsFuse(ins, dx, 3, 1.0f, -1, 0.0f, gyro.x - ins->gyroBias[0], R);
    FusionAltitudeInsFuse(ins, dx, 4, 1.0f, -1, 0.0f, gyro.y - ins->gyroBias[1], R);
    FusionAltitudeInsFuse(ins, dx, 5, 1.0f, -1, 0.0f, gyro.z - ins->gyroBias[2], R);
    FusionAltitudeInsFuse(ins, dx, 7, 1.0f, -1, 0.0f, -ins->velocity, s->zeroVelocityNoise * s->zeroVelocityNoise);
    const float k = dt / (s->accelBiasTimeConstant + dt);
    ins->accelZBias = ins->accelZBias + k * ((accel.z - FUSION_ALTITUDE_GRAVITY * r[2]) - ins->accelZBias);
}

/** @internal
 * Baro update (baroAltitude, m; NaN: none): the first reading sets the baro
 * bias b = baroAltitude - d (m); while stationary the bias is low-passed
 * towards baroAltitude - d with k = t / (baroBiasTimeConstant + t) (t: time
 * since the previous reading, s); otherwise d is fused with residual
 * y = (baroAltitude - b) - (d + dd) (m), noise R = baroNoise^2 (m^2), through
 * the innovation gate: rejected while y^2 > baroGate^2 (P_dd + R); once the
 * rejection streak is older than baroRejectionTimeout (s), d is decorrelated
 * (variance FUSION_ALTITUDE_INS_VARIANCE_LIMIT, m^2), the velocity variance
 * raised to at least initialVelocitySigma^2 ((m/s)^2), and the reading fused.
 */
static inline FUSION_ALTITUDE_INS_ONCE void FusionAltitudeInsFuseBaro(FusionAltitudeIns *const ins, float dx[FUSION_ALTITUDE_INS_STATES],
                                                                      const float baroAltitude) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    const FusionAltitudeInsSettings *const s = &ins->settings;
    if (FusionAltitudeIsNaN(baroAltitude)) {
        return;
    }
    if (!ins->baroInitialised) {
        ins->baroBias = baroAltitude - ins->distance;
        ins->baroInitialised = true;
    } else if (ins->stationary) { /* every reading is bias: d is held by the zero-velocity update */
        const float k = ins->baroElapsed / (s->baroBiasTimeConstant + ins->baroElapsed);
        ins->baroBias = ins->baroBias + k * ((baroAltitude - ins->distance) - ins->baroBias);
    } else {
        const float R = s->baroNoise * s->baroNoise;
        const float y = (baroAltitude - ins->baroBias) - ins->distance;
        const float innovation = y - dx[6];
        const float S = ins->P[6][6] + R;
        if (innovation * innovation > (s->baroGate * s->baroGate) * S) {
            ins->baroRejections++;
            if (!ins->baroRejecting) {
                ins->baroRejecting = true;
                ins->baroRejectingFor = 0.0f;
            }
            if (!(ins->baroRejectingFor > s->baroRejectionTimeout)) {
                ins->baroElapsed = 0.0f;
                return; /* rejected: the INS coasts on the IMU */
            }
            /* the streak outlasted the timeout: the INS height is what is wrong; the reading sets it */
            ins->baroResets++;
            FusionAltitudeInsForgetHeight(ins);
        }
        ins->baroRejecting = false;
        ins->baroRejectingFor = 0.0f;
        FusionAltitudeInsFuse(ins, dx, 6, 1.0f, -1, 0.0f, y, R);
    }
    ins->baroElapsed = 0.0f;
}

/** @internal
 * Injects the error state dx into the nominal state: q = q (x) [1, dtheta/2]
 * (dtheta = dx[0..2], rad), gyro bias += dx[3..5] (rad/s), d += dx[6] (m),
 * v += dx[7] (m/s).
 */
static inline FUSION_ALTITUDE_INS_ONCE void FusionAltitudeInsInject(FusionAltitudeIns *const ins, const float dx[FUSION_ALTITUDE_INS_STATES]) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    FusionAltitudeInsRotate(ins->q, 0.5f * dx[0], 0.5f * dx[1], 0.5f * dx[2]);
    ins->gyroBias[0] = ins->gyroBias[0] + dx[3];
    ins->gyroBias[1] = ins->gyroBias[1] + dx[4];
    ins->gyroBias[2] = ins->gyroBias[2] + dx[5];
    ins->distance = ins->distance + dx[6];
    ins->velocity = ins->velocity + dx[7];
}

/** @internal
 * Magnetometer (any unit, body; FusionAltitudeInsNoMag(): none): the local ->
 * global yaw offset only. m is rotated to the local frame, its horizontal
 * direction (mx, -my) / |(mx, my)| (unit) is the target (cos, sin) of the
 * offset, low-passed with k = t / (magTimeConstant + t) (t: time since the
 * previous reading, s) and renormalised.
 */
static inline FUSION_ALTITUDE_INS_ONCE void FusionAltitudeInsFuseMag(FusionAltitudeIns *const ins, const FusionAltitudeInsVector mag) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    const FusionAltitudeInsSettings *const s = &ins->settings;
    if (FusionAltitudeInsIsNoMag(mag)) {
        return;
    }
    const float w = ins->q[0], x = ins->q[1], y = ins->q[2], z = ins->q[3];
    /* first two rows of R(q) times m */
    const float mx = (1.0f - 2.0f * (y * y + z * z)) * mag.x + 2.0f * (x * y - w * z) * mag.y + 2.0f * (x * z + w * y) * mag.z;
    const float my = 2.0f * (x * y + w * z) * mag.x + (1.0f - 2.0f * (x * x + z * z)) * mag.y + 2.0f * (y * z - w * x) * mag.z;
    const float horizontal = sqrtf(mx * mx + my * my);
    if (!(horizontal > 0.0f)) {
        return;
    }
    const float targetCos = mx / horizontal;
    const float targetSin = -my / horizontal;
    if (!ins->magInitialised) {
        ins->yawCos = targetCos;
        ins->yawSin = targetSin;
        ins->magInitialised = true;
    } else {
        const float k = ins->magElapsed / (s->magTimeConstant + ins->magElapsed);
        const float c = ins->yawCos + k * (targetCos - ins->yawCos);
        const float sn = ins->yawSin + k * (targetSin - ins->yawSin);
        const float norm = sqrtf(c * c + sn * sn);
        if (norm > 1e-3f) {
            ins->yawCos = c / norm;
            ins->yawSin = sn / norm;
        } else {
            ins->yawCos = targetCos;
            ins->yawSin = targetSin;
        }
    }
    ins->magElapsed = 0.0f;
}

/**
 * @brief One IMU step: gyro (rad/s) and accel (m/s^2) in the body frame, mag
 * (any unit, body; FusionAltitudeInsNoMag() for none), baro altitude (m;
 * FUSION_ALTITUDE_NO_BARO for none), dt (s) since the previous step. Bad
 * input: returns its status and leaves the INS bit-identical.
 */
static inline FusionAltitudeInsStatus FusionAltitudeInsUpdate(FusionAltitudeIns *const ins, const FusionAltitudeInsVector gyro,
                                                              const FusionAltitudeInsVector accel, const FusionAltitudeInsVector mag,
                                                              const float baroAltitude, const float dt) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    const FusionAltitudeInsStatus status = FusionAltitudeInsCheckInputs(gyro, accel, mag, baroAltitude, dt);
    if (status != FusionAltitudeInsStatusOk) {
        return status;
    }
    const FusionAltitudeInsSettings *const s = &ins->settings;
    const float g = FUSION_ALTITUDE_GRAVITY;
    const float accelNorm = sqrtf(accel.x * accel.x + accel.y * accel.y + accel.z * accel.z);
    const float normError = (accelNorm > g) ? (accelNorm - g) : (g - accelNorm);
    if (!FusionAltitudeInsPropagate(ins, gyro, accel, normError, baroAltitude, dt)) {
        return FusionAltitudeInsStatusOk;
    }
    ins->stationary = (ins->stationaryTime >= s->stationaryWindow) && ins->stationaryBaroStill;
    const bool baroWasTimedOut = FusionAltitudeInsIsBaroSilentFor(ins, s->baroTimeout);
    ins->baroElapsed = ins->baroElapsed + dt;
    if (!baroWasTimedOut && FusionAltitudeInsIsBaroSilentFor(ins, s->baroTimeout)) {
        ins->baroTimeouts++; /* this silence is counted once */
    }
    ins->magElapsed = ins->magElapsed + dt;
    if (ins->baroRejecting) {
        ins->baroRejectingFor = ins->baroRejectingFor + dt;
    }

    float dx[FUSION_ALTITUDE_INS_STATES] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
    float r[3];
    FusionAltitudeInsUpInBody(ins->q, r);
    FusionAltitudeInsFuseGravity(ins, dx, accel, r, normError, dt);
    FusionAltitudeInsLimitYaw(ins, dx, r);
    if (ins->stationary) {
        FusionAltitudeInsFuseStationary(ins, dx, gyro, accel, r, dt);
    }
    FusionAltitudeInsFuseBaro(ins, dx, baroAltitude);
    /* once per step, after the prediction and every correction */
    FusionAltitudeInsConditionCovariance(ins->P);
    FusionAltitudeInsInject(ins, dx);
    FusionAltitudeInsFuseMag(ins, mag);
    return FusionAltitudeInsStatusOk;
}

//------------------------------------------------------------------------------
// Getters

/** @return true while the INS is not baro-aided: the baro has had a reading, then none for longer than baroTimeout (s). */
static inline bool FusionAltitudeInsIsBaroTimedOut(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsIsBaroSilentFor(ins, ins->settings.baroTimeout);
}

/** @return true while dead reckoning is stopped: no baro reading for longer than deadReckoningHorizon (s); see the file comment. */
static inline bool FusionAltitudeInsIsHeightHeld(const FusionAltitudeIns *const ins) {
    return FusionAltitudeInsIsBaroSilentFor(ins, ins->settings.deadReckoningHorizon);
}

/** @return the number of baro silences longer than baroTimeout so far (each counted once). */
static inline uint32_t FusionAltitudeInsGetBaroTimeouts(const FusionAltitudeIns *const ins) {
    return ins->baroTimeouts;
}

/** @return the settings. */
static inline FusionAltitudeInsSettings FusionAltitudeInsGetSettings(const FusionAltitudeIns *const ins) {
    return ins->settings;
}

/** @return the height above the reference d, m, +up (the baro reads d + baro bias). */
static inline float FusionAltitudeInsGetAltitude(const FusionAltitudeIns *const ins) {
    return ins->distance;
}

/** @return the vertical velocity, m/s, +up. */
static inline float FusionAltitudeInsGetVerticalVelocity(const FusionAltitudeIns *const ins) {
    return ins->velocity;
}

/** @return the local attitude (body -> local earth, NWU, yaw integrated from 0). */
static inline FusionAltitudeInsQuaternion FusionAltitudeInsGetQuaternion(const FusionAltitudeIns *const ins) {
    FusionAltitudeInsQuaternion q;
    q.w = ins->q[0];
    q.x = ins->q[1];
    q.y = ins->q[2];
    q.z = ins->q[3];
    return q;
}

/**
 * @return the local-to-global rotation (about earth z by the magnetometer's
 * yaw offset; identity until the first usable mag sample).
 */
static inline FusionAltitudeInsQuaternion FusionAltitudeInsGetLocalToGlobal(const FusionAltitudeIns *const ins) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    /* half angle without trig: normalise(1 + cos, sin) */
    FusionAltitudeInsQuaternion q;
    const float a = 1.0f + ins->yawCos;
    const float b = ins->yawSin;
    const float norm = sqrtf(a * a + b * b);
    q.x = 0.0f;
    q.y = 0.0f;
    if (norm > 1e-6f) {
        q.w = a / norm;
        q.z = b / norm;
    } else {
        q.w = 0.0f;
        q.z = 1.0f;
    }
    return q;
}

/** @return the global attitude q_g = localToGlobal (x) q (body -> NWU with north from the magnetometer). */
static inline FusionAltitudeInsQuaternion FusionAltitudeInsGetGlobalQuaternion(const FusionAltitudeIns *const ins) {
    FUSION_ALTITUDE_INS_NO_CONTRACT
    const FusionAltitudeInsQuaternion a = FusionAltitudeInsGetLocalToGlobal(ins);
    const float w = ins->q[0], x = ins->q[1], y = ins->q[2], z = ins->q[3];
    FusionAltitudeInsQuaternion q;
    q.w = a.w * w - a.z * z;
    q.x = a.w * x - a.z * y;
    q.y = a.w * y + a.z * x;
    q.z = a.w * z + a.z * w;
    return q;
}

/** @return the gyroscope bias, rad/s, body frame. */
static inline FusionAltitudeInsVector FusionAltitudeInsGetGyroBias(const FusionAltitudeIns *const ins) {
    FusionAltitudeInsVector b;
    b.x = ins->gyroBias[0];
    b.y = ins->gyroBias[1];
    b.z = ins->gyroBias[2];
    return b;
}

/** @return the accelerometer z bias, m/s^2, body z (learned while stationary). */
static inline float FusionAltitudeInsGetAccelZBias(const FusionAltitudeIns *const ins) {
    return ins->accelZBias;
}

/** @return the baro bias, m: the baro altitude at d = 0 (set by the first baro sample, learned while stationary). */
static inline float FusionAltitudeInsGetBaroBias(const FusionAltitudeIns *const ins) {
    return ins->baroBias;
}

/** @return true while stationary (see the file comment). */
static inline bool FusionAltitudeInsIsStationary(const FusionAltitudeIns *const ins) {
    return ins->stationary;
}

/** @return true if the latest step did not use the accelerometer for attitude. */
static inline bool FusionAltitudeInsIsAccelRejected(const FusionAltitudeIns *const ins) {
    return ins->accelRejected;
}

/** @return the number of baro readings rejected by the innovation gate. */
static inline uint32_t FusionAltitudeInsGetBaroRejections(const FusionAltitudeIns *const ins) {
    return ins->baroRejections;
}

/** @return the number of height resets from the baro after a rejection streak longer than baroRejectionTimeout. */
static inline uint32_t FusionAltitudeInsGetBaroResets(const FusionAltitudeIns *const ins) {
    return ins->baroResets;
}

/** @return true while a baro rejection streak is in progress (the latest readings failed the gate). */
static inline bool FusionAltitudeInsIsBaroRejecting(const FusionAltitudeIns *const ins) {
    return ins->baroRejecting;
}

/** @return the number of steps with dt > gapPeriod (not integrated). */
static inline uint32_t FusionAltitudeInsGetGapCount(const FusionAltitudeIns *const ins) {
    return ins->gapCount;
}

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC pop_options
#endif

#undef FUSION_ALTITUDE_INS_UNROLL

#ifdef __cplusplus
}
#endif

#endif
