# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Cython binding of the two-stage complementary filter in csrc/fusion_altitude_complementary.h: see ``_core/__init__.py`` for what a binding does."""

include "_complementary_fields.pxi"

from fusion_altitude._core._complementary_glue import ComplementaryBatch

status_message = c_status_message
_settings_error = _complementary_glue.raise_complementary_settings_error


cdef class ComplementaryFilter(_ComplementaryFilterGetters):
    __doc__ = DOC_ComplementaryFilter  # generated from the reference's docstring (_complementary_fields.pxi)

    def __init__(self, settings=None):
        self._initialise(settings)  # _complementary_fields.pxi

    def update(self, accel, baro_altitude, dt):
        """Process one sample: accel m/s², baro_altitude m (NaN: none), dt s.

        Raises
        ------
        ValueError
            accel not finite, baro_altitude infinite, dt not finite or <= 0;
            the state is unchanged.
        """
        cdef double a = _as_double(accel, "accel")
        cdef double z = _as_double(baro_altitude, "baro_altitude")
        cdef double t = _as_double(dt, "dt")
        cdef FusionAltitudeComplementaryStatus status = FusionAltitudeComplementaryUpdate(&self._c, <float>a, <float>z,
                                                                                          <float>t)
        if status != FusionAltitudeComplementaryStatusOk:
            _complementary_glue.raise_complementary_update_error(status, a, z, t)

    def reset(self, baro_altitude):
        """Set the reference: altitude = filtered baro = ``baro_altitude`` (m), velocities 0.

        Raises
        ------
        ValueError
            baro_altitude not finite; the state is unchanged.
        """
        cdef double z = _as_double(baro_altitude, "baro_altitude")
        if FusionAltitudeComplementaryReset(&self._c, <float>z) != FusionAltitudeComplementaryStatusOk:
            raise ValueError(f"baro_altitude must be finite (m), got {z!r}")

    def update_batch(self, accel, baro_altitude, dt, out=None):
        accel32, baro32, dt32, dt_is_array = _common.prepare_inputs(accel, baro_altitude, dt)
        result = _complementary_glue.complementary_outputs(accel32.shape[0], out)
        _batch_into(&self._c, accel32, baro32, dt32, dt_is_array, result)  # the loop: _complementary_fields.pxi
        return result if out is None else out  # out=: the caller's object itself

    def __repr__(self):
        return (f"ComplementaryFilter(altitude={self.altitude!r}, vertical_velocity={self.vertical_velocity!r}, "
                f"settings={self.settings!r})")


_common.share_docstrings(ComplementaryFilter, _complementary_glue.ComplementaryContract)  # update_batch


_complementary_glue.C_SETTINGS_FUNCTIONS.update(check=c_settings_check)
