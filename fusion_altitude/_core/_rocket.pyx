# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Cython binding of the rocket estimator in csrc/fusion_altitude_rocket.h (``FlightEvents`` lives in ``_rocket_glue``): see ``_core/__init__.py`` for what a binding does."""

include "_rocket_fields.pxi"

from fusion_altitude._core._rocket_glue import BaroFate, FlightEvents, Phase, RocketBatch, RocketStatus

#: The C values, for checking that the Python constants match.
C_MACH_LOCKOUT = FUSION_ALTITUDE_ROCKET_MACH_LOCKOUT
C_NUMBER_OF_EVENTS = FUSION_ALTITUDE_ROCKET_NUMBER_OF_EVENTS

status_message = c_status_message


cdef class RocketEstimator(_RocketEstimatorGetters):
    __doc__ = DOC_RocketEstimator  # generated from the reference's docstring (_rocket_fields.pxi)

    def __init__(self, settings=None):
        settings = RocketSettings() if settings is None else RocketSettings.coerce(settings)
        cdef FusionAltitudeRocketSettings c = _settings_to_c(settings.as_dict())
        cdef FusionAltitudeRocketStatus status = FusionAltitudeRocketInitialise(&self._c, &c)
        if status != FusionAltitudeRocketStatusOk:  # cannot happen: RocketSettings checked them
            _rocket_glue.raise_settings_error(status, _settings_from_c(&c))

    def update(self, accel, baro_altitude, dt, *, accel_is_vertical=False):
        cdef double a = _as_double(accel, "accel")
        cdef double z = _as_double(baro_altitude, "baro_altitude")
        cdef double t = _as_double(dt, "dt")
        cdef FusionAltitudeRocketStatus status
        if accel_is_vertical:
            status = FusionAltitudeRocketUpdateWithVerticalAccel(&self._c, <float>a, <float>z, <float>t)
        else:
            status = FusionAltitudeRocketUpdate(&self._c, <float>a, <float>z, <float>t)
        if status != FusionAltitudeRocketStatusOk:
            _rocket_glue.raise_update_error(status, a, z, t)

    def update_batch(self, accel, baro_altitude, dt, *, accel_is_vertical=False, out=None):
        """Process arrays, continuing from the current state (GIL released).

        Parameters
        ----------
        accel, baro_altitude : array_like
            Per step, as for :meth:`update` (m/s², m; NaN = no baro); 1-D, any real dtype.
        dt : float or array_like
            s, one value or one per step.
        accel_is_vertical : bool, default False
            As for :meth:`update`, for every step.
        out : RocketBatch or sequence of 5 arrays, optional
            Preallocated contiguous arrays (float32 ×3, uint8 ×2) of the input's length.

        Returns
        -------
        RocketBatch
            Height, vertical velocity, accel bias, phase and baro fate after each step.

        Raises
        ------
        ValueError
            A bad step, naming the argument and its first bad index; nothing is
            applied to the state.

        Notes
        -----
        Equal, bit for bit, to calling :meth:`update` for each step and to the
        reference :class:`fusion_altitude.reference.rocket.RocketEstimator`.
        """
        accel32, baro32, dt32, dt_is_array, result = _rocket_glue.prepare_batch(accel, baro_altitude, dt, out)
        _batch_into(&self._c, accel32, baro32, dt32, dt_is_array, result, bool(accel_is_vertical))  # _rocket_fields.pxi
        return result if out is None else out  # out=: the caller's object itself

    @property
    def settings(self):
        """The :class:`RocketSettings` given at construction."""
        return RocketSettings(**_settings_from_c(&self._c.settings))

    @property
    def phase(self):
        """The current :class:`Phase`."""
        return Phase(<int>FusionAltitudeRocketGetPhase(&self._c))

    @property
    def baro(self):
        """:class:`BaroFate` of the latest step's baro sample."""
        return BaroFate(<int>FusionAltitudeRocketGetBaro(&self._c))

    @property
    def events(self):
        """:class:`FlightEvents` so far (time in s since initialise)."""
        cdef FusionAltitudeRocketEvent e
        rows = []
        for index in range(FUSION_ALTITUDE_ROCKET_NUMBER_OF_EVENTS):
            e = FusionAltitudeRocketGetEvent(&self._c, <FusionAltitudeRocketEventId>index)
            rows.append((e.occurred, e.sample, e.time, e.height, e.velocity))
        return _rocket_glue.events_from_tuples(rows)

    def __repr__(self):
        return (f"RocketEstimator(phase={self.phase.name}, height={self.height!r}, "
                f"vertical_velocity={self.vertical_velocity!r})")


_common.share_docstrings(RocketEstimator, _rocket_glue.RocketContract)


_rocket_glue.C_SETTINGS_FUNCTIONS.update(check=c_settings_check)
