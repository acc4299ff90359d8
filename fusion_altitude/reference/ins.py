"""The inertial navigation filter, in plain Python.

Read it next to ``csrc/fusion_altitude_ins.h``: every method below mirrors
the C function named in its docstring, statement for statement, in float32
arithmetic (numpy scalars, and numpy float32 arrays only for element-wise
operations, which round each element exactly as the C loop does) in the same
operation order, so its results equal the C core's bit for bit.

Frames: body axes right-handed; earth NWU (z up). Inputs gyro rad/s, accel
m/s² (specific force: +9.81 on z when level at rest), mag any unit, baro m.

Nominal state: local attitude q (body → local earth; yaw integrated from 0,
never touched by the magnetometer), gyro bias b (rad/s), vertical distance d
(m, +up), vertical velocity v (m/s, +up). Error state of the EKF (8):
attitude error δθ (body frame, q_true = q ⊗ (1, δθ/2)), bias error δb, δd, δv.

Prediction, w = gyro − b, f = accel − (0, 0, b_z), r = Rᵀe_z (up in body):
    a = r·f − g;  d += v·dt + a·dt²/2;  v += a·dt;  q ← normalise(q ⊗ (1, w·dt/2))
    F: δθ ← (I − [w·dt]×)δθ − dt·δb;  δv += dt·c·δθ;  δd += dt·δv + dt²/2·c·δθ;  c = f × r
    P ← F P Fᵀ + Q
Corrections (sequential scalar, accumulated in dx, injected at the end):
    accel  u = f/|f| ≈ r + [r]×δθ (two rows; rejected when ||f| − g| or |u − r| is too large)
    yaw    pseudo-measurement r·δθ = 0 while the local yaw variance exceeds its limit
    still  zero rate (gyro = b) and zero velocity (v = 0)
    baro   baro − baro_bias = d (not while stationary: then the reading is bias)
"""

from __future__ import annotations

from typing import Optional

import numpy as np

from .._core import _c_tables, _ins_glue
from .._core._ins_glue import InsBatch
from ._checkpoint import Checkpointable
from ._diagnostics import settings_property, state_property
from ._settings import KeywordSettings

f32 = np.float32
# The header's constants (fusion_altitude.h, fusion_altitude_ins.h), through the generated tables.
N_STATES = _c_tables.FUSION_ALTITUDE_INS_STATES
GRAVITY = f32(_c_tables.FUSION_ALTITUDE_GRAVITY)
VARIANCE_LIMIT = f32(_c_tables.FUSION_ALTITUDE_INS_VARIANCE_LIMIT)
ATTITUDE_VARIANCE_LIMIT = f32(_c_tables.FUSION_ALTITUDE_INS_ATTITUDE_VARIANCE_LIMIT)
YAW_VARIANCE_LIMIT = f32(_c_tables.FUSION_ALTITUDE_INS_YAW_VARIANCE_LIMIT)
NEWTON_NORM = f32(_c_tables.FUSION_ALTITUDE_INS_NEWTON_NORM)
_ZERO = f32(0)
_ONE = f32(1)
_HALF = f32(0.5)
_TWO = f32(2)
#: upper triangle (j >= i): the C computes these entries and mirrors them (np.where keeps -0.0, unlike adding)
_UPPER = np.triu(np.ones((N_STATES, N_STATES), dtype=bool))


class InsSettings(KeywordSettings):
    """Settings of the INS, float32, in physical units (keyword arguments only).

    The defaults are for a MEMS IMU at 100–500 Hz on a multirotor.

    Parameters
    ----------
    gyro_noise : 3e-4 rad/s/√Hz
        Gyro white-noise density.
    gyro_bias_random_walk : 1e-5 rad/s²/√Hz
        Gyro bias random walk.
    accel_noise : 0.05 m/s²/√Hz
        Vertical acceleration noise density (vibration included).
    accel_attitude_noise : 0.05 rad
        1σ of the gravity direction per sample (> 0).
    accel_norm_rejection : 2.0 m/s²
        Accel not used for attitude while ||f| − g| exceeds it.
    accel_rejection : 0.17 rad
        Accel not used while its direction is further than this from the prediction.
    recovery_trigger_period : 5.0 s
        Rejected for longer lifts the direction gate (the Fusion AHRS recovery).
    baro_noise : 0.3 m
        Baro 1σ per sample (> 0).
    stationary_gyro_threshold : 0.05 rad/s
    stationary_accel_threshold : 0.5 m/s²
    stationary_window : 1.0 s
        Stationary once |gyro| and ||accel| − g| stayed below the thresholds on every sample for the window
        (and the baro holds still, ``stationary_baro_rate``).
    zero_rate_noise : 0.01 rad/s
    zero_velocity_noise : 0.05 m/s
        1σ of the zero-rate and zero-velocity updates while stationary (> 0).
    baro_bias_time_constant, accel_bias_time_constant : 5.0 s, 2.0 s
        Complementary filters of the baro bias and accel z bias while stationary (> 0).
    mag_time_constant : 2.0 s
        Local-to-global yaw filter (> 0).
    initial_attitude_sigma : 0.05 rad
    initial_gyro_bias_sigma : 0.01 rad/s
    initial_velocity_sigma : 0.5 m/s
    gap_period : 0.1 s
        A dt above it is a gap: not integrated, counted (> 0).
    baro_gate : 5.0 σ
        A baro reading with innovation y² > baro_gate² S is rejected (> 0).
    baro_rejection_timeout : 1.0 s
        Baro rejected for longer: its bias is reset from the next reading.
    baro_timeout : 1.5 s
        No baro reading for longer: not baro-aided (``baro_timed_out``, counted in ``baro_timeouts``) (> 0).
    dead_reckoning_horizon : 5.0 s
        No baro reading for longer: dead reckoning stops (``height_held``): the velocity decays to 0 with this
        time constant and the height variance grows (> 0).
    stationary_baro_rate : 0.5 m/s
        While the IMU is still, the means of the baro readings over consecutive half windows differing by more
        than this rate × stationary_window / 2 (m) veto stationary: a climb at constant velocity is still to the
        IMU. No baro readings: no veto.

    Raises
    ------
    ValueError
        A setting out of range, naming it. TypeError for an unknown name.
    """

    __slots__ = ()
    _DISTINCT = "gyro_bias_random_walk"

    def __init__(self, **kwargs) -> None:
        self._values = {name: float(value) for name, value in _ins_glue.convert_ins_settings(kwargs).items()}

    def f32(self, name: str) -> np.float32:
        """A setting as the float32 the C sees."""
        return f32(self._values[name])


def _decorrelate(P: np.ndarray, k: int, variance: np.float32) -> None:
    """FusionAltitudeInsDecorrelate: row and column k of P zeroed, P[k, k] = variance, in place."""
    P[k, :] = 0
    P[:, k] = 0
    P[k, k] = variance


def _hold_variance(P: np.ndarray, k: int, limit: np.float32) -> None:
    """FusionAltitudeInsHoldVariance: a variance P[k, k] above limit is decorrelated and held at limit, in place."""
    if P[k, k] > limit:
        _decorrelate(P, k, limit)


def _normalise(q: np.ndarray) -> np.ndarray:
    """FusionAltitudeInsNormalise."""
    norm2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]
    excess = norm2 - _ONE
    if -NEWTON_NORM < excess < NEWTON_NORM:  # 1/|q| = 1 - e/2 + O(e²): error < 4e-9 (no square root)
        inverse = _ONE - f32(0.5) * excess
    else:
        inverse = _ONE / np.sqrt(norm2)
    return np.array([q[0] * inverse, q[1] * inverse, q[2] * inverse, q[3] * inverse], dtype=f32)


def _rotate(q: np.ndarray, hx, hy, hz) -> np.ndarray:
    """FusionAltitudeInsRotate: normalise(q ⊗ (1, h))."""
    w, x, y, z = q[0], q[1], q[2], q[3]
    return _normalise(np.array([w - x * hx - y * hy - z * hz,
                                x + w * hx + y * hz - z * hy,
                                y + w * hy - x * hz + z * hx,
                                z + w * hz + x * hy - y * hx], dtype=f32))


def _up_in_body(q: np.ndarray):
    """FusionAltitudeInsUpInBody: r = Rᵀe_z, the third row of R(q)."""
    w, x, y, z = q[0], q[1], q[2], q[3]
    return (_TWO * (x * z - w * y), _TWO * (y * z + w * x), _ONE - _TWO * (x * x + y * y))


class InsEstimator(Checkpointable):
    """Inertial navigation filter: attitude, gyro bias, height and vertical velocity from a raw IMU and a baro.

    An error-state EKF (csrc/fusion_altitude_ins.h). Body axes: any
    right-handed set, the same for gyro, accel and mag. Earth frame: NWU
    (x north, y west, z up), so a level IMU at rest reads accel (0, 0, +g).
    The local attitude (``quaternion``; yaw integrated from 0) drives the
    vertical channel and never sees the magnetometer; the magnetometer only
    sets the local-to-global yaw (``global_quaternion``).

    Parameters
    ----------
    settings : InsSettings, optional
        Defaults when omitted.
    gyro_units : {"rad/s", "deg/s"}
        Unit of the ``gyro`` input ("°/s" and "dps" also accepted), as imufusion users have it in °/s.
    accel_units : {"m/s^2", "g"}
        Unit of the ``accel`` input ("m/s²" also accepted).

    Notes
    -----
    ``height_above_start`` is the height d above the reference, m, +up; the
    baro reads ``height_above_start + baro_bias``, which is ``altitude`` (the
    baro's datum, as for every estimator). The first baro sample sets ``baro_bias``; while
    stationary every baro reading goes to ``baro_bias`` (the height is held by
    a zero-velocity update) and the accel z bias is learned.
    """

    def __init__(self, settings: Optional[InsSettings] = None, *, gyro_units: str = "rad/s",
                 accel_units: str = "m/s^2"):
        self._gyro_scale, self._accel_scale = _ins_glue.units_tuple(gyro_units, accel_units)
        self._units = (gyro_units, accel_units)
        self._initialise(settings if settings is not None else InsSettings())

    # -- FusionAltitudeInsInitialiseWith -------------------------------------------------------
    def _initialise(self, settings: InsSettings) -> None:
        self._s = InsSettings.coerce(settings)
        self.q = np.array([1, 0, 0, 0], dtype=f32)
        self.gyro_bias_ = np.zeros(3, dtype=f32)
        self.distance = _ZERO
        self.velocity = _ZERO
        self.P = np.zeros((N_STATES, N_STATES), dtype=f32)
        self.accel_z_bias_ = _ZERO
        self.baro_bias_ = _ZERO
        self.yaw_cos = _ONE
        self.yaw_sin = _ZERO
        self.stationary_time = self.rejection_time = self.baro_elapsed = self.mag_elapsed = _ZERO
        self.baro_rejecting_for = _ZERO
        self.gap_count_ = self.baro_rejections_ = self.baro_resets_ = self.baro_timeouts_ = 0
        self.baro_rejecting = self.aligned = self.baro_initialised = self.mag_initialised = False
        self.stationary = self.accel_rejected = False
        self._restart_stationary()
        self._reset_covariance()

    def _restart_stationary(self) -> None:
        """FusionAltitudeInsRestartStationary: the still timer (s) and the baro half-window test."""
        self.stationary_time = self.stationary_half_time = _ZERO  # s
        self.stationary_baro_sum = self.stationary_baro_count = self.stationary_baro_previous = _ZERO  # m, 1, m
        self.stationary_half_done = self.stationary_has_previous = False
        self.stationary_baro_still = True  # no baro reading yet: no veto

    def _detect_stationary(self, gyro: np.ndarray, norm_error: np.float32, baro: np.float32, dt: np.float32) -> None:
        """FusionAltitudeInsDetectStationary: IMU still for the window, and the baro's half-window means
        (m) not differing by more than stationary_baro_rate (m/s) × stationary_window / 2 (s)."""
        s = self._s
        gyro_squared = gyro[0] * gyro[0] + gyro[1] * gyro[1] + gyro[2] * gyro[2]
        threshold = s.f32("stationary_gyro_threshold")
        still = gyro_squared < threshold * threshold and norm_error < s.f32("stationary_accel_threshold")
        if not still:
            self._restart_stationary()
            return
        time = self.stationary_time + dt
        window = s.f32("stationary_window")
        self.stationary_time = time if time < window else window
        if not np.isnan(baro):
            self.stationary_baro_sum = self.stationary_baro_sum + baro
            self.stationary_baro_count = self.stationary_baro_count + _ONE
        self.stationary_half_time = self.stationary_half_time + dt
        half = _HALF * window
        if self.stationary_half_time >= half:
            has_mean = bool(self.stationary_baro_count > _ZERO)
            mean = self.stationary_baro_sum / self.stationary_baro_count if has_mean else _ZERO
            if self.stationary_half_done:
                change = mean - self.stationary_baro_previous
                magnitude = -change if change < _ZERO else change
                self.stationary_baro_still = not (has_mean and self.stationary_has_previous
                                                  and magnitude > s.f32("stationary_baro_rate") * half)
            else:
                self.stationary_baro_still = not has_mean  # readings in the first half: wait for the comparison
            self.stationary_half_done = True
            self.stationary_has_previous = has_mean
            self.stationary_baro_previous = f32(mean)
            self.stationary_half_time = _ZERO
            self.stationary_baro_sum = _ZERO
            self.stationary_baro_count = _ZERO

    def _reset_covariance(self) -> None:
        """FusionAltitudeInsResetCovariance."""
        s = self._s
        attitude = s.f32("initial_attitude_sigma") * s.f32("initial_attitude_sigma")
        bias = s.f32("initial_gyro_bias_sigma") * s.f32("initial_gyro_bias_sigma")
        self.P[:] = 0
        for i in range(3):
            self.P[i, i] = attitude
            self.P[3 + i, 3 + i] = bias
        self.P[7, 7] = s.f32("initial_velocity_sigma") * s.f32("initial_velocity_sigma")

    settings = settings_property(InsSettings, None, attribute="_s")  # FusionAltitudeInsSetSettings: state kept

    def reset(self) -> None:
        """Back to the start state (not aligned, FusionAltitudeInsInitialiseWith), keeping the settings and units."""
        self._initialise(self._s)

    # -- FusionAltitudeInsAlign ----------------------------------------------------------------
    def _align(self, f: np.ndarray) -> bool:
        """False (nothing changed) when |f| is 0 in float32: no direction."""
        norm = np.sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2])
        if not norm > 0:
            return False
        ux, uy, uz = f[0] / norm, f[1] / norm, f[2] / norm
        if uz > f32(-0.999999):
            self.q = _normalise(np.array([_ONE + uz, uy, -ux, _ZERO], dtype=f32))
        else:
            self.q = np.array([0, 1, 0, 0], dtype=f32)
        self.aligned = True
        return True

    # -- FusionAltitudeInsPredict --------------------------------------------------------------
    def _predict(self, w: np.ndarray, f: np.ndarray, dt: np.float32) -> None:
        s, P = self._s, self.P
        half_dt = _HALF * dt
        half_dt2 = half_dt * dt
        r = _up_in_body(self.q)
        accel = (r[0] * f[0] + r[1] * f[1] + r[2] * f[2]) - GRAVITY
        self.distance = self.distance + self.velocity * dt + accel * half_dt2
        self.velocity = self.velocity + accel * dt
        self.q = _rotate(self.q, w[0] * half_dt, w[1] * half_dt, w[2] * half_dt)
        ax, ay, az = w[0] * dt, w[1] * dt, w[2] * dt
        cx = f[1] * r[2] - f[2] * r[1]
        cy = f[2] * r[0] - f[0] * r[2]
        cz = f[0] * r[1] - f[1] * r[0]
        vx, vy, vz = dt * cx, dt * cy, dt * cz
        hx, hy, hz = half_dt2 * cx, half_dt2 * cy, half_dt2 * cz
        # G = F P (rows), element-wise over the columns
        G = np.empty_like(P)
        G[0] = P[0] + az * P[1] - ay * P[2] - dt * P[3]
        G[1] = P[1] - az * P[0] + ax * P[2] - dt * P[4]
        G[2] = P[2] + ay * P[0] - ax * P[1] - dt * P[5]
        G[3:6] = P[3:6]
        G[6] = P[6] + dt * P[7] + hx * P[0] + hy * P[1] + hz * P[2]
        G[7] = P[7] + vx * P[0] + vy * P[1] + vz * P[2]
        # G Fᵀ (columns), upper triangle mirrored
        M = np.empty_like(P)
        M[:, 0] = G[:, 0] + az * G[:, 1] - ay * G[:, 2] - dt * G[:, 3]
        M[:, 1] = G[:, 1] - az * G[:, 0] + ax * G[:, 2] - dt * G[:, 4]
        M[:, 2] = G[:, 2] + ay * G[:, 0] - ax * G[:, 1] - dt * G[:, 5]
        M[:, 3:6] = G[:, 3:6]
        M[:, 6] = G[:, 6] + dt * G[:, 7] + hx * G[:, 0] + hy * G[:, 1] + hz * G[:, 2]
        M[:, 7] = G[:, 7] + vx * G[:, 0] + vy * G[:, 1] + vz * G[:, 2]
        P = np.where(_UPPER, M, M.T)
        q_theta = s.f32("gyro_noise") * s.f32("gyro_noise") * dt
        q_bias = s.f32("gyro_bias_random_walk") * s.f32("gyro_bias_random_walk") * dt
        q_accel = s.f32("accel_noise") * s.f32("accel_noise") * dt
        for i in range(3):
            P[i, i] = P[i, i] + q_theta
            P[3 + i, 3 + i] = P[3 + i, 3 + i] + q_bias
        P[6, 6] = P[6, 6] + q_accel * (f32(0.25) * dt * dt)
        P[6, 7] = P[6, 7] + q_accel * half_dt
        P[7, 6] = P[6, 7]
        P[7, 7] = P[7, 7] + q_accel
        for k in (6, 7):
            _hold_variance(P, k, VARIANCE_LIMIT)
        self.P = P

    # -- FusionAltitudeInsConditionCovariance ------------------------------------------------
    @staticmethod
    def _condition_covariance(P: np.ndarray) -> np.ndarray:
        """Decorrelate an attitude variance (rad^2) above ATTITUDE_VARIANCE_LIMIT and hold
        it there, floor negative variances at 0 and clip |P_ij| to sqrt(P_ii P_jj), sign kept.

        The C loop reads each P_ii after the floor and only off-diagonal
        entries change afterwards, so the element-wise form gives the same
        bits: P_ij * P_ij > P_ii * P_jj never holds on the diagonal.
        """
        P = P.copy()
        for i in range(3):
            _hold_variance(P, i, ATTITUDE_VARIANCE_LIMIT)
        diagonal = np.diagonal(P).copy()
        diagonal = np.where(diagonal < _ZERO, _ZERO, diagonal).astype(np.float32)
        np.fill_diagonal(P, diagonal)
        bound2 = np.outer(diagonal, diagonal)
        clip = (P * P) > bound2
        if clip.any():
            bound = np.sqrt(bound2)
            P = np.where(clip, np.where(P < _ZERO, -bound, bound), P).astype(np.float32)
        return P

    # -- FusionAltitudeInsFuseGain / Fuse / LimitYaw -------------------------------------------
    def _fuse_gain(self, dx: np.ndarray, c: np.ndarray, S: np.float32, innovation: np.float32) -> None:
        # K = c/S as c times 1/S; P - c cᵀ/S entry by entry as (c_i c_j)(1/S): bit-symmetric
        inverse_S = _ONE / S
        dx += (c * inverse_S) * innovation
        self.P = self.P - np.outer(c, c) * inverse_S

    def _fuse(self, dx, i0, h0, i1, h1, y, R) -> None:
        P = self.P
        if i1 < 0:
            c = P[:, i0] * h0
            hc = h0 * c[i0]
            hdx = h0 * dx[i0]
        else:
            c = P[:, i0] * h0 + P[:, i1] * h1
            hc = h0 * c[i0] + h1 * c[i1]
            hdx = h0 * dx[i0] + h1 * dx[i1]
        self._fuse_gain(dx, c, hc + R, y - hdx)

    def _limit_yaw(self, dx, r) -> None:
        P = self.P
        c = P[:, 0] * r[0] + P[:, 1] * r[1] + P[:, 2] * r[2]
        hc = r[0] * c[0] + r[1] * c[1] + r[2] * c[2]
        if hc > YAW_VARIANCE_LIMIT:
            hdx = r[0] * dx[0] + r[1] * dx[1] + r[2] * dx[2]
            self._fuse_gain(dx, c, hc + YAW_VARIANCE_LIMIT, _ZERO - hdx)

    # -- FusionAltitudeInsUpdate ---------------------------------------------------------------
    def _step(self, gyro: np.ndarray, accel: np.ndarray, mag: np.ndarray, baro: np.float32, dt: np.float32) -> None:
        s = self._s
        g = GRAVITY
        accel_norm = np.sqrt(accel[0] * accel[0] + accel[1] * accel[1] + accel[2] * accel[2])
        norm_error = (accel_norm - g) if accel_norm > g else (g - accel_norm)
        if not self._propagate(gyro, accel, norm_error, baro, dt):
            return
        self.stationary = bool(self.stationary_time >= s.f32("stationary_window")) and self.stationary_baro_still
        baro_was_timed_out = self._baro_silent_for(s.f32("baro_timeout"))
        self.baro_elapsed = self.baro_elapsed + dt
        if not baro_was_timed_out and self._baro_silent_for(s.f32("baro_timeout")):
            self.baro_timeouts_ = (self.baro_timeouts_ + 1) & 0xFFFFFFFF  # this silence is counted once
        self.mag_elapsed = self.mag_elapsed + dt
        if self.baro_rejecting:
            self.baro_rejecting_for = self.baro_rejecting_for + dt

        dx = np.zeros(N_STATES, dtype=f32)
        r = _up_in_body(self.q)
        self._fuse_gravity(dx, accel, r, norm_error, dt)
        self._limit_yaw(dx, r)
        if self.stationary:
            self._fuse_stationary(dx, gyro, accel, r, dt)
        if not np.isnan(baro):
            self._fuse_baro(dx, baro)
            self.baro_elapsed = _ZERO
        # once per step, after the prediction and every correction
        self.P = self._condition_covariance(self.P)
        self._inject(dx)
        if not np.isnan(mag).all():
            self._fuse_mag(mag)

    def _propagate(self, gyro: np.ndarray, accel: np.ndarray, norm_error: np.float32, baro: np.float32,
                   dt: np.float32) -> bool:
        """FusionAltitudeInsPropagate: alignment, a gap, or the prediction over dt (s) and stationary detection;
        False while not aligned (the step ends)."""
        s = self._s
        if not self.aligned:
            if not (norm_error <= s.f32("accel_norm_rejection")) or not self._align(accel):
                return False  # wait for a usable gravity direction
        elif dt > s.f32("gap_period"):
            self._gap()
        else:
            w = gyro - self.gyro_bias_
            f = np.array([accel[0], accel[1], accel[2] - self.accel_z_bias_], dtype=f32)
            d0, v0 = self.distance, self.velocity
            self._predict(w, f, dt)
            if self._baro_silent_for(s.f32("dead_reckoning_horizon")):
                self._hold_height(d0, v0, dt)  # beyond the horizon: dead reckoning stops
            self._detect_stationary(gyro, norm_error, baro, dt)
        return True

    def _gap(self) -> None:
        """FusionAltitudeInsGap: counted; the attitude variance raised to at least initial_attitude_sigma² (rad²),
        the height forgotten, stationary detection restarted, a baro rejection streak ended."""
        s = self._s
        self.gap_count_ = (self.gap_count_ + 1) & 0xFFFFFFFF
        attitude = s.f32("initial_attitude_sigma") * s.f32("initial_attitude_sigma")
        for i in range(3):
            self.P[i, i] = self.P[i, i] if self.P[i, i] > attitude else attitude
        self._forget_height()  # the vehicle moved during the gap: the next baro sets the height
        self._restart_stationary()
        self.baro_rejecting, self.baro_rejecting_for = False, _ZERO  # the gap ends a baro rejection streak

    def _fuse_gravity(self, dx: np.ndarray, accel: np.ndarray, r, norm_error: np.float32, dt: np.float32) -> None:
        """FusionAltitudeInsFuseGravity: the accel's direction against the predicted up r, with acceleration
        rejection (norm error, m/s², and chord gates; recovery after recovery_trigger_period s)."""
        s = self._s
        fz = accel[2] - self.accel_z_bias_
        f_norm = np.sqrt(accel[0] * accel[0] + accel[1] * accel[1] + fz * fz)
        rejected = not (norm_error <= s.f32("accel_norm_rejection")) or not f_norm > 0  # |f| = 0: no direction
        if not rejected:
            u = (accel[0] / f_norm, accel[1] / f_norm, fz / f_norm)
            e = (u[0] - r[0], u[1] - r[1], u[2] - r[2])
            chord2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2]
            recovering = self.rejection_time > s.f32("recovery_trigger_period")
            gate = s.f32("accel_rejection")
            if chord2 > gate * gate and not recovering:
                rejected = True
            else:
                a0, a1, a2 = abs(r[0]), abs(r[1]), abs(r[2])
                skip = 2 if (a2 >= a0 and a2 >= a1) else (1 if a1 >= a0 else 0)
                R = s.f32("accel_attitude_noise") * s.f32("accel_attitude_noise")
                if skip != 0:
                    self._fuse(dx, 1, -r[2], 2, r[1], e[0], R)
                if skip != 1:
                    self._fuse(dx, 0, r[2], 2, -r[0], e[1], R)
                if skip != 2:
                    self._fuse(dx, 0, -r[1], 1, r[0], e[2], R)
        self.rejection_time = (self.rejection_time + dt) if rejected else _ZERO
        self.accel_rejected = rejected

    def _fuse_stationary(self, dx: np.ndarray, gyro: np.ndarray, accel: np.ndarray, r, dt: np.float32) -> None:
        """FusionAltitudeInsFuseStationary: zero rate, zero velocity, and the accel z bias low-passed towards
        accel_z − g·r_z (m/s²)."""
        s = self._s
        R = s.f32("zero_rate_noise") * s.f32("zero_rate_noise")
        for i in range(3):
            self._fuse(dx, 3 + i, _ONE, -1, _ZERO, gyro[i] - self.gyro_bias_[i], R)
        self._fuse(dx, 7, _ONE, -1, _ZERO, -self.velocity, s.f32("zero_velocity_noise") * s.f32("zero_velocity_noise"))
        k = dt / (s.f32("accel_bias_time_constant") + dt)
        self.accel_z_bias_ = self.accel_z_bias_ + k * ((accel[2] - GRAVITY * r[2]) - self.accel_z_bias_)

    def _inject(self, dx: np.ndarray) -> None:
        """FusionAltitudeInsInject: the error state into the nominal state."""
        self.q = _rotate(self.q, _HALF * dx[0], _HALF * dx[1], _HALF * dx[2])
        self.gyro_bias_ = self.gyro_bias_ + dx[3:6]
        self.distance = self.distance + dx[6]
        self.velocity = self.velocity + dx[7]

    def _fuse_mag(self, mag: np.ndarray) -> None:
        """FusionAltitudeInsFuseMag (a reading present): the local → global yaw offset only."""
        w, x, y, z = self.q
        mx = (_ONE - _TWO * (y * y + z * z)) * mag[0] + _TWO * (x * y - w * z) * mag[1] + _TWO * (x * z + w * y) * mag[2]
        my = _TWO * (x * y + w * z) * mag[0] + (_ONE - _TWO * (x * x + z * z)) * mag[1] + _TWO * (y * z - w * x) * mag[2]
        horizontal = np.sqrt(mx * mx + my * my)
        if not horizontal > 0:
            return
        target_cos = mx / horizontal
        target_sin = -my / horizontal
        if not self.mag_initialised:
            self.yaw_cos, self.yaw_sin = target_cos, target_sin
            self.mag_initialised = True
        else:
            k = self.mag_elapsed / (self._s.f32("mag_time_constant") + self.mag_elapsed)
            c = self.yaw_cos + k * (target_cos - self.yaw_cos)
            sn = self.yaw_sin + k * (target_sin - self.yaw_sin)
            norm = np.sqrt(c * c + sn * sn)
            if norm > f32(1e-3):
                self.yaw_cos, self.yaw_sin = c / norm, sn / norm
            else:
                self.yaw_cos, self.yaw_sin = target_cos, target_sin
        self.mag_elapsed = _ZERO

    def _baro_silent_for(self, timeout: np.float32) -> bool:
        """FusionAltitudeInsIsBaroSilentFor: a baro reading once, none for longer than ``timeout`` s since."""
        return self.baro_initialised and bool(self.baro_elapsed > timeout)

    def _hold_height(self, d0: np.float32, v0: np.float32, dt: np.float32) -> None:
        """FusionAltitudeInsHoldHeight: beyond the dead-reckoning horizon the accel no longer moves d, v: v decays
        (time constant: the horizon, s), d integrates it; d, v decorrelated, sigma_d grows by sigma_v per s."""
        s, P = self._s, self.P
        k = dt / (s.f32("dead_reckoning_horizon") + dt)
        self.velocity = v0 - k * v0
        self.distance = d0 + self.velocity * dt
        velocity_floor = s.f32("initial_velocity_sigma") * s.f32("initial_velocity_sigma")
        pvv = P[7, 7] if P[7, 7] > velocity_floor else velocity_floor
        pdd = P[6, 6] if P[6, 6] > _ZERO else _ZERO
        sigma = np.sqrt(pdd) + np.sqrt(pvv) * dt
        grown = sigma * sigma
        _decorrelate(P, 6, grown if grown < VARIANCE_LIMIT else VARIANCE_LIMIT)
        _decorrelate(P, 7, pvv)

    def _forget_height(self) -> None:
        """FusionAltitudeInsForgetHeight: velocity variance raised to at least initial_velocity_sigma² ((m/s)²),
        d decorrelated with VARIANCE_LIMIT (m²), so the next baro reading sets d."""
        velocity = self._s.f32("initial_velocity_sigma") * self._s.f32("initial_velocity_sigma")
        self.P[7, 7] = self.P[7, 7] if self.P[7, 7] > velocity else velocity
        _decorrelate(self.P, 6, VARIANCE_LIMIT)

    def _fuse_baro(self, dx: np.ndarray, baro: np.float32) -> None:
        """FusionAltitudeInsFuseBaro (a reading present): bias, stationary bias filter, or the gated d update."""
        s = self._s
        if not self.baro_initialised:
            self.baro_bias_ = baro - self.distance
            self.baro_initialised = True
        elif self.stationary:
            k = self.baro_elapsed / (s.f32("baro_bias_time_constant") + self.baro_elapsed)
            self.baro_bias_ = self.baro_bias_ + k * ((baro - self.distance) - self.baro_bias_)
        else:
            R = s.f32("baro_noise") * s.f32("baro_noise")
            y = (baro - self.baro_bias_) - self.distance
            innovation = y - dx[6]
            gate = s.f32("baro_gate")
            if innovation * innovation > (gate * gate) * (self.P[6, 6] + R):
                self.baro_rejections_ = (self.baro_rejections_ + 1) & 0xFFFFFFFF
                if not self.baro_rejecting:
                    self.baro_rejecting, self.baro_rejecting_for = True, _ZERO
                if not (self.baro_rejecting_for > s.f32("baro_rejection_timeout")):
                    return  # rejected: the INS coasts on the IMU
                # the streak outlasted the timeout: the INS height is what is wrong; the reading sets it
                self.baro_resets_ = (self.baro_resets_ + 1) & 0xFFFFFFFF
                self._forget_height()
            self.baro_rejecting, self.baro_rejecting_for = False, _ZERO
            self._fuse(dx, 6, _ONE, -1, _ZERO, y, R)

    def update(self, gyro, accel, dt, baro_altitude=float("nan"), mag=None) -> None:
        """One IMU step (see :meth:`fusion_altitude.InsEstimator.update`)."""
        g, a, m, b, t = _ins_glue.step_inputs(gyro, accel, dt, baro_altitude, mag, self._gyro_scale,
                                              self._accel_scale)
        with np.errstate(all="ignore"):
            self._step(g, a, m, b, t)

    def update_batch(self, gyro, accel, dt, baro_altitude=None, mag=None, out=None) -> InsBatch:
        """Arrays of steps (see :meth:`fusion_altitude.InsEstimator.update_batch`)."""
        n, inputs, result = _ins_glue.prepare_batch(gyro, accel, dt, baro_altitude, mag, out, self._gyro_scale,
                                                    self._accel_scale)
        with np.errstate(all="ignore"):
            for i in range(n):
                self._step(inputs["gyro"][i], inputs["accel"][i], inputs["mag"][i], inputs["baro_altitude"][i],
                           inputs["dt"][i])
                result.height_above_start[i] = self.distance
                result.vertical_velocity[i] = self.velocity
                result.quaternion[i] = self.q
                result.global_quaternion[i] = self.global_quaternion
                result.gyro_bias[i] = self.gyro_bias_
                result.accel_z_bias[i] = self.accel_z_bias_
                result.baro_bias[i] = self.baro_bias_
                result.is_stationary[i] = self.stationary
                result.baro_timed_out[i] = self.baro_timed_out
        return result if out is None else out  # out=: the caller's object itself

    # -- getters -------------------------------------------------------------------------------
    @property
    def altitude(self) -> float:
        """Altitude in the baro's datum, m, +up: ``height_above_start + baro_bias`` (float32 sum), as every
        estimator's ``altitude`` (in 0.1.0 it was the height above the start; see docs/ins.md)."""
        return float(f32(self.distance) + f32(self.baro_bias_))

    @property
    def baro_datum_altitude(self) -> float:
        """The same as :attr:`altitude` (altitude in the baro's datum, m, +up), kept from the release that added it."""
        return self.altitude

    height_above_start = state_property(
        "distance", "The height above the reference d, m, +up (the baro reads d + baro bias).")
    vertical_velocity = state_property("velocity", "m/s, +up.")

    @property
    def quaternion(self) -> np.ndarray:
        """Local attitude (w, x, y, z), body → local NWU earth, float32 copy."""
        return self.q.copy()

    @property
    def local_to_global(self) -> np.ndarray:
        """FusionAltitudeInsGetLocalToGlobal: rotation about up by the magnetometer's yaw offset."""
        a = _ONE + self.yaw_cos
        b = self.yaw_sin
        norm = np.sqrt(a * a + b * b)
        if norm > f32(1e-6):
            return np.array([a / norm, 0, 0, b / norm], dtype=f32)
        return np.array([0, 0, 0, 1], dtype=f32)

    @property
    def global_quaternion(self) -> np.ndarray:
        """FusionAltitudeInsGetGlobalQuaternion: local_to_global ⊗ quaternion."""
        a = self.local_to_global
        w, x, y, z = self.q
        return np.array([a[0] * w - a[3] * z, a[0] * x - a[3] * y, a[0] * y + a[3] * x, a[0] * z + a[3] * w],
                        dtype=f32)

    @property
    def euler(self) -> np.ndarray:
        """Local roll, pitch, yaw, degrees."""
        return _ins_glue.quaternion_to_euler(self.q)

    @property
    def global_euler(self) -> np.ndarray:
        """Global roll, pitch, yaw (yaw from the magnetometer), degrees."""
        return _ins_glue.quaternion_to_euler(self.global_quaternion)

    @property
    def gyro_bias(self) -> np.ndarray:
        """rad/s, body frame, float32 copy."""
        return self.gyro_bias_.copy()

    accel_z_bias = state_property("accel_z_bias_", "m/s², body z (learned while stationary).")
    baro_bias = state_property("baro_bias_", "m: the baro altitude at d = 0.")
    is_stationary = state_property("stationary", None, bool)
    is_accel_rejected = state_property("accel_rejected", None, bool)
    gap_count = state_property("gap_count_", "Steps with dt > gap_period, not integrated.", int)
    baro_rejections = state_property("baro_rejections_", "Baro readings rejected by the innovation gate, in total.",
                                     int)
    baro_resets = state_property(
        "baro_resets_", "Height resets from the baro after a rejection streak longer than baro_rejection_timeout.", int)

    @property
    def baro_timed_out(self) -> bool:
        """Not baro-aided: the baro had a reading, then none for longer than ``baro_timeout`` s
        (FusionAltitudeInsIsBaroTimedOut)."""
        return self._baro_silent_for(self._s.f32("baro_timeout"))

    @property
    def height_held(self) -> bool:
        """Dead reckoning stopped: no baro reading for longer than ``dead_reckoning_horizon`` s; the velocity decays
        to 0 and the height variance grows (FusionAltitudeInsIsHeightHeld)."""
        return self._baro_silent_for(self._s.f32("dead_reckoning_horizon"))

    baro_timeouts = state_property(
        "baro_timeouts_", "Baro silences longer than ``baro_timeout`` so far, each counted once.", int)
    is_baro_rejecting = state_property("baro_rejecting", "A baro rejection streak is in progress.", bool)

    @property
    def covariance(self) -> np.ndarray:
        """Error covariance P (8 × 8), float32 copy."""
        return self.P.copy()

    def state_dict(self) -> dict:
        """Every field of the C struct, for bit-for-bit comparison with the binding."""
        return {
            "q": self.q.copy(), "gyro_bias": self.gyro_bias_.copy(), "distance": f32(self.distance),
            "velocity": f32(self.velocity), "P": self.P.copy(), "accel_z_bias": f32(self.accel_z_bias_),
            "baro_bias": f32(self.baro_bias_), "yaw_cos": f32(self.yaw_cos), "yaw_sin": f32(self.yaw_sin),
            "stationary_time": f32(self.stationary_time), "rejection_time": f32(self.rejection_time),
            "baro_elapsed": f32(self.baro_elapsed), "mag_elapsed": f32(self.mag_elapsed),
            "stationary_half_time": f32(self.stationary_half_time), "stationary_baro_sum": f32(self.stationary_baro_sum),
            "stationary_baro_count": f32(self.stationary_baro_count),
            "stationary_baro_previous": f32(self.stationary_baro_previous),
            "baro_rejecting_for": f32(self.baro_rejecting_for), "baro_rejections": int(self.baro_rejections_),
            "baro_resets": int(self.baro_resets_), "baro_timeouts": int(self.baro_timeouts_),
            "baro_rejecting": self.baro_rejecting,
            "gap_count": int(self.gap_count_), "aligned": self.aligned, "baro_initialised": self.baro_initialised,
            "mag_initialised": self.mag_initialised, "stationary": self.stationary,
            "stationary_half_done": self.stationary_half_done, "stationary_has_previous": self.stationary_has_previous,
            "stationary_baro_still": self.stationary_baro_still, "accel_rejected": self.accel_rejected,
        }

    # -- checkpoint: (the fields of FusionAltitudeIns in order, arrays as lists, P row-major; the input units) ------
    def _get_state(self) -> tuple:
        fields = (self._s.as_dict(), [float(x) for x in self.q], [float(x) for x in self.gyro_bias_],
                  float(self.distance), float(self.velocity), [float(x) for x in self.P.ravel()],
                  float(self.accel_z_bias_), float(self.baro_bias_), float(self.yaw_cos), float(self.yaw_sin),
                  float(self.stationary_time), float(self.rejection_time), float(self.baro_elapsed),
                  float(self.mag_elapsed), float(self.stationary_half_time), float(self.stationary_baro_sum),
                  float(self.stationary_baro_count), float(self.stationary_baro_previous),
                  float(self.baro_rejecting_for), int(self.gap_count_), int(self.baro_rejections_),
                  int(self.baro_resets_), int(self.baro_timeouts_), bool(self.aligned), bool(self.baro_initialised), bool(self.mag_initialised),
                  bool(self.stationary), bool(self.stationary_half_done), bool(self.stationary_has_previous),
                  bool(self.stationary_baro_still), bool(self.accel_rejected), bool(self.baro_rejecting))
        return fields, self._units

    def _set_state(self, state: tuple) -> None:
        fields, units = state
        if len(fields) == 31:  # a checkpoint from before the baro timeout
            fields = (*fields[:22], 0, *fields[22:])
        (settings, q, gyro_bias, distance, velocity, P, accel_z_bias, baro_bias, yaw_cos, yaw_sin, stationary_time,
         rejection_time, baro_elapsed, mag_elapsed, half_time, baro_sum, baro_count, baro_previous, rejecting_for,
         gap_count, baro_rejections, baro_resets, baro_timeouts, aligned, baro_initialised, mag_initialised, stationary, half_done,
         has_previous, baro_still, accel_rejected, baro_rejecting) = fields
        self._gyro_scale, self._accel_scale = _ins_glue.units_tuple(*units)
        self._units = tuple(units)
        self._s = InsSettings(**settings)
        self.q = np.array(q, dtype=f32)
        self.gyro_bias_ = np.array(gyro_bias, dtype=f32)
        self.distance, self.velocity = f32(distance), f32(velocity)
        self.P = np.array(P, dtype=f32).reshape(N_STATES, N_STATES)
        self.accel_z_bias_, self.baro_bias_ = f32(accel_z_bias), f32(baro_bias)
        self.yaw_cos, self.yaw_sin = f32(yaw_cos), f32(yaw_sin)
        self.stationary_time, self.rejection_time = f32(stationary_time), f32(rejection_time)
        self.baro_elapsed, self.mag_elapsed = f32(baro_elapsed), f32(mag_elapsed)
        self.stationary_half_time, self.stationary_baro_sum = f32(half_time), f32(baro_sum)
        self.stationary_baro_count, self.stationary_baro_previous = f32(baro_count), f32(baro_previous)
        self.stationary_half_done, self.stationary_has_previous = bool(half_done), bool(has_previous)
        self.stationary_baro_still = bool(baro_still)
        self.gap_count_ = int(gap_count)
        self.baro_rejecting_for = f32(rejecting_for)
        self.baro_rejections_, self.baro_resets_ = int(baro_rejections), int(baro_resets)
        self.baro_timeouts_ = int(baro_timeouts)
        self.baro_rejecting = bool(baro_rejecting)
        self.aligned, self.baro_initialised, self.mag_initialised = bool(aligned), bool(baro_initialised), \
            bool(mag_initialised)
        self.stationary, self.accel_rejected = bool(stationary), bool(accel_rejected)

    def __repr__(self):
        return (f"InsEstimator(altitude={self.altitude!r}, vertical_velocity={self.vertical_velocity!r}, "
                f"is_stationary={self.is_stationary!r})")
