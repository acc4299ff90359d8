# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Cython binding of the observer in csrc/fusion_altitude.h.

This module converts and checks Python arguments, calls the C functions and
raises for the statuses they return. It holds no copy of the algorithm.
"""

from fusion_altitude._convert cimport as_double as _as_double

from fusion_altitude.cfusion_altitude cimport *


from fusion_altitude import _common, _observer_glue
from fusion_altitude._observer_glue import AltitudeBatch

GRAVITY = _common.GRAVITY

#: The C enum values, for checking that :class:`fusion_altitude.Status` matches.
C_STATUS_VALUES = {
    "OK": FusionAltitudeStatusOk,
    "INVALID_ACCEL": FusionAltitudeStatusInvalidAccel,
    "INVALID_BARO_ALTITUDE": FusionAltitudeStatusInvalidBaroAltitude,
    "INVALID_DT": FusionAltitudeStatusInvalidDt,
    "INVALID_ACCEL_BIAS": FusionAltitudeStatusInvalidAccelBias,
    "INVALID_GAIN": FusionAltitudeStatusInvalidGain,
    "UNSTABLE_GAINS": FusionAltitudeStatusUnstableGains,
    "UNSTABLE_DISCRETE": FusionAltitudeStatusUnstableDiscrete,
    "INVALID_BANDWIDTH": FusionAltitudeStatusInvalidBandwidth,
    "INVALID_PRESET": FusionAltitudeStatusInvalidPreset,
    "INVALID_GAP_PERIOD": FusionAltitudeStatusInvalidGapPeriod,
}
C_GRAVITY = FUSION_ALTITUDE_GRAVITY
C_VERSION = FUSION_ALTITUDE_VERSION


def status_message(int status):
    """The C header's message for a status code (FusionAltitudeStatusMessage)."""
    return FusionAltitudeStatusMessage(<FusionAltitudeStatus>status).decode("ascii")


cdef class AltitudeSettings:
    """Observer gains (float32).

    Parameters
    ----------
    position_gain : float, default 2.40
        Kh, 1/s: baro residual into altitude.
    velocity_gain : float, default 2.88
        Kv, 1/s²: baro residual into vertical velocity.
    bias_gain : float, default 0.675
        Kb, 1/s³: baro residual into the accel bias; 0 disables bias estimation.
    gap_period : float, default 0.5
        s: an update whose dt exceeds this is a gap, not integrated; ``inf``
        never detects a gap.

    Raises
    ------
    ValueError
        A gain is not finite or negative, the observer is unstable
        (Routh–Hurwitz: Kh·Kv > Kb when Kb > 0; Kh > 0 when Kv > 0), or
        gap_period is NaN or <= 0.

    Notes
    -----
    The gains set the observer's characteristic polynomial
    s³ + Kh·s² + Kv·s + Kb. Prefer :meth:`from_bandwidth` or :meth:`preset`.
    """

    cdef FusionAltitudeSettings _c

    def __init__(self, position_gain=2.40, velocity_gain=2.88, bias_gain=0.675, gap_period=0.5):
        self._c.positionGain = <float>_as_double(position_gain, "position_gain")
        self._c.velocityGain = <float>_as_double(velocity_gain, "velocity_gain")
        self._c.biasGain = <float>_as_double(bias_gain, "bias_gain")
        self._c.gapPeriod = <float>_as_double(gap_period, "gap_period")
        cdef FusionAltitudeStatus status = FusionAltitudeSettingsCheck(&self._c)
        if status != FusionAltitudeStatusOk:
            _observer_glue.raise_settings_error(status, self.as_tuple())

    @staticmethod
    cdef AltitudeSettings _wrap(FusionAltitudeSettings c):
        cdef AltitudeSettings settings = AltitudeSettings.__new__(AltitudeSettings)
        settings._c = c
        return settings

    @classmethod
    def from_bandwidth(cls, omega, zeta=0.7, omega_b=None, gap_period=0.5):
        """Gains from position-loop bandwidth ω (rad/s), damping ζ and bias-loop bandwidth ω_b (rad/s).

        ``Kh = 2ζω + ω_b`` (1/s), ``Kv = ω² + 2ζω·ω_b`` (1/s²), ``Kb = ω²·ω_b``
        (1/s³), evaluated in float32; ``omega_b`` defaults to ``float32(ω) / 5``.

        Raises
        ------
        ValueError
            ω or ζ not finite and > 0, ω_b not finite and >= 0.
        """
        cdef float w = <float>_as_double(omega, "omega")
        cdef float z = <float>_as_double(zeta, "zeta")
        cdef float wb = w / 5.0 if omega_b is None else <float>_as_double(omega_b, "omega_b")
        cdef float period = <float>_as_double(gap_period, "gap_period")
        cdef FusionAltitudeSettings c
        cdef FusionAltitudeStatus status = FusionAltitudeSettingsFromBandwidth(&c, w, z, wb)
        if status != FusionAltitudeStatusOk:
            _observer_glue.raise_settings_error(status, (w, z, wb))
        c.gapPeriod = period
        status = FusionAltitudeSettingsCheck(&c)
        if status != FusionAltitudeStatusOk:
            _observer_glue.raise_settings_error(status, (w, z, wb))
        return AltitudeSettings._wrap(c)

    @classmethod
    def preset(cls, name):
        """Preset gains (ζ = 0.7, ω_b = ω/5, exact formulas rounded to float32).

        ``balloon`` (ω 0.2 rad/s), ``fixed_wing`` (0.5), ``vtol`` (1.5, the
        default), ``racing`` (5.0).
        """
        cdef FusionAltitudeSettings c
        cdef int index = _observer_glue.check_preset(name)
        FusionAltitudeSettingsFromPreset(&c, <FusionAltitudePreset>index)
        return AltitudeSettings._wrap(c)

    @property
    def position_gain(self):
        """Kh, 1/s."""
        return self._c.positionGain

    @property
    def velocity_gain(self):
        """Kv, 1/s²."""
        return self._c.velocityGain

    @property
    def bias_gain(self):
        """Kb, 1/s³."""
        return self._c.biasGain

    @property
    def gap_period(self):
        """s: an update whose dt exceeds this is a gap, not integrated."""
        return self._c.gapPeriod

    def validate(self, dt):
        """Check that the update is stable at sample period ``dt`` (s) (Jury's test).

        Raises
        ------
        ValueError
            The discrete update diverges at this dt, or dt is not finite and > 0.

        Warns
        -----
        DiscretisationWarning
            The fastest observer pole ω has ω·dt ≥ 0.1 (advice, not an error).
        """
        cdef float t = <float>_as_double(dt, "dt")
        cdef FusionAltitudeStatus status = FusionAltitudeSettingsValidate(&self._c, t)
        if status != FusionAltitudeStatusOk:
            _observer_glue.raise_settings_error(status, self.as_tuple(), dt)
        _observer_glue.warn_if_coarse(self.as_tuple(), t)

    def as_tuple(self):
        """(position_gain, velocity_gain, bias_gain) as Python floats."""
        return (self._c.positionGain, self._c.velocityGain, self._c.biasGain)

    def __eq__(self, other):
        if not hasattr(other, "as_tuple") or not hasattr(other, "velocity_gain"):
            return NotImplemented
        return self.as_tuple() == other.as_tuple() and self.gap_period == getattr(other, "gap_period", 0.5)

    def __hash__(self):
        return hash((self.as_tuple(), self.gap_period))

    def __repr__(self):
        import numpy as np
        kh, kv, kb = (str(np.float32(g)) for g in self.as_tuple())
        return (f"AltitudeSettings(position_gain={kh}, velocity_gain={kv}, bias_gain={kb}, "
                f"gap_period={np.float32(self.gap_period)})")

    def __reduce__(self):
        return (AltitudeSettings, (*self.as_tuple(), self.gap_period))


cdef AltitudeSettings _as_settings(object settings):
    if isinstance(settings, AltitudeSettings):
        return settings
    if hasattr(settings, "as_tuple"):
        return AltitudeSettings(*settings.as_tuple(), gap_period=getattr(settings, "gap_period", 0.5))
    raise TypeError(f"settings must be AltitudeSettings, got {type(settings).__name__}")


cdef Py_ssize_t _run(FusionAltitude *state, const float *accel, const float *baro, const float *dt,
                     Py_ssize_t dt_step, Py_ssize_t n, float *altitude, float *velocity, float *bias,
                     float *residual) noexcept nogil:
    """Run n updates on a private copy of *state; commit it only if all succeed.

    Returns the index of the first rejected sample, or -1.
    """
    cdef FusionAltitude local = state[0]
    cdef Py_ssize_t i
    for i in range(n):
        if FusionAltitudeUpdate(&local, accel[i], baro[i], dt[i * dt_step]) != FusionAltitudeStatusOk:
            return i
        altitude[i] = local.altitude
        velocity[i] = local.verticalVelocity
        bias[i] = local.accelBias
        residual[i] = local.baroResidual
    state[0] = local
    return -1


cdef class AltitudeEstimator:
    """3rd-order complementary observer: baro altitude + vertical acceleration.

    Estimates altitude (m), vertical velocity (m/s, +up) and the
    accelerometer's vertical bias (m/s², +up).

    Parameters
    ----------
    settings : AltitudeSettings, optional
        Gains; the defaults (VTOL multirotor) if omitted.

    Notes
    -----
    Inputs: vertical acceleration (m/s², earth frame, +up, gravity removed),
    baro altitude (m; NaN for "no baro this step") and dt (s). The first baro
    sample sets the reference (auto-zero). NED users negate. Copies and
    pickles carry the full state, so a run can be checkpointed and resumed.
    """

    cdef FusionAltitude _c

    def __init__(self, settings=None):
        FusionAltitudeInitialise(&self._c)
        if settings is not None:
            self.settings = settings

    def update(self, accel, baro_altitude, dt):
        """Process one sample.

        Parameters
        ----------
        accel : float
            Vertical acceleration, m/s², earth frame, +up, gravity removed.
        baro_altitude : float
            Barometric altitude, m; NaN when no baro sample arrived this step
            (the filter then integrates the acceleration only).
        dt : float
            Time since the previous sample, s.

        Raises
        ------
        ValueError
            accel not finite, baro_altitude infinite, dt not finite or <= 0;
            the state is unchanged.
        """
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
        cdef double b
        cdef FusionAltitudeStatus status
        if accel_bias is None:
            status = FusionAltitudeReset(&self._c, <float>z)
            b = 0.0
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
        cdef const float[::1] a = accel32
        cdef const float[::1] z = baro32
        cdef const float[::1] t = dt32
        cdef float[::1] h = result.altitude
        cdef float[::1] v = result.vertical_velocity
        cdef float[::1] b = result.accel_bias
        cdef float[::1] r = result.baro_residual
        cdef Py_ssize_t n = a.shape[0]
        cdef Py_ssize_t dt_step = 1 if dt_is_array else 0
        cdef Py_ssize_t bad = -1
        if n == 0:
            return result
        with nogil:
            bad = _run(&self._c, &a[0], &z[0], &t[0], dt_step, n, &h[0], &v[0], &b[0], &r[0])
        if bad >= 0:
            _observer_glue.raise_update_error(FusionAltitudeCheckInputs(a[bad], z[bad], t[bad * dt_step]),
                                       a[bad], z[bad], t[bad * dt_step], bad, dt_is_array)
        return result

    @property
    def altitude(self):
        """Altitude estimate h, m (0 until the reference is set)."""
        return FusionAltitudeGetAltitude(&self._c)

    @property
    def vertical_velocity(self):
        """Vertical velocity estimate v, m/s, +up."""
        return FusionAltitudeGetVerticalVelocity(&self._c)

    @property
    def accel_bias(self):
        """Accelerometer bias estimate b, m/s², +up (subtracted from the input)."""
        return FusionAltitudeGetAccelBias(&self._c)

    @property
    def baro_residual(self):
        """Baro residual z − h of the last update before its correction, m (0 after reset, NaN without baro)."""
        return FusionAltitudeGetBaroResidual(&self._c)

    @property
    def reference_set(self):
        """Whether the reference is set (first baro sample or reset); False again from a gap to the next baro sample."""
        return FusionAltitudeIsReferenceSet(&self._c)

    @property
    def gap_count(self):
        """Number of gaps so far: updates whose dt exceeded ``settings.gap_period`` once the reference was set."""
        return FusionAltitudeGetGapCount(&self._c)

    @property
    def settings(self):
        """The gains; assign new :class:`AltitudeSettings` to retune without losing the state."""
        return AltitudeSettings._wrap(FusionAltitudeGetSettings(&self._c))

    @settings.setter
    def settings(self, settings):
        cdef AltitudeSettings checked = _as_settings(settings)
        cdef FusionAltitudeStatus status = FusionAltitudeSetSettings(&self._c, &checked._c)
        if status != FusionAltitudeStatusOk:
            _observer_glue.raise_settings_error(status, checked.as_tuple())

    def _get_state(self):
        return ((*self.settings.as_tuple(), self._c.settings.gapPeriod), self._c.altitude, self._c.verticalVelocity,
                self._c.accelBias, self._c.baroResidual, bool(self._c.referenceSet), self._c.gapTime,
                self._c.gapCount, self._c.sinceRestart)

    def _set_state(self, state):
        gains, h, v, b, r, reference_set = state[:6]
        gap_time, gap_count, since_restart = state[6:] if len(state) > 6 else (0.0, 0, -1.0)
        cdef AltitudeSettings settings = AltitudeSettings(*gains)
        self._c.settings = settings._c
        self._c.altitude = h
        self._c.verticalVelocity = v
        self._c.accelBias = b
        self._c.baroResidual = r
        self._c.referenceSet = bool(reference_set)
        self._c.gapTime = gap_time
        self._c.gapCount = gap_count
        self._c.sinceRestart = since_restart

    def __copy__(self):
        cdef AltitudeEstimator clone = AltitudeEstimator.__new__(AltitudeEstimator)
        clone._c = self._c
        return clone

    def __deepcopy__(self, memo):
        return self.__copy__()

    def __reduce__(self):
        return (_restore, (self._get_state(),))

    def __repr__(self):
        return (f"AltitudeEstimator(altitude={self.altitude!r}, vertical_velocity={self.vertical_velocity!r}, "
                f"accel_bias={self.accel_bias!r}, baro_residual={self.baro_residual!r}, settings={self.settings!r})")


def _restore(state):
    cdef AltitudeEstimator estimator = AltitudeEstimator.__new__(AltitudeEstimator)
    estimator._set_state(state)
    return estimator
