# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Cython binding of the multi-sensor Kalman filter in csrc/fusion_altitude_kalman.h: see ``_core/__init__.py`` for what a binding does."""

import math

from cpython.long cimport PyLong_AsLongLongAndOverflow, PyLong_CheckExact
from libc.math cimport NAN
from libc.stdint cimport int32_t, uint8_t, uint32_t

include "_kalman_fields.pxi"

import numpy as np

from fusion_altitude._core._kalman_glue import KalmanBatch, KalmanResult, KalmanSensors, KalmanStatus

kalman_status_message = c_status_message
_settings_error = _kalman_glue.raise_kalman_settings_error


#: An argument left out (update's keywords default to it, so that a name given twice in the deprecated
#: positional order is caught).
cdef object _UNSET = _common.UNSET
_UPDATE_KEYWORDS = ("baro_altitude", "dt", "range_distance", "gps_altitude", "gps_satellites",
                    "gps_vertical_accuracy", "ground_effect")
_BATCH_KEYWORDS = _UPDATE_KEYWORDS + ("out",)


cdef int32_t _satellites(object value) except? -2:
    """gps_satellites as a C int32 (as _kalman_glue.kalman_satellites; a plain int without a Python call)."""
    cdef int overflow = 0
    cdef long long count
    if PyLong_CheckExact(value):
        count = PyLong_AsLongLongAndOverflow(value, &overflow)
        if overflow > 0 or count > 2147483647:
            return 2147483647
        if overflow == 0 and count >= 0:
            return <int32_t>count
    return _kalman_glue.kalman_satellites(value)  # None, NaN, floats, and the refusal of a negative count


cdef class KalmanEstimator(_KalmanEstimatorGetters):
    __doc__ = DOC_KalmanEstimator  # generated from the reference's docstring (_kalman_fields.pxi)


    def __init__(self, settings=None):
        cdef FusionAltitudeKalmanSettings c
        if settings is None:
            FusionAltitudeKalmanInitialise(&self._c)
        else:
            c = _settings_to_c(KalmanSettings.coerce(settings).as_dict())
            FusionAltitudeKalmanInitialiseWith(&self._c, &c)

    def update(self, accel, *args, baro_altitude=_UNSET, dt=_UNSET, range_distance=_UNSET, gps_altitude=_UNSET,
               gps_satellites=_UNSET, gps_vertical_accuracy=_UNSET, ground_effect=_UNSET):
        # Parsed here, not by a Python wrapper: keywords after accel (the contract) are the fast path;
        # update(accel, baro_altitude, dt=...) is the contract too; other positional arguments after accel
        # are the deprecated old order (_common.positional_after_accel: the same rules as the reference).
        if args:
            baro_altitude, dt, range_distance, gps_altitude, gps_satellites, gps_vertical_accuracy, ground_effect = \
                _common.positional_after_accel(
                    type(self).__name__, "update", _UPDATE_KEYWORDS, _kalman_glue.KALMAN_LEGACY_ORDER, args,
                    (baro_altitude, dt, range_distance, gps_altitude, gps_satellites, gps_vertical_accuracy,
                     ground_effect), _UNSET)
        self._update(accel, baro_altitude, dt, range_distance, gps_altitude, gps_satellites, gps_vertical_accuracy,
                     ground_effect)

    cdef int _update(self, accel, baro_altitude, dt, range_distance, gps_altitude, gps_satellites,
                     gps_vertical_accuracy, ground_effect) except -1:
        """update() after argument parsing: _UNSET is an argument left out (its default)."""
        cdef FusionAltitudeKalmanMeasurements m
        cdef double a = _as_double(accel, "accel")
        cdef double t = _as_double(None if dt is _UNSET else dt, "dt")
        m.baroAltitude = NAN if baro_altitude is _UNSET else <float>_as_double(baro_altitude, "baro_altitude")
        m.rangeDistance = NAN if range_distance is _UNSET else <float>_as_double(range_distance, "range_distance")
        m.gpsAltitude = NAN if gps_altitude is _UNSET else <float>_as_double(gps_altitude, "gps_altitude")
        m.gpsVerticalAccuracy = NAN if gps_vertical_accuracy is _UNSET or gps_vertical_accuracy is None else \
            <float>_as_double(gps_vertical_accuracy, "gps_vertical_accuracy")
        m.gpsSatellites = -1 if gps_satellites is _UNSET or gps_satellites is None else _satellites(gps_satellites)
        m.groundEffect = False if ground_effect is _UNSET else <bint>ground_effect
        cdef FusionAltitudeKalmanStatus status = FusionAltitudeKalmanUpdate(&self._c, <float>a, <float>t, &m)
        if status != FusionAltitudeKalmanStatusOk:
            _kalman_glue.raise_kalman_update_error(status, {
                "accel": accel, "dt": dt, "baro_altitude": math.nan if baro_altitude is _UNSET else baro_altitude,
                "gps_altitude": math.nan if gps_altitude is _UNSET else gps_altitude,
                "gps_vertical_accuracy": None if gps_vertical_accuracy is _UNSET else gps_vertical_accuracy})
        return 0

    def update_batch(self, accel, *args, baro_altitude=_UNSET, dt=_UNSET, range_distance=_UNSET,
                     gps_altitude=_UNSET, gps_satellites=_UNSET, gps_vertical_accuracy=_UNSET, ground_effect=_UNSET,
                     out=_UNSET):
        """Process arrays of steps, continuing from the current state.

        Parameters
        ----------
        accel : array_like
            Vertical acceleration per step, m/s² (1-D, any real dtype; converted to float32).
        dt : float or array_like
            Step period, s: one value for all steps or one per step.
        baro_altitude, range_distance, gps_altitude, gps_vertical_accuracy : array_like, float or None
            Per step, m; NaN where a sensor has no sample. A scalar applies to
            every step; None means no samples (no reported accuracy).
        gps_satellites : array_like, int or None
            Per step; negative or NaN: unknown. None: unknown throughout.
        ground_effect : array_like of bool, bool or None
            Per step ground-effect flag.
        out : KalmanBatch, optional
            Preallocated contiguous output arrays of the right shapes and
            dtypes (reusing them avoids page faults on long logs).

        Returns
        -------
        KalmanBatch
            The state after each step, the covariance diagonal, and the
            innovation, NIS and :class:`KalmanResult` of each sensor.

        Raises
        ------
        ValueError
            A bad step (as for :meth:`update`), naming the argument and its
            first bad index; nothing is applied to the state.

        Notes
        -----
        Equal, bit for bit, to calling :meth:`update` for each step. The loop
        runs with the GIL released.
        """
        values = (baro_altitude, dt, range_distance, gps_altitude, gps_satellites, gps_vertical_accuracy,
                  ground_effect, out)
        if args:  # as in update
            values = _common.positional_after_accel(type(self).__name__, "update_batch", _BATCH_KEYWORDS,
                                                    _kalman_glue.KALMAN_LEGACY_ORDER + ("out",), args, values, _UNSET)
        baro_altitude, dt, range_distance, gps_altitude, gps_satellites, gps_vertical_accuracy, ground_effect, \
            out = [None if value is _UNSET else value for value in values]  # left out: None (no samples)
        n, inputs, steps, result = _kalman_glue.prepare_kalman_batch(
            accel, dt, baro_altitude, range_distance, gps_altitude, gps_satellites, gps_vertical_accuracy,
            ground_effect, out)
        bad = _batch_into(&self._c, n, inputs, steps, result)  # the loop: _kalman_fields.pxi
        if bad >= 0:
            at = {name: array[bad * steps[name]] for name, array in inputs.items()}  # the first bad step's inputs
            status = self._rejection(at["accel"], at["dt"], at["baro_altitude"], at["range_distance"],
                                     at["gps_altitude"], at["gps_vertical_accuracy"], at["gps_satellites"],
                                     at["ground_effect"])
            values = {name: float(at[name]) for name in ("accel", "dt", "baro_altitude", "gps_altitude",
                                                         "gps_vertical_accuracy")}
            _kalman_glue.raise_kalman_update_error(status, values, bad, {k: bool(s) for k, s in steps.items()})
        return result if out is None else out  # out=: the caller's object itself, filled

    cdef FusionAltitudeKalmanStatus _rejection(self, float accel, float dt, float baro, float rng, float gps,
                                               float accuracy, int32_t satellites, uint8_t ground):
        """The status the first bad step gets, from a state the batch did not touch.

        The batch stops at the first rejected step, but its state then is not
        this one: every input check comes before any state change in
        FusionAltitudeKalmanUpdate and depends on the inputs alone, so the
        status is the same from any state.
        """
        cdef FusionAltitudeKalman trial = self._c
        cdef FusionAltitudeKalmanMeasurements m
        m.baroAltitude = baro
        m.rangeDistance = rng
        m.gpsAltitude = gps
        m.gpsVerticalAccuracy = accuracy
        m.gpsSatellites = satellites
        m.groundEffect = ground != 0
        return FusionAltitudeKalmanUpdate(&trial, accel, dt, &m)

    @property
    def state(self):
        """State vector (h, v, baro_offset, gps_offset, accel_bias), float32 copy."""
        return np.array([self._c.x[i] for i in range(5)], dtype=np.float32)

    @property
    def covariance(self):
        """Covariance P (5×5, order of :attr:`state`), float32 copy."""
        return np.array([[self._c.P[i][j] for j in range(5)] for i in range(5)], dtype=np.float32)

    @property
    def innovations(self):
        """Latest innovation y = z − H·x per sensor, m (NaN: no tested sample)."""
        return KalmanSensors(*(self._c.sensors[i].innovation for i in range(3)))

    @property
    def innovation_variances(self):
        """Latest innovation variance S per sensor, m² (NaN: no tested sample)."""
        return KalmanSensors(*(self._c.sensors[i].innovationVariance for i in range(3)))

    @property
    def nis(self):
        """Latest normalized innovation squared y²/S per sensor (NaN: no tested sample)."""
        return KalmanSensors(*(FusionAltitudeKalmanGetNis(&self._c, <FusionAltitudeKalmanSensorIndex>i) for i in range(3)))

    @property
    def rejections(self):
        """Samples rejected by the gate so far, per sensor."""
        return KalmanSensors(*(int(self._c.sensors[i].rejections) for i in range(3)))

    @property
    def resets(self):
        """Resets after rejection streaks longer than the timeout, per sensor."""
        return KalmanSensors(*(int(self._c.sensors[i].resets) for i in range(3)))

    @property
    def timeout_counts(self):
        """Silences longer than the sensor's timeout so far, per sensor (each counted once)."""
        return KalmanSensors(*(int(self._c.sensors[i].timeouts) for i in range(3)))

    @property
    def results(self):
        """What the latest update did with each sensor (:class:`KalmanResult`)."""
        return KalmanSensors(*(KalmanResult(<int>self._c.sensors[i].result) for i in range(3)))

    @property
    def baro_initialised(self):
        """Whether the baro offset is set (first baro sample seen)."""
        return bool(self._c.baroInitialised)

    @property
    def gps_initialised(self):
        """Whether the GPS offset is set (first usable GPS sample seen)."""
        return bool(self._c.gpsInitialised)

    def _set_state(self, state):
        state = list(state)
        sensors = state[3]
        if sensors and len(sensors[0]) == 8:  # a checkpoint from before the sensor timeouts (with nis)
            state[3] = [(*row[:2], row[3], 0.0, row[4], row[5], 0, row[6], row[7], False, False) for row in sensors]
        _state_set(&self._c, tuple(state), _checked_settings)

    def __repr__(self):
        return (f"KalmanEstimator(height_above_ground={self.height_above_ground!r}, altitude={self.altitude!r}, "
                f"vertical_velocity={self.vertical_velocity!r}, accel_bias={self.accel_bias!r})")


_common.share_docstrings(KalmanEstimator, _kalman_glue.KalmanContract)
_common.share_signatures(KalmanEstimator, _kalman_glue.KalmanContract, ("update", "update_batch"))


_kalman_glue.C_SETTINGS_FUNCTIONS.update(check=c_settings_check)
