# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Cython binding of the complementary altitude observer in csrc/fusion_altitude.h: see ``_core/__init__.py`` for what a binding does."""

include "_observer_fields.pxi"

from fusion_altitude._core._observer_glue import AltitudeBatch

GRAVITY = _common.GRAVITY
C_GRAVITY = FUSION_ALTITUDE_GRAVITY
C_VERSION = FUSION_ALTITUDE_VERSION
status_message = c_status_message


def c_settings_from_bandwidth(float omega, float zeta, float omega_b):
    """FusionAltitudeSettingsFromBandwidth, from C: (status, gains dict)."""
    cdef FusionAltitudeSettings c
    cdef FusionAltitudeStatus status = FusionAltitudeSettingsFromBandwidth(&c, omega, zeta, omega_b)
    return int(status), (_settings_from_c(&c) if status == FusionAltitudeStatusOk else None)


def c_gains_check(float position_gain, float velocity_gain, float bias_gain):
    """FusionAltitudeSettingsCheck of the gains (with the default gap period and baro timeout), from C: the status."""
    cdef FusionAltitudeSettings c = FusionAltitudeSettingsDefault()
    c.positionGain = position_gain
    c.velocityGain = velocity_gain
    c.biasGain = bias_gain
    return int(FusionAltitudeSettingsCheck(&c))


_observer_glue.C_SETTINGS_FUNCTIONS.update(from_bandwidth=c_settings_from_bandwidth, check_gains=c_gains_check)


def c_settings_from_preset(int preset):
    """FusionAltitudeSettingsFromPreset, from C: the gains dict."""
    cdef FusionAltitudeSettings c
    FusionAltitudeSettingsFromPreset(&c, <FusionAltitudePreset>preset)
    return _settings_from_c(&c)


def c_settings_validate(values, float dt):
    """FusionAltitudeSettingsValidate (Jury's test at dt), from C: the status."""
    cdef FusionAltitudeSettings c = _settings_to_c(values)
    return int(FusionAltitudeSettingsValidate(&c, dt))


_observer_glue.C_SETTINGS_FUNCTIONS.update(validate=c_settings_validate)


def _gains(values):
    return tuple(values.values())


def _checked_gains(gains):
    return AltitudeSettings(*gains).as_dict()


_settings_out, _checked_settings = _gains, _checked_gains  # a checkpoint holds the gains as a tuple


cdef class AltitudeEstimator(_AltitudeEstimatorGetters):
    __doc__ = DOC_AltitudeEstimator  # generated from the reference's docstring (_observer_fields.pxi)

    def __init__(self, settings=None):
        self._initialise(settings)  # _observer_fields.pxi

    def update(self, accel, baro_altitude, dt):
        cdef double a = _as_double(accel, "accel")
        cdef double z = _as_double(baro_altitude, "baro_altitude")
        cdef double t = _as_double(dt, "dt")
        cdef FusionAltitudeStatus status = FusionAltitudeUpdate(&self._c, <float>a, <float>z, <float>t)
        if status != FusionAltitudeStatusOk:
            _observer_glue.raise_update_error(status, a, z, t)

    def reset(self, baro_altitude, accel_bias=None):
        """Set the reference: altitude = ``baro_altitude`` (m), velocity 0, residual 0.

        The bias estimate is kept unless ``accel_bias`` (m/s², +up) is given
        (warm start from a ground calibration).

        Raises
        ------
        ValueError
            baro_altitude or accel_bias not finite; the state is unchanged.
        """
        cdef double z = _as_double(baro_altitude, "baro_altitude")
        cdef double b = 0.0
        cdef FusionAltitudeStatus status
        if accel_bias is None:
            status = FusionAltitudeReset(&self._c, <float>z)
        else:
            b = _as_double(accel_bias, "accel_bias")
            status = FusionAltitudeResetWithBias(&self._c, <float>z, <float>b)
        if status != FusionAltitudeStatusOk:
            _observer_glue.raise_reset_error(status, z, b)

    def update_batch(self, accel, baro_altitude, dt, out=None):
        """Process arrays of samples, continuing from the current state.

        Parameters
        ----------
        accel : array_like
            Vertical acceleration per sample, m/s², earth frame, +up, gravity
            removed; 1-D, any real dtype and stride (converted to float32).
        baro_altitude : array_like
            Barometric altitude per sample, m; NaN where there is no sample.
        dt : float or array_like
            Sample period, s: one value for all samples or one per sample.
        out : AltitudeBatch or sequence of 4 arrays, optional
            Preallocated contiguous float32 arrays of the input's length for
            altitude, vertical_velocity, accel_bias and baro_residual.

        Returns
        -------
        AltitudeBatch
            The state after each sample (``out`` if given).

        Raises
        ------
        ValueError
            A bad sample (as for :meth:`update`), naming the argument and its
            first bad index; nothing is applied to the state. ``out`` may hold
            the samples before the bad one.

        Notes
        -----
        Equal, bit for bit, to calling :meth:`update` for each sample. The loop
        runs with the GIL released.
        """
        accel32, baro32, dt32, dt_is_array, result = _observer_glue.prepare_batch(accel, baro_altitude, dt, out)
        _batch_into(&self._c, accel32, baro32, dt32, dt_is_array, result)  # the loop: _observer_fields.pxi
        return result if out is None else out  # out=: the caller's object itself

    @property
    def settings(self):
        """The gains; assign new :class:`AltitudeSettings` to retune without losing the state."""
        return AltitudeSettings(*_gains(_settings_from_c(&self._c.settings)))

    @settings.setter
    def settings(self, settings):
        cdef FusionAltitudeSettings c = _settings_to_c(AltitudeSettings.coerce(settings).as_dict())
        cdef FusionAltitudeStatus status = FusionAltitudeSetSettings(&self._c, &c)
        if status != FusionAltitudeStatusOk:
            _observer_glue.raise_settings_error(status, _gains(_settings_from_c(&c)))

    def __repr__(self):
        return (f"AltitudeEstimator(altitude={self.altitude!r}, vertical_velocity={self.vertical_velocity!r}, "
                f"accel_bias={self.accel_bias!r}, baro_residual={self.baro_residual!r}, settings={self.settings!r})")


_common.share_docstrings(AltitudeEstimator, _observer_glue.AltitudeContract)

