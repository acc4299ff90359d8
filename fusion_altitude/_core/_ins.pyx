# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Cython binding of the inertial navigation filter in csrc/fusion_altitude_ins.h: see ``_core/__init__.py`` for what a binding does."""

import math

from cpython.list cimport PyList_CheckExact
from cpython.tuple cimport PyTuple_CheckExact
from libc.stdint cimport uint8_t, uint32_t

include "_ins_fields.pxi"

import numpy as np

from fusion_altitude._core._ins_glue import InsBatch, InsStatus


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


cdef object _quaternion_array(FusionAltitudeInsQuaternion q):
    """A quaternion as the float32 array (w, x, y, z)."""
    return np.array([q.w, q.x, q.y, q.z], dtype=np.float32)


cdef Py_ssize_t _run(FusionAltitudeIns *ins, Py_ssize_t n, const float *gyro, const float *accel, const float *mag,
                     const float *baro, const float *dt, float *height, float *velocity, float *quaternion,
                     float *global_quaternion, float *gyro_bias, float *accel_z_bias, float *baro_bias,
                     uint8_t *stationary, uint8_t *timed_out, FusionAltitudeInsStatus *status) noexcept nogil:
    """The batch loop: one FusionAltitudeInsUpdate per row; returns the first rejected row (its status in *status)
    or -1."""
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
        status[0] = FusionAltitudeInsUpdate(ins, g, a, m, baro[i], dt[i])
        if status[0] != FusionAltitudeInsStatusOk:
            return i
        height[i] = FusionAltitudeInsGetAltitude(ins)
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
        timed_out[i] = FusionAltitudeInsIsBaroTimedOut(ins)
    return -1


cdef class InsEstimator(_InsEstimatorGetters):
    __doc__ = DOC_InsEstimator  # generated from the reference's docstring (_ins_fields.pxi)

    cdef double _gyro_scale
    cdef double _accel_scale
    cdef tuple _units

    def __init__(self, settings=None, *, gyro_units="rad/s", accel_units="m/s^2"):
        cdef FusionAltitudeInsSettings c = _settings_to_c(
            (InsSettings() if settings is None else InsSettings.coerce(settings)).as_dict())
        self._gyro_scale, self._accel_scale = _ins_glue.units_tuple(gyro_units, accel_units)
        self._units = (gyro_units, accel_units)
        FusionAltitudeInsInitialiseWith(&self._c, &c)  # settings already checked by InsSettings

    @property
    def altitude(self):
        """Altitude in the baro's datum, m, +up: ``height_above_start + baro_bias`` (float32 sum), as every
        estimator's ``altitude`` (in 0.1.0 it was the height above the start; see docs/ins.md)."""
        cdef float altitude = FusionAltitudeInsGetAltitude(&self._c) + FusionAltitudeInsGetBaroBias(&self._c)
        return altitude

    @property
    def baro_datum_altitude(self):
        """The same as :attr:`altitude` (altitude in the baro's datum, m, +up), kept from the release that added it."""
        return self.altitude

    def reset(self):
        """Back to the start state (not aligned, FusionAltitudeInsInitialiseWith), keeping the settings and units."""
        cdef FusionAltitudeInsSettings c = self._c.settings
        FusionAltitudeInsInitialiseWith(&self._c, &c)

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
            first bad index; the state is left as it was (``out``'s rows
            before that index may have been written).

        Notes
        -----
        Equal, bit for bit, to calling :meth:`update` for each step. The loop
        runs with the GIL released.
        """
        n, inputs, result = _ins_glue.prepare_batch(gyro, accel, dt, baro_altitude, mag, out, self._gyro_scale,
                                                    self._accel_scale, check=False)
        if n == 0:
            return result if out is None else out  # out=: the caller's object itself
        cdef const float[:, ::1] g = inputs["gyro"]
        cdef const float[:, ::1] a = inputs["accel"]
        cdef const float[:, ::1] m = inputs["mag"]
        cdef const float[::1] b = inputs["baro_altitude"]
        cdef const float[::1] t = inputs["dt"]
        cdef float[::1] h = result.height_above_start
        cdef float[::1] v = result.vertical_velocity
        cdef float[:, ::1] q = result.quaternion
        cdef float[:, ::1] qg = result.global_quaternion
        cdef float[:, ::1] bias = result.gyro_bias
        cdef float[::1] bz = result.accel_z_bias
        cdef float[::1] bb = result.baro_bias
        cdef uint8_t[::1] still = result.is_stationary.view(np.uint8)
        cdef uint8_t[::1] timed_out = result.baro_timed_out.view(np.uint8)
        cdef FusionAltitudeIns saved = self._c
        cdef Py_ssize_t count = n
        cdef Py_ssize_t bad
        cdef FusionAltitudeInsStatus status = FusionAltitudeInsStatusOk
        with nogil:
            bad = _run(&self._c, count, &g[0, 0], &a[0, 0], &m[0, 0], &b[0], &t[0], &h[0], &v[0], &q[0, 0], &qg[0, 0],
                       &bias[0, 0], &bz[0], &bb[0], &still[0], &timed_out[0], &status)
        if bad >= 0:  # the C checks of each step (no separate pass over the inputs): nothing applied, the first bad step
            self._c = saved
            _ins_glue.batch_step_error(status, inputs, bad)
        return result if out is None else out  # out=: the caller's object itself

    @property
    def quaternion(self):
        """Local attitude (w, x, y, z), body → local NWU earth (yaw integrated from 0), float32."""
        return _quaternion_array(FusionAltitudeInsGetQuaternion(&self._c))

    @property
    def local_to_global(self):
        """Rotation about up by the magnetometer's yaw offset (w, x, y, z), float32."""
        return _quaternion_array(FusionAltitudeInsGetLocalToGlobal(&self._c))

    @property
    def global_quaternion(self):
        """Global attitude local_to_global ⊗ quaternion (north from the magnetometer), float32."""
        return _quaternion_array(FusionAltitudeInsGetGlobalQuaternion(&self._c))

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
            "stationary_half_time": np.float32(c.stationaryHalfTime),
            "stationary_baro_sum": np.float32(c.stationaryBaroSum),
            "stationary_baro_count": np.float32(c.stationaryBaroCount),
            "stationary_baro_previous": np.float32(c.stationaryBaroPrevious),
            "baro_rejecting_for": np.float32(c.baroRejectingFor), "baro_rejections": int(c.baroRejections),
            "baro_resets": int(c.baroResets), "baro_timeouts": int(c.baroTimeouts),
            "baro_rejecting": bool(c.baroRejecting),
            "gap_count": int(c.gapCount), "aligned": bool(c.aligned), "baro_initialised": bool(c.baroInitialised),
            "mag_initialised": bool(c.magInitialised), "stationary": bool(c.stationary),
            "stationary_half_done": bool(c.stationaryHalfDone), "stationary_has_previous": bool(c.stationaryHasPrevious),
            "stationary_baro_still": bool(c.stationaryBaroStill), "accel_rejected": bool(c.accelRejected),
        }

    def _get_state(self):
        """(the fields of FusionAltitudeIns in order, arrays as lists, P row-major; the input units)."""
        return (_state_get(&self._c, dict), self._units)

    def _set_state(self, state):
        fields, units = state
        fields = tuple(fields)
        if len(fields) == 31:  # a checkpoint from before the baro timeout
            fields = (*fields[:22], 0, *fields[22:])
        self._gyro_scale, self._accel_scale = _ins_glue.units_tuple(*units)
        self._units = tuple(units)
        _state_set(&self._c, fields, _checked_settings)

    def __repr__(self):
        return (f"InsEstimator(altitude={self.altitude!r}, vertical_velocity={self.vertical_velocity!r}, "
                f"is_stationary={self.is_stationary!r})")


_ins_glue.C_SETTINGS_FUNCTIONS.update(check=c_settings_check)
