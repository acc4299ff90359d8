# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Cython binding of the two-stage complementary filter in csrc/fusion_altitude_complementary.h.

This module converts and checks Python arguments, calls the C functions and
raises for the statuses they return. It holds no copy of the algorithm.
"""

from fusion_altitude._convert cimport as_double as _as_double

from fusion_altitude.ccomplementary cimport *

from fusion_altitude import _complementary_glue, _observer_glue
from fusion_altitude._complementary_glue import ComplementaryBatch

#: The C enum values, for checking that :class:`ComplementaryStatus` matches.
C_STATUS_VALUES = {
    "OK": FusionAltitudeComplementaryStatusOk,
    "INVALID_ACCEL": FusionAltitudeComplementaryStatusInvalidAccel,
    "INVALID_BARO_ALTITUDE": FusionAltitudeComplementaryStatusInvalidBaroAltitude,
    "INVALID_DT": FusionAltitudeComplementaryStatusInvalidDt,
    "INVALID_TIME_CONSTANT": FusionAltitudeComplementaryStatusInvalidTimeConstant,
    "INVALID_COEFFICIENT": FusionAltitudeComplementaryStatusInvalidCoefficient,
    "INVALID_GAP_PERIOD": FusionAltitudeComplementaryStatusInvalidGapPeriod,
}


def c_default_settings():
    """The header's FusionAltitudeComplementarySettingsDefault() as a dict."""
    cdef FusionAltitudeComplementarySettings c = FusionAltitudeComplementarySettingsDefault()
    return _settings_to_dict(&c)


def status_message(int status):
    """The C header's message for a status code."""
    return FusionAltitudeComplementaryStatusMessage(<FusionAltitudeComplementaryStatus>status).decode("ascii")


cdef dict _settings_to_dict(const FusionAltitudeComplementarySettings *c):
    return {
        "accel_time_constant": c.accelTimeConstant,
        "baro_time_constant": c.baroTimeConstant,
        "per_sample_coefficients": bool(c.perSampleCoefficients),
        "velocity_coefficient": c.velocityCoefficient,
        "altitude_coefficient": c.altitudeCoefficient,
        "velocity_time_constant": c.velocityTimeConstant,
        "altitude_time_constant": c.altitudeTimeConstant,
        "gap_period": c.gapPeriod,
    }


cdef class ComplementarySettings:
    """Settings of the two-stage complementary filter (float32).

    Parameters
    ----------
    accel_time_constant : float, default 0.02
        τ_a, s (>= 0): accel low-pass ``y += dt/(τ+dt)·(x − y)``; 0 disables it.
    baro_time_constant : float, default 0.05
        τ_b, s (>= 0): baro low-pass; 0 disables it.
    velocity_time_constant : float, default 9.99
        T_v, s: velocity blend coefficient c_v = T_v/(T_v + D), D the time
        since the previous baro sample (0.999 at 100 Hz).
    altitude_time_constant : float, default 4.99
        T_h, s: altitude blend coefficient c_h = T_h/(T_h + D) (0.998 at 100 Hz).
    per_sample_coefficients : bool, default False
        True: use ``velocity_coefficient`` and ``altitude_coefficient`` as the
        fixed per-baro-sample coefficients of the write-up instead (prefer
        :meth:`from_coefficients`).
    velocity_coefficient, altitude_coefficient : float, default 0.999, 0.998
        c_v, c_h in [0, 1] (used when ``per_sample_coefficients``).
    gap_period : float, default 0.5
        s: an update whose dt exceeds this is a gap, not integrated: the
        filter restarts from the next baro sample; ``inf`` never detects one.

    Notes
    -----
    The time constants are the default because they make the filter behave
    the same at any loop or baro rate; the write-up's fixed coefficients are
    tied to the rate it ran at (0.999 per sample is T_v = 10 s at 100 Hz but
    1 s at 10 Hz). At 100 Hz the defaults equal the write-up's numbers.

    Raises
    ------
    ValueError
        A time constant not finite or negative, or a coefficient outside [0, 1].
    """

    cdef FusionAltitudeComplementarySettings _c

    def __init__(self, **kwargs):
        v = _complementary_glue.convert_complementary_settings(kwargs)
        self._c.accelTimeConstant = v["accel_time_constant"]
        self._c.baroTimeConstant = v["baro_time_constant"]
        self._c.perSampleCoefficients = v["per_sample_coefficients"]
        self._c.velocityCoefficient = v["velocity_coefficient"]
        self._c.altitudeCoefficient = v["altitude_coefficient"]
        self._c.velocityTimeConstant = v["velocity_time_constant"]
        self._c.altitudeTimeConstant = v["altitude_time_constant"]
        self._c.gapPeriod = v["gap_period"]
        cdef FusionAltitudeComplementaryStatus status = FusionAltitudeComplementarySettingsCheck(&self._c)
        if status != FusionAltitudeComplementaryStatusOk:
            _complementary_glue.raise_complementary_settings_error(status, self.as_dict())

    @classmethod
    def from_coefficients(cls, velocity_coefficient=0.999, altitude_coefficient=0.998, **kwargs):
        """The write-up's form: fixed blend coefficients per baro sample, c_v and c_h in [0, 1].

        Other keyword arguments (the low-pass time constants) as for the constructor.
        """
        return cls(per_sample_coefficients=True, velocity_coefficient=velocity_coefficient,
                   altitude_coefficient=altitude_coefficient, **kwargs)

    @classmethod
    def from_time_constants(cls, velocity_time_constant=9.99, altitude_time_constant=4.99, **kwargs):
        """Blend from time constants in s (the default form): same behaviour at any sample rate."""
        return cls(velocity_time_constant=velocity_time_constant, altitude_time_constant=altitude_time_constant,
                   **kwargs)

    @staticmethod
    cdef ComplementarySettings _wrap(FusionAltitudeComplementarySettings c):
        cdef ComplementarySettings settings = ComplementarySettings.__new__(ComplementarySettings)
        settings._c = c
        return settings

    def __getattr__(self, name):
        values = self.as_dict()
        if name in values:
            return values[name]
        raise AttributeError(f"'ComplementarySettings' object has no attribute {name!r}")

    def as_dict(self):
        """Every setting as a Python value, in the order of the C struct."""
        return _settings_to_dict(&self._c)

    def replace(self, **changes):
        """A copy with some settings changed."""
        return ComplementarySettings(**{**self.as_dict(), **changes})

    def __eq__(self, other):
        if not hasattr(other, "as_dict") or not hasattr(other, "per_sample_coefficients"):
            return NotImplemented
        return self.as_dict() == other.as_dict()

    def __hash__(self):
        return hash(tuple(self.as_dict().items()))

    def __repr__(self):
        return "ComplementarySettings(" + ", ".join(f"{k}={v!r}" for k, v in self.as_dict().items()) + ")"

    def __reduce__(self):
        return (_settings_from_dict, (self.as_dict(),))


def _settings_from_dict(values):
    return ComplementarySettings(**values)


cdef ComplementarySettings _as_settings(object settings):
    if isinstance(settings, ComplementarySettings):
        return settings
    if hasattr(settings, "as_dict") and hasattr(settings, "per_sample_coefficients"):
        return ComplementarySettings(**settings.as_dict())
    raise TypeError(f"settings must be ComplementarySettings, got {type(settings).__name__}")


cdef Py_ssize_t _run(FusionAltitudeComplementary *state, const float *accel, const float *baro, const float *dt,
                     Py_ssize_t dt_step, Py_ssize_t n, float *altitude, float *velocity, float *baro_filtered,
                     float *baro_velocity) noexcept nogil:
    """Run n updates on a private copy of *state; commit it only if all succeed.

    Returns the index of the first rejected sample, or -1.
    """
    cdef FusionAltitudeComplementary local = state[0]
    cdef Py_ssize_t i
    for i in range(n):
        if FusionAltitudeComplementaryUpdate(&local, accel[i], baro[i], dt[i * dt_step]) != FusionAltitudeComplementaryStatusOk:
            return i
        altitude[i] = local.altitude
        velocity[i] = local.verticalVelocity
        baro_filtered[i] = local.baroFiltered
        baro_velocity[i] = local.baroVelocity
    state[0] = local
    return -1


cdef class ComplementaryFilter:
    """The hobbyist two-stage complementary filter: baro altitude + vertical acceleration.

    Low-passes both signals, blends the integrated acceleration with a
    finite-difference baro velocity, then the predicted altitude with the baro
    altitude. It has no accelerometer-bias state: a constant bias b leaves an
    altitude error of b·T_v·T_h (5.9 m for 12 mg with the defaults).

    Parameters
    ----------
    settings : ComplementarySettings, optional
        Default: time constants T_v = 9.99 s, T_h = 4.99 s (the write-up's
        0.999 and 0.998 at 100 Hz).

    Notes
    -----
    Inputs as for :class:`fusion_altitude.AltitudeEstimator`: acceleration
    m/s² (+up, gravity removed), baro altitude m (NaN: no sample this step),
    dt s. The first baro sample sets the reference. Copies and pickles carry
    the full state.
    """

    cdef FusionAltitudeComplementary _c

    def __init__(self, settings=None):
        FusionAltitudeComplementaryInitialise(&self._c)
        if settings is not None:
            self.settings = settings

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
        """Process arrays of samples, continuing from the current state.

        Parameters
        ----------
        accel, baro_altitude : array_like
            1-D, per sample (m/s², m; NaN baro where there is no sample).
        dt : float or array_like
            Sample period, s: one value or one per sample.
        out : ComplementaryBatch or sequence of 4 arrays, optional
            Preallocated contiguous float32 arrays of the input's length.

        Returns
        -------
        ComplementaryBatch

        Raises
        ------
        ValueError
            A bad sample, naming the argument and its first bad index; nothing
            is applied to the state.

        Notes
        -----
        Equal, bit for bit, to calling :meth:`update` for each sample. The loop
        runs with the GIL released.
        """
        accel32, baro32, dt32, dt_is_array = _observer_glue.prepare_inputs(accel, baro_altitude, dt)
        result = _complementary_glue.complementary_outputs(accel32.shape[0], out)
        cdef const float[::1] a = accel32
        cdef const float[::1] z = baro32
        cdef const float[::1] t = dt32
        cdef float[::1] h = result.altitude
        cdef float[::1] v = result.vertical_velocity
        cdef float[::1] zf = result.baro_filtered
        cdef float[::1] vb = result.baro_velocity
        cdef Py_ssize_t n = a.shape[0]
        cdef Py_ssize_t dt_step = 1 if dt_is_array else 0
        cdef Py_ssize_t bad = -1
        if n == 0:
            return result
        with nogil:
            bad = _run(&self._c, &a[0], &z[0], &t[0], dt_step, n, &h[0], &v[0], &zf[0], &vb[0])
        if bad >= 0:
            _complementary_glue.raise_complementary_update_error(
                FusionAltitudeComplementaryCheckInputs(a[bad], z[bad], t[bad * dt_step]),
                a[bad], z[bad], t[bad * dt_step], bad, dt_is_array)
        return result

    @property
    def altitude(self):
        """Altitude estimate h, m (0 until the reference is set)."""
        return FusionAltitudeComplementaryGetAltitude(&self._c)

    @property
    def vertical_velocity(self):
        """Vertical velocity estimate v, m/s, +up."""
        return FusionAltitudeComplementaryGetVerticalVelocity(&self._c)

    @property
    def baro_filtered(self):
        """Low-passed baro altitude, m."""
        return FusionAltitudeComplementaryGetBaroFiltered(&self._c)

    @property
    def baro_velocity(self):
        """Finite-difference baro velocity of the latest step, m/s (NaN on a step without baro)."""
        return FusionAltitudeComplementaryGetBaroVelocity(&self._c)

    @property
    def reference_set(self):
        """Whether the reference is set (False from a gap to the next baro sample)."""
        return FusionAltitudeComplementaryIsReferenceSet(&self._c)

    @property
    def gap_count(self):
        """Number of gaps so far: updates whose dt exceeded ``settings.gap_period`` once the reference was set."""
        return FusionAltitudeComplementaryGetGapCount(&self._c)

    @property
    def settings(self):
        """The settings; assign new :class:`ComplementarySettings` to retune, keeping the state."""
        return ComplementarySettings._wrap(FusionAltitudeComplementaryGetSettings(&self._c))

    @settings.setter
    def settings(self, settings):
        cdef ComplementarySettings checked = _as_settings(settings)
        cdef FusionAltitudeComplementaryStatus status = FusionAltitudeComplementarySetSettings(&self._c, &checked._c)
        if status != FusionAltitudeComplementaryStatusOk:
            _complementary_glue.raise_complementary_settings_error(status, checked.as_dict())

    def _get_state(self):
        return (self.settings.as_dict(), self._c.altitude, self._c.verticalVelocity, self._c.accelFiltered,
                self._c.baroFiltered, self._c.baroVelocity, self._c.sinceBaro, bool(self._c.referenceSet),
                self._c.gapTime, self._c.gapCount)

    def _set_state(self, state):
        values, h, v, a, zf, vb, since, reference_set = state[:8]
        gap_time, gap_count = state[8:] if len(state) > 8 else (0.0, 0)
        cdef ComplementarySettings settings = ComplementarySettings(**values)
        self._c.settings = settings._c
        self._c.altitude = h
        self._c.verticalVelocity = v
        self._c.accelFiltered = a
        self._c.baroFiltered = zf
        self._c.baroVelocity = vb
        self._c.sinceBaro = since
        self._c.referenceSet = bool(reference_set)
        self._c.gapTime = gap_time
        self._c.gapCount = gap_count

    def __copy__(self):
        cdef ComplementaryFilter clone = ComplementaryFilter.__new__(ComplementaryFilter)
        clone._c = self._c
        return clone

    def __deepcopy__(self, memo):
        return self.__copy__()

    def __reduce__(self):
        return (_restore, (self._get_state(),))

    def __repr__(self):
        return (f"ComplementaryFilter(altitude={self.altitude!r}, vertical_velocity={self.vertical_velocity!r}, "
                f"settings={self.settings!r})")


def _restore(state):
    cdef ComplementaryFilter estimator = ComplementaryFilter.__new__(ComplementaryFilter)
    estimator._set_state(state)
    return estimator
