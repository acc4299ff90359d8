# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Cython binding of the inertial navigation filter in csrc/fusion_altitude_ins.h.

This module converts and checks Python arguments, calls the C functions and
raises for the statuses they return. It holds no copy of the algorithm.
"""

import math

from cpython.list cimport PyList_CheckExact
from cpython.tuple cimport PyTuple_CheckExact
from libc.stdint cimport uint8_t, uint32_t
from libc.string cimport memcpy

from fusion_altitude._convert cimport as_double as _as_double
from fusion_altitude.cins cimport *

import numpy as np

from fusion_altitude import _ins_glue
from fusion_altitude._ins_glue import InsBatch, InsStatus

#: The C enum values, for checking that :class:`fusion_altitude.InsStatus` matches.
C_STATUS_VALUES = {
    "OK": FusionAltitudeInsStatusOk,
    "INVALID_GYRO": FusionAltitudeInsStatusInvalidGyro,
    "INVALID_ACCEL": FusionAltitudeInsStatusInvalidAccel,
    "INVALID_MAG": FusionAltitudeInsStatusInvalidMag,
    "INVALID_BARO_ALTITUDE": FusionAltitudeInsStatusInvalidBaroAltitude,
    "INVALID_DT": FusionAltitudeInsStatusInvalidDt,
    "INVALID_SETTINGS": FusionAltitudeInsStatusInvalidSettings,
}

_FIELDS = _ins_glue.INS_SETTINGS_NAMES


def c_default_settings():
    """FusionAltitudeInsSettingsDefault() as a dict, for checking the Python defaults against the header's."""
    cdef FusionAltitudeInsSettings c = FusionAltitudeInsSettingsDefault()
    cdef float *values = <float *>&c
    return {name: values[i] for i, name in enumerate(_FIELDS)}


def ins_status_message(int status):
    """The C header's message for a status code (FusionAltitudeInsStatusMessage)."""
    return FusionAltitudeInsStatusMessage(<FusionAltitudeInsStatus>status).decode("utf-8")


cdef class InsSettings:
    """Settings of the inertial navigation filter, float32, physical units. Keyword arguments only.

    Parameters (defaults: a MEMS IMU at 100–500 Hz on a multirotor)
    ----------------------------------------------------------------
    gyro_noise : 3e-4 rad/s/√Hz
        Gyro white-noise density.
    gyro_bias_random_walk : 1e-5 rad/s²/√Hz
        Gyro bias random walk.
    accel_noise : 0.05 m/s²/√Hz
        Vertical acceleration noise density (vibration included).
    accel_attitude_noise : 0.05 rad
        1σ of the gravity direction per sample (> 0).
    accel_norm_rejection : 2.0 m/s²
        The accelerometer is not used for attitude while ||accel| − g| exceeds it.
    accel_rejection : 0.17 rad
        ... nor while its direction is further than this from the prediction.
    recovery_trigger_period : 5.0 s
        Rejected for longer lifts the direction gate (the Fusion AHRS recovery).
    baro_noise : 0.3 m
        Baro 1σ per sample (> 0).
    stationary_gyro_threshold, stationary_accel_threshold, stationary_window : 0.05 rad/s, 0.5 m/s², 1.0 s
        Stationary once |gyro| and ||accel| − g| stayed below the thresholds on every sample for the window.
    zero_rate_noise, zero_velocity_noise : 0.01 rad/s, 0.05 m/s
        1σ of the zero-rate and zero-velocity updates while stationary (> 0).
    baro_bias_time_constant, accel_bias_time_constant : 5.0 s, 2.0 s
        Complementary filters of the baro bias and the accel z bias while stationary (> 0).
    mag_time_constant : 2.0 s
        Local-to-global yaw filter (> 0).
    initial_attitude_sigma, initial_gyro_bias_sigma, initial_velocity_sigma : 0.05 rad, 0.01 rad/s, 0.5 m/s
    gap_period : 0.1 s
        A dt above it is a gap: not integrated, counted in ``gap_count`` (> 0).

    Raises
    ------
    ValueError
        A setting out of range, naming it. TypeError for an unknown name.
    """

    cdef FusionAltitudeInsSettings _c

    def __init__(self, **kwargs):
        values = _ins_glue.convert_ins_settings(kwargs)
        cdef float *fields = <float *>&self._c
        for i, name in enumerate(_FIELDS):
            fields[i] = values[name]

    def __getattr__(self, name):
        if name in _FIELDS:
            return float((<float *>&self._c)[_FIELDS.index(name)])
        raise AttributeError(name)

    def as_dict(self):
        """Every setting by name (Python floats of the float32 values)."""
        cdef float *fields = <float *>&self._c
        return {name: float(fields[i]) for i, name in enumerate(_FIELDS)}

    def replace(self, **changes):
        """A copy with some settings changed."""
        return InsSettings(**{**self.as_dict(), **changes})

    def __eq__(self, other):
        return isinstance(other, InsSettings) and self.as_dict() == other.as_dict()

    def __hash__(self):
        return hash(tuple(self.as_dict().items()))

    def __repr__(self):
        return "InsSettings(" + ", ".join(f"{k}={v!r}" for k, v in self.as_dict().items()) + ")"

    def __reduce__(self):
        return (_settings_from_dict, (self.as_dict(),))


def _settings_from_dict(values):
    return InsSettings(**values)


cdef inline int _vector(object value, double scale, str name, FusionAltitudeInsVector *out) except -1:
    """A 3-vector argument as float32 (value × scale in double): fast path for tuples and lists."""
    if (PyTuple_CheckExact(value) or PyList_CheckExact(value)) and len(value) == 3:
        out.x = <float>(_as_double(value[0], name) * scale)
        out.y = <float>(_as_double(value[1], name) * scale)
        out.z = <float>(_as_double(value[2], name) * scale)
        return 0
    array = _ins_glue.as_vector(value, scale, name)
    out.x = array[0]
    out.y = array[1]
    out.z = array[2]
    return 0


cdef Py_ssize_t _run(FusionAltitudeIns *ins, Py_ssize_t n, const float *gyro, const float *accel, const float *mag,
                     const float *baro, const float *dt, float *altitude, float *velocity, float *quaternion,
                     float *global_quaternion, float *gyro_bias, float *accel_z_bias, float *baro_bias,
                     uint8_t *stationary) noexcept nogil:
    """The batch loop: one FusionAltitudeInsUpdate per row; returns the first rejected row or -1."""
    cdef Py_ssize_t i
    cdef FusionAltitudeInsVector g, a, m, b
    cdef FusionAltitudeInsQuaternion q
    for i in range(n):
        g.x = gyro[3 * i]
        g.y = gyro[3 * i + 1]
        g.z = gyro[3 * i + 2]
        a.x = accel[3 * i]
        a.y = accel[3 * i + 1]
        a.z = accel[3 * i + 2]
        m.x = mag[3 * i]
        m.y = mag[3 * i + 1]
        m.z = mag[3 * i + 2]
        if FusionAltitudeInsUpdate(ins, g, a, m, baro[i], dt[i]) != FusionAltitudeInsStatusOk:
            return i
        altitude[i] = FusionAltitudeInsGetAltitude(ins)
        velocity[i] = FusionAltitudeInsGetVerticalVelocity(ins)
        q = FusionAltitudeInsGetQuaternion(ins)
        quaternion[4 * i] = q.w
        quaternion[4 * i + 1] = q.x
        quaternion[4 * i + 2] = q.y
        quaternion[4 * i + 3] = q.z
        q = FusionAltitudeInsGetGlobalQuaternion(ins)
        global_quaternion[4 * i] = q.w
        global_quaternion[4 * i + 1] = q.x
        global_quaternion[4 * i + 2] = q.y
        global_quaternion[4 * i + 3] = q.z
        b = FusionAltitudeInsGetGyroBias(ins)
        gyro_bias[3 * i] = b.x
        gyro_bias[3 * i + 1] = b.y
        gyro_bias[3 * i + 2] = b.z
        accel_z_bias[i] = FusionAltitudeInsGetAccelZBias(ins)
        baro_bias[i] = FusionAltitudeInsGetBaroBias(ins)
        stationary[i] = FusionAltitudeInsIsStationary(ins)
    return -1


cdef class InsEstimator:
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
    ``altitude`` is the height d above the reference, m, +up; the baro reads
    ``altitude + baro_bias``. The first baro sample sets ``baro_bias``; while
    stationary every baro reading goes to ``baro_bias`` (the height is held by
    a zero-velocity update) and the accel z bias is learned.
    """

    cdef FusionAltitudeIns _c
    cdef double _gyro_scale
    cdef double _accel_scale
    cdef tuple _units

    def __init__(self, settings=None, *, gyro_units="rad/s", accel_units="m/s^2"):
        cdef InsSettings s = _as_settings(settings)
        self._gyro_scale, self._accel_scale = _ins_glue.units_tuple(gyro_units, accel_units)
        self._units = (gyro_units, accel_units)
        FusionAltitudeInsInitialiseWith(&self._c, &s._c)  # settings already checked

    @property
    def settings(self):
        """The settings (InsSettings); assigning one keeps the state."""
        cdef InsSettings s = InsSettings.__new__(InsSettings)
        s._c = FusionAltitudeInsGetSettings(&self._c)
        return s

    @settings.setter
    def settings(self, value):
        cdef InsSettings s = _as_settings(value)
        FusionAltitudeInsSetSettings(&self._c, &s._c)

    def update(self, gyro, accel, dt, baro_altitude=math.nan, mag=None):
        """One IMU step.

        Parameters
        ----------
        gyro : sequence of 3 floats
            Angular rate, body frame, rad/s (or ``gyro_units``).
        accel : sequence of 3 floats
            Specific force, body frame, m/s² (or ``accel_units``): (0, 0, +g) level at rest.
        dt : float
            Time since the previous step, s. Above ``settings.gap_period``: a gap, not integrated.
        baro_altitude : float, optional
            Baro altitude, m, +up; NaN (default): no sample this step.
        mag : sequence of 3 floats, optional
            Magnetic field, body frame, any unit; None or all NaN: no sample.

        Raises
        ------
        ValueError
            A component not finite or above 1e6 in magnitude, baro infinite,
            dt not finite or <= 0; names the argument, the state is unchanged.
        TypeError
            An argument that is not real numbers.
        """
        cdef FusionAltitudeInsVector g, a, m
        _vector(gyro, self._gyro_scale, "gyro", &g)
        _vector(accel, self._accel_scale, "accel", &a)
        if mag is None:
            m = FusionAltitudeInsNoMag()
        else:
            _vector(mag, 1.0, "mag", &m)
        cdef float b = <float>_as_double(baro_altitude, "baro_altitude")
        cdef float t = <float>_as_double(dt, "dt")
        cdef FusionAltitudeInsStatus status = FusionAltitudeInsUpdate(&self._c, g, a, m, b, t)
        if status != FusionAltitudeInsStatusOk:
            _ins_glue.raise_step_error(InsStatus(status), {"gyro": [g.x, g.y, g.z], "accel": [a.x, a.y, a.z],
                                                           "mag": [m.x, m.y, m.z], "baro_altitude": b, "dt": t})

    def update_batch(self, gyro, accel, dt, baro_altitude=None, mag=None, out=None):
        """Process arrays of steps, continuing from the current state.

        Parameters
        ----------
        gyro, accel : array_like, shape (N, 3)
            Per step, rad/s and m/s² (or the estimator's units), body frame; any real dtype.
        dt : float or array_like
            Step period, s: one value for all steps or one per step.
        baro_altitude : array_like, float or None
            Per step, m; NaN rows: no sample. None: no baro at all.
        mag : array_like of shape (N, 3), or None
            Per step, any unit; all-NaN rows: no sample.
        out : InsBatch, optional
            Preallocated C-contiguous outputs of the right shapes and dtypes.

        Returns
        -------
        InsBatch
            The state after each step.

        Raises
        ------
        ValueError
            A bad step (as for :meth:`update`), naming the argument and its
            first bad index; nothing is applied.

        Notes
        -----
        Equal, bit for bit, to calling :meth:`update` for each step. The loop
        runs with the GIL released.
        """
        n, inputs, result = _ins_glue.prepare_batch(gyro, accel, dt, baro_altitude, mag, out, self._gyro_scale,
                                                    self._accel_scale)
        if n == 0:
            return result if out is None else out  # out=: the caller's object itself
        cdef const float[:, ::1] g = inputs["gyro"]
        cdef const float[:, ::1] a = inputs["accel"]
        cdef const float[:, ::1] m = inputs["mag"]
        cdef const float[::1] b = inputs["baro_altitude"]
        cdef const float[::1] t = inputs["dt"]
        cdef float[::1] h = result.altitude
        cdef float[::1] v = result.vertical_velocity
        cdef float[:, ::1] q = result.quaternion
        cdef float[:, ::1] qg = result.global_quaternion
        cdef float[:, ::1] bias = result.gyro_bias
        cdef float[::1] bz = result.accel_z_bias
        cdef float[::1] bb = result.baro_bias
        cdef uint8_t[::1] still = result.is_stationary.view(np.uint8)
        cdef FusionAltitudeIns saved = self._c
        cdef Py_ssize_t count = n
        cdef Py_ssize_t bad
        with nogil:
            bad = _run(&self._c, count, &g[0, 0], &a[0, 0], &m[0, 0], &b[0], &t[0], &h[0], &v[0], &q[0, 0], &qg[0, 0],
                       &bias[0, 0], &bz[0], &bb[0], &still[0])
        if bad >= 0:  # cannot happen: every row was checked first; keep nothing half-applied anyway
            self._c = saved
            raise RuntimeError(f"FusionAltitudeInsUpdate rejected row {bad} that passed the checks")
        return result if out is None else out  # out=: the caller's object itself

    @property
    def altitude(self):
        """Height above the reference d, m, +up (the baro reads altitude + baro_bias)."""
        return FusionAltitudeInsGetAltitude(&self._c)

    @property
    def vertical_velocity(self):
        """Vertical velocity, m/s, +up."""
        return FusionAltitudeInsGetVerticalVelocity(&self._c)

    @property
    def quaternion(self):
        """Local attitude (w, x, y, z), body → local NWU earth (yaw integrated from 0), float32."""
        cdef FusionAltitudeInsQuaternion q = FusionAltitudeInsGetQuaternion(&self._c)
        return np.array([q.w, q.x, q.y, q.z], dtype=np.float32)

    @property
    def local_to_global(self):
        """Rotation about up by the magnetometer's yaw offset (w, x, y, z), float32."""
        cdef FusionAltitudeInsQuaternion q = FusionAltitudeInsGetLocalToGlobal(&self._c)
        return np.array([q.w, q.x, q.y, q.z], dtype=np.float32)

    @property
    def global_quaternion(self):
        """Global attitude local_to_global ⊗ quaternion (north from the magnetometer), float32."""
        cdef FusionAltitudeInsQuaternion q = FusionAltitudeInsGetGlobalQuaternion(&self._c)
        return np.array([q.w, q.x, q.y, q.z], dtype=np.float32)

    @property
    def euler(self):
        """Local roll, pitch, yaw, degrees (ZYX, as imufusion's ``quaternion.to_euler()``)."""
        return _ins_glue.quaternion_to_euler(self.quaternion)

    @property
    def global_euler(self):
        """Global roll, pitch, yaw (yaw from the magnetometer), degrees."""
        return _ins_glue.quaternion_to_euler(self.global_quaternion)

    @property
    def gyro_bias(self):
        """Gyro bias, rad/s, body frame, float32."""
        cdef FusionAltitudeInsVector b = FusionAltitudeInsGetGyroBias(&self._c)
        return np.array([b.x, b.y, b.z], dtype=np.float32)

    @property
    def accel_z_bias(self):
        """Accelerometer z bias, m/s², body z (learned while stationary)."""
        return FusionAltitudeInsGetAccelZBias(&self._c)

    @property
    def baro_bias(self):
        """Baro bias, m: the baro altitude at altitude 0."""
        return FusionAltitudeInsGetBaroBias(&self._c)

    @property
    def is_stationary(self):
        """True while stationary (still for the whole window)."""
        return bool(FusionAltitudeInsIsStationary(&self._c))

    @property
    def is_accel_rejected(self):
        """True if the latest step did not use the accelerometer for attitude."""
        return bool(FusionAltitudeInsIsAccelRejected(&self._c))

    @property
    def gap_count(self):
        """Steps with dt > gap_period, not integrated."""
        return FusionAltitudeInsGetGapCount(&self._c)

    @property
    def covariance(self):
        """Error covariance P (8 × 8: attitude error, gyro bias, d, v), float32 copy."""
        return np.array(self._c.P, dtype=np.float32).reshape(8, 8)

    def state_dict(self):
        """Every field of the C struct, for bit-for-bit comparison with the reference."""
        cdef FusionAltitudeIns *c = &self._c
        return {
            "q": np.array([c.q[i] for i in range(4)], dtype=np.float32),
            "gyro_bias": np.array([c.gyroBias[i] for i in range(3)], dtype=np.float32),
            "distance": np.float32(c.distance), "velocity": np.float32(c.velocity), "P": self.covariance,
            "accel_z_bias": np.float32(c.accelZBias), "baro_bias": np.float32(c.baroBias),
            "yaw_cos": np.float32(c.yawCos), "yaw_sin": np.float32(c.yawSin),
            "stationary_time": np.float32(c.stationaryTime), "rejection_time": np.float32(c.rejectionTime),
            "baro_elapsed": np.float32(c.baroElapsed), "mag_elapsed": np.float32(c.magElapsed),
            "gap_count": int(c.gapCount), "aligned": bool(c.aligned), "baro_initialised": bool(c.baroInitialised),
            "mag_initialised": bool(c.magInitialised), "stationary": bool(c.stationary),
            "accel_rejected": bool(c.accelRejected),
        }

    def _get_state(self):
        return (bytes((<char *>&self._c)[:sizeof(FusionAltitudeIns)]), self._units)

    def __copy__(self):
        cdef InsEstimator clone = InsEstimator.__new__(InsEstimator)
        clone._c = self._c
        clone._gyro_scale = self._gyro_scale
        clone._accel_scale = self._accel_scale
        clone._units = self._units
        return clone

    def __deepcopy__(self, memo):
        return self.__copy__()

    def __reduce__(self):
        return (_restore, self._get_state())

    def __repr__(self):
        return (f"InsEstimator(altitude={self.altitude!r}, vertical_velocity={self.vertical_velocity!r}, "
                f"is_stationary={self.is_stationary!r})")


def _restore(bytes raw, tuple units):
    """Unpickle: the C struct's bytes (same platform layout) and the input units."""
    cdef InsEstimator estimator = InsEstimator.__new__(InsEstimator)
    if len(raw) != sizeof(FusionAltitudeIns):
        raise ValueError(f"pickled INS state has {len(raw)} bytes, this build expects {sizeof(FusionAltitudeIns)}")
    memcpy(&estimator._c, <const char *>raw, sizeof(FusionAltitudeIns))
    estimator._gyro_scale, estimator._accel_scale = _ins_glue.units_tuple(*units)
    estimator._units = units
    return estimator


cdef InsSettings _as_settings(object settings):
    if settings is None:
        return InsSettings()
    if isinstance(settings, InsSettings):
        return settings
    if hasattr(settings, "as_dict") and hasattr(settings, "gap_period"):
        return InsSettings(**settings.as_dict())
    raise TypeError(f"settings must be InsSettings, got {type(settings).__name__}")
