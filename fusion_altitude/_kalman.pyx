# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Cython binding of the multi-sensor Kalman filter in csrc/fusion_altitude_kalman.h.

This module converts and checks Python arguments, calls the C functions and
raises for the statuses they return. It holds no copy of the algorithm.
"""

import math

from fusion_altitude._convert cimport as_double as _as_double
from libc.stdint cimport int32_t, uint8_t, uint32_t

from fusion_altitude.ckalman cimport *

import numpy as np

from fusion_altitude import _kalman_glue
from fusion_altitude._kalman_glue import KalmanBatch, KalmanResult, KalmanSensors, KalmanStatus

#: The C enum values, for checking that :class:`fusion_altitude.KalmanStatus` matches.
C_STATUS_VALUES = {
    "OK": FusionAltitudeKalmanStatusOk,
    "INVALID_ACCEL": FusionAltitudeKalmanStatusInvalidAccel,
    "INVALID_DT": FusionAltitudeKalmanStatusInvalidDt,
    "INVALID_BARO_ALTITUDE": FusionAltitudeKalmanStatusInvalidBaroAltitude,
    "INVALID_GPS_ALTITUDE": FusionAltitudeKalmanStatusInvalidGpsAltitude,
    "INVALID_GPS_ACCURACY": FusionAltitudeKalmanStatusInvalidGpsAccuracy,
    "INVALID_NOISE": FusionAltitudeKalmanStatusInvalidNoise,
    "INVALID_RANGE": FusionAltitudeKalmanStatusInvalidRange,
    "INVALID_GPS": FusionAltitudeKalmanStatusInvalidGps,
    "INVALID_GATE": FusionAltitudeKalmanStatusInvalidGate,
    "INVALID_GROUND_EFFECT": FusionAltitudeKalmanStatusInvalidGroundEffect,
    "INVALID_GAP_PERIOD": FusionAltitudeKalmanStatusInvalidGapPeriod,
}
C_RESULT_VALUES = {
    "NO_SAMPLE": FusionAltitudeKalmanResultNoSample,
    "FUSED": FusionAltitudeKalmanResultFused,
    "REJECTED": FusionAltitudeKalmanResultRejected,
    "RESET": FusionAltitudeKalmanResultReset,
    "INITIALISED": FusionAltitudeKalmanResultInitialised,
    "UNUSABLE": FusionAltitudeKalmanResultUnusable,
}


def c_default_settings():
    """FusionAltitudeKalmanSettingsDefault() as a dict, for checking the Python defaults against the header's."""
    cdef FusionAltitudeKalmanSettings c = FusionAltitudeKalmanSettingsDefault()
    return _settings_to_dict(&c)


def kalman_status_message(int status):
    """The C header's message for a status code (FusionAltitudeKalmanStatusMessage)."""
    return FusionAltitudeKalmanStatusMessage(<FusionAltitudeKalmanStatus>status).decode("ascii")


cdef FusionAltitudeKalmanSettings _settings_from_dict(dict v):
    cdef FusionAltitudeKalmanSettings c
    c.accelNoise = v["accel_noise"]
    c.accelBiasRandomWalk = v["accel_bias_random_walk"]
    c.accelBiasInitialSigma = v["accel_bias_initial_sigma"]
    c.estimateAccelBias = v["estimate_accel_bias"]
    c.baroNoise = v["baro_noise"]
    c.baroOffsetRandomWalk = v["baro_offset_random_walk"]
    c.rangeNoise = v["range_noise"]
    c.rangeMinimum = v["range_min"]
    c.rangeMaximum = v["range_max"]
    c.gpsNoiseBase = v["gps_noise_base"]
    c.gpsNoiseSatellite = v["gps_noise_satellite"]
    c.gpsMinimumSatellites = v["gps_min_satellites"]
    c.gpsOffsetRandomWalk = v["gps_offset_random_walk"]
    c.gate = v["gate"]
    c.rejectionTimeout = v["rejection_timeout"]
    c.groundEffectNoiseScale = v["ground_effect_noise_scale"]
    c.groundEffectDeadZone = v["ground_effect_dead_zone"]
    c.initialHeightSigma = v["initial_height_sigma"]
    c.initialVelocitySigma = v["initial_velocity_sigma"]
    c.gapPeriod = v["gap_period"]
    return c


cdef dict _settings_to_dict(const FusionAltitudeKalmanSettings *c):
    return {
        "accel_noise": c.accelNoise,
        "accel_bias_random_walk": c.accelBiasRandomWalk,
        "accel_bias_initial_sigma": c.accelBiasInitialSigma,
        "estimate_accel_bias": bool(c.estimateAccelBias),
        "baro_noise": c.baroNoise,
        "baro_offset_random_walk": c.baroOffsetRandomWalk,
        "range_noise": c.rangeNoise,
        "range_min": c.rangeMinimum,
        "range_max": c.rangeMaximum,
        "gps_noise_base": c.gpsNoiseBase,
        "gps_noise_satellite": c.gpsNoiseSatellite,
        "gps_min_satellites": int(c.gpsMinimumSatellites),
        "gps_offset_random_walk": c.gpsOffsetRandomWalk,
        "gate": c.gate,
        "rejection_timeout": c.rejectionTimeout,
        "ground_effect_noise_scale": c.groundEffectNoiseScale,
        "ground_effect_dead_zone": c.groundEffectDeadZone,
        "initial_height_sigma": c.initialHeightSigma,
        "initial_velocity_sigma": c.initialVelocitySigma,
        "gap_period": c.gapPeriod,
    }


cdef class KalmanSettings:
    """Settings of the Kalman filter, in physical units (float32). Keyword arguments only.

    Parameters (defaults for a multirotor)
    --------------------------------------
    accel_noise : 0.035 m/s²/√Hz
        Accelerometer white-noise density N_a, vibration included.
    accel_bias_random_walk : 0.003 m/s³/√Hz
        Accelerometer bias random walk N_b.
    accel_bias_initial_sigma : 0.2 m/s²
        Initial bias uncertainty.
    estimate_accel_bias : True
        False holds the bias state at 0.
    baro_noise : 0.5 m
        Baro 1σ per sample (> 0).
    baro_offset_random_walk : 0.05 m/√s
        Baro offset drift N_ob (weather, temperature).
    range_noise : 0.05 m
        Rangefinder 1σ per sample (> 0).
    range_min, range_max : 0.1 m, 8.0 m
        Readings outside are "no echo" (not fused).
    gps_noise_base, gps_noise_satellite : 1.0 m, 1.0 m
        GPS σ = base + satellite/√n for n satellites.
    gps_min_satellites : 4
        Fewer satellites: GPS not fused.
    gps_offset_random_walk : 0.1 m/√s
        GPS altitude wander N_og.
    gate : 5.0 σ
        A sample is rejected if y²/S > gate².
    rejection_timeout : 1.0 s
        A sensor rejected for longer is reset (offset; rangefinder: ground).
    ground_effect_noise_scale : 3.0
        Baro σ multiplier with the ground-effect flag (>= 1).
    ground_effect_dead_zone : 0.5 m
        Negative baro innovations up to this are ignored in ground effect.
    initial_height_sigma, initial_velocity_sigma : 0.1 m, 1.0 m/s
        Initial uncertainty of "on the ground, at rest".
    gap_period : 0.5 s
        An update whose dt exceeds this is a gap: no prediction, the height
        and velocity variances are inflated instead so the next samples are
        accepted; ``inf`` never detects one.

    Raises
    ------
    ValueError
        A setting out of range, naming it. TypeError for an unknown name.
    """

    cdef FusionAltitudeKalmanSettings _c

    def __init__(self, **kwargs):
        values = _kalman_glue.convert_kalman_settings(kwargs)
        self._c = _settings_from_dict(values)
        cdef FusionAltitudeKalmanStatus status = FusionAltitudeKalmanSettingsCheck(&self._c)
        if status != FusionAltitudeKalmanStatusOk:
            _kalman_glue.raise_kalman_settings_error(status, values)

    @staticmethod
    cdef KalmanSettings _wrap(FusionAltitudeKalmanSettings c):
        cdef KalmanSettings settings = KalmanSettings.__new__(KalmanSettings)
        settings._c = c
        return settings

    def __getattr__(self, name):
        values = _settings_to_dict(&self._c)
        try:
            return values[name]
        except KeyError:
            raise AttributeError(name) from None

    def as_dict(self):
        """All settings as {name: value}, in the C struct's order."""
        return _settings_to_dict(&self._c)

    def replace(self, **changes):
        """A copy with some settings changed."""
        return KalmanSettings(**{**self.as_dict(), **changes})

    def __eq__(self, other):
        if not hasattr(other, "as_dict") or not hasattr(other, "gps_min_satellites"):
            return NotImplemented
        return self.as_dict() == other.as_dict()

    def __hash__(self):
        return hash(tuple(self.as_dict().items()))

    def __repr__(self):
        inner = ", ".join(f"{k}={v!r}" for k, v in self.as_dict().items())
        return f"KalmanSettings({inner})"

    def __reduce__(self):
        return (_settings_from_kwargs, (self.as_dict(),))


def _settings_from_kwargs(values):
    return KalmanSettings(**values)


cdef KalmanSettings _as_settings(object settings):
    if isinstance(settings, KalmanSettings):
        return settings
    if hasattr(settings, "as_dict") and hasattr(settings, "gps_min_satellites"):
        return KalmanSettings(**settings.as_dict())
    raise TypeError(f"settings must be KalmanSettings, got {type(settings).__name__}")


cdef Py_ssize_t _run(FusionAltitudeKalman *state, Py_ssize_t n,
                     const float *accel, Py_ssize_t sa, const float *dt, Py_ssize_t sd,
                     const float *baro, Py_ssize_t sb, const float *rng, Py_ssize_t sr,
                     const float *gps, Py_ssize_t sg, const float *acc, Py_ssize_t sacc,
                     const int32_t *sats, Py_ssize_t ss, const uint8_t *ground, Py_ssize_t se,
                     float *h, float *alt, float *v, float *b, float *ob, float *og,
                     float *diag, float *innovation, float *nis, uint8_t *result) noexcept nogil:
    """Run n steps on a private copy of *state; commit it only if all succeed.

    Returns the index of the first rejected step, or -1.
    """
    cdef FusionAltitudeKalman local = state[0]
    cdef FusionAltitudeKalmanMeasurements m
    cdef Py_ssize_t i
    cdef int j
    for i in range(n):
        m.baroAltitude = baro[i * sb]
        m.rangeDistance = rng[i * sr]
        m.gpsAltitude = gps[i * sg]
        m.gpsVerticalAccuracy = acc[i * sacc]
        m.gpsSatellites = sats[i * ss]
        m.groundEffect = ground[i * se] != 0
        if FusionAltitudeKalmanUpdate(&local, accel[i * sa], dt[i * sd], &m) != FusionAltitudeKalmanStatusOk:
            return i
        h[i] = local.x[0]
        alt[i] = FusionAltitudeKalmanGetAltitude(&local)
        v[i] = local.x[1]
        b[i] = local.x[4]
        ob[i] = local.x[2]
        og[i] = local.x[3]
        for j in range(5):
            diag[i * 5 + j] = local.P[j][j]
        for j in range(3):
            innovation[i * 3 + j] = local.sensors[j].innovation
            nis[i * 3 + j] = local.sensors[j].nis
            result[i * 3 + j] = <uint8_t>local.sensors[j].result
    state[0] = local
    return -1


cdef class KalmanEstimator:
    """Multi-sensor altitude Kalman filter: baro, rangefinder and GPS altitude with vertical acceleration.

    Estimates height above ground (m), baro-referenced altitude (m), vertical
    velocity (m/s, +up), the accelerometer's vertical bias (m/s², +up) and the
    baro and GPS offsets to the ground (m).

    Parameters
    ----------
    settings : KalmanSettings, optional
        The defaults if omitted.

    Notes
    -----
    Starts on the ground at rest with unknown baro and GPS offsets; each
    sensor's first sample sets its offset (no start-up phase). ``altitude``
    is h + baro_offset: what a noise-free baro would read, comparable to
    :class:`AltitudeEstimator`'s altitude. Copies and pickles carry the full
    state.
    """

    cdef FusionAltitudeKalman _c

    def __init__(self, settings=None):
        cdef KalmanSettings checked
        if settings is None:
            FusionAltitudeKalmanInitialise(&self._c)
        else:
            checked = _as_settings(settings)
            FusionAltitudeKalmanInitialiseWith(&self._c, &checked._c)

    def update(self, accel, dt, baro_altitude=math.nan, range_distance=math.nan, gps_altitude=math.nan,
               gps_satellites=None, gps_vertical_accuracy=None, ground_effect=False):
        """Process one step: predict with ``accel`` over ``dt``, then fuse the samples given.

        Parameters
        ----------
        accel : float
            Vertical acceleration, m/s², earth frame, +up, gravity removed.
        dt : float
            Time since the previous step, s.
        baro_altitude, range_distance, gps_altitude : float, optional
            Samples, m; NaN (the default) when a sensor has none this step. A
            range outside [range_min, range_max] (or ±inf) counts as no echo.
        gps_satellites : int, optional
            Satellites used; None: unknown (the GPS model then assumes
            ``gps_min_satellites``). Fewer than ``gps_min_satellites``: not fused.
        gps_vertical_accuracy : float, optional
            Receiver-reported 1σ vertical accuracy, m; used instead of the
            satellite model when given.
        ground_effect : bool
            Take-off or landing: widen the baro noise and ignore negative baro
            innovations up to the dead zone.

        Raises
        ------
        ValueError
            accel not finite, dt not finite or <= 0, baro or GPS altitude
            infinite, a GPS accuracy (with a GPS sample) not finite and > 0;
            the state is unchanged.
        """
        cdef FusionAltitudeKalmanMeasurements m
        cdef double a = _as_double(accel, "accel")
        cdef double t = _as_double(dt, "dt")
        m.baroAltitude = <float>_as_double(baro_altitude, "baro_altitude")
        m.rangeDistance = <float>_as_double(range_distance, "range_distance")
        m.gpsAltitude = <float>_as_double(gps_altitude, "gps_altitude")
        m.gpsVerticalAccuracy = math.nan if gps_vertical_accuracy is None else \
            <float>_as_double(gps_vertical_accuracy, "gps_vertical_accuracy")
        m.gpsSatellites = _kalman_glue.kalman_satellites(gps_satellites)
        m.groundEffect = bool(ground_effect)
        cdef FusionAltitudeKalmanStatus status = FusionAltitudeKalmanUpdate(&self._c, <float>a, <float>t, &m)
        if status != FusionAltitudeKalmanStatusOk:
            _kalman_glue.raise_kalman_update_error(status, {
                "accel": accel, "dt": dt, "baro_altitude": baro_altitude, "gps_altitude": gps_altitude,
                "gps_vertical_accuracy": gps_vertical_accuracy})

    def update_batch(self, accel, dt, baro_altitude=None, range_distance=None, gps_altitude=None,
                     gps_satellites=None, gps_vertical_accuracy=None, ground_effect=None, out=None):
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
        n, inputs, steps, result = _kalman_glue.prepare_kalman_batch(
            accel, dt, baro_altitude, range_distance, gps_altitude, gps_satellites, gps_vertical_accuracy,
            ground_effect, out)
        cdef const float[::1] a = inputs["accel"]
        cdef const float[::1] t = inputs["dt"]
        cdef const float[::1] zb = inputs["baro_altitude"]
        cdef const float[::1] zr = inputs["range_distance"]
        cdef const float[::1] zg = inputs["gps_altitude"]
        cdef const float[::1] acc = inputs["gps_vertical_accuracy"]
        cdef const int32_t[::1] sats = inputs["gps_satellites"]
        cdef const uint8_t[::1] ground = inputs["ground_effect"]
        cdef float[::1] h = result.height_above_ground
        cdef float[::1] alt = result.altitude
        cdef float[::1] v = result.vertical_velocity
        cdef float[::1] b = result.accel_bias
        cdef float[::1] ob = result.baro_offset
        cdef float[::1] og = result.gps_offset
        cdef float[:, ::1] diag = result.covariance_diagonal
        cdef float[:, ::1] innovation = result.innovation
        cdef float[:, ::1] nis = result.nis
        cdef uint8_t[:, ::1] codes = result.result
        cdef Py_ssize_t count = n
        cdef Py_ssize_t bad = -1
        cdef Py_ssize_t sa = steps["accel"], sd = steps["dt"], sb = steps["baro_altitude"]
        cdef Py_ssize_t sr = steps["range_distance"], sg = steps["gps_altitude"]
        cdef Py_ssize_t sacc = steps["gps_vertical_accuracy"], ss = steps["gps_satellites"]
        cdef Py_ssize_t se = steps["ground_effect"]
        if count == 0:
            return result
        with nogil:
            bad = _run(&self._c, count, &a[0], sa, &t[0], sd, &zb[0], sb, &zr[0], sr, &zg[0], sg, &acc[0], sacc,
                       &sats[0], ss, &ground[0], se, &h[0], &alt[0], &v[0], &b[0], &ob[0], &og[0],
                       &diag[0, 0], &innovation[0, 0], &nis[0, 0], &codes[0, 0])
        if bad >= 0:
            status = self._rejection(a[bad * sa], t[bad * sd], zb[bad * sb], zr[bad * sr], zg[bad * sg],
                                     acc[bad * sacc], sats[bad * ss], ground[bad * se])
            values = {"accel": float(a[bad * sa]), "dt": float(t[bad * sd]), "baro_altitude": float(zb[bad * sb]),
                      "gps_altitude": float(zg[bad * sg]), "gps_vertical_accuracy": float(acc[bad * sacc])}
            _kalman_glue.raise_kalman_update_error(status, values, bad, {k: bool(s) for k, s in steps.items()})
        return result

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
    def height_above_ground(self):
        """Height above ground h, m."""
        return FusionAltitudeKalmanGetHeightAboveGround(&self._c)

    @property
    def altitude(self):
        """Baro-referenced altitude h + baro_offset, m (equals h before the first baro sample)."""
        return FusionAltitudeKalmanGetAltitude(&self._c)

    @property
    def altitude_variance(self):
        """Variance of the altitude, m²: P_hh + 2·P_h,ob + P_ob,ob."""
        return FusionAltitudeKalmanGetAltitudeVariance(&self._c)

    @property
    def vertical_velocity(self):
        """Vertical velocity v, m/s, +up."""
        return FusionAltitudeKalmanGetVerticalVelocity(&self._c)

    @property
    def accel_bias(self):
        """Accelerometer bias b, m/s², +up (subtracted from the input)."""
        return FusionAltitudeKalmanGetAccelBias(&self._c)

    @property
    def baro_offset(self):
        """Baro offset (baro reads h + offset), m; 0 before the first baro sample."""
        return FusionAltitudeKalmanGetBaroOffset(&self._c)

    @property
    def gps_offset(self):
        """GPS offset (GPS reads h + offset), m; 0 before the first usable GPS sample."""
        return FusionAltitudeKalmanGetGpsOffset(&self._c)

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
        return KalmanSensors(*(self._c.sensors[i].nis for i in range(3)))

    @property
    def rejections(self):
        """Samples rejected by the gate so far, per sensor."""
        return KalmanSensors(*(int(self._c.sensors[i].rejections) for i in range(3)))

    @property
    def resets(self):
        """Resets after rejection streaks longer than the timeout, per sensor."""
        return KalmanSensors(*(int(self._c.sensors[i].resets) for i in range(3)))

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

    @property
    def gap_count(self):
        """Number of gaps so far: updates whose dt exceeded ``settings.gap_period``."""
        return FusionAltitudeKalmanGetGapCount(&self._c)

    @property
    def settings(self):
        """The settings; assign new :class:`KalmanSettings` to retune, keeping the state."""
        return KalmanSettings._wrap(FusionAltitudeKalmanGetSettings(&self._c))

    @settings.setter
    def settings(self, settings):
        cdef KalmanSettings checked = _as_settings(settings)
        FusionAltitudeKalmanSetSettings(&self._c, &checked._c)

    def _get_state(self):
        sensors = []
        for i in range(3):
            s = self._c.sensors[i]
            sensors.append((s.innovation, s.innovationVariance, s.nis, s.rejectingFor, int(s.rejections),
                            int(s.resets), int(<int>s.result), bool(s.rejecting)))
        return (_settings_to_dict(&self._c.settings), [self._c.x[i] for i in range(5)],
                [self._c.P[i][j] for i in range(5) for j in range(5)], sensors,
                bool(self._c.baroInitialised), bool(self._c.gpsInitialised), self._c.gapCount, self._c.sinceFused)

    def _set_state(self, state):
        settings, x, P, sensors, baro_initialised, gps_initialised = state[:6]
        gap_count = state[6] if len(state) > 6 else 0
        since_fused = state[7] if len(state) > 7 else 0.0
        cdef KalmanSettings checked = KalmanSettings(**settings)
        cdef int i, j
        self._c.settings = checked._c
        for i in range(5):
            self._c.x[i] = x[i]
            for j in range(5):
                self._c.P[i][j] = P[i * 5 + j]
        for i in range(3):
            innovation, variance, nis, rejecting_for, rejections, resets, result, rejecting = sensors[i]
            self._c.sensors[i].innovation = innovation
            self._c.sensors[i].innovationVariance = variance
            self._c.sensors[i].nis = nis
            self._c.sensors[i].rejectingFor = rejecting_for
            self._c.sensors[i].rejections = rejections
            self._c.sensors[i].resets = resets
            self._c.sensors[i].result = <FusionAltitudeKalmanResult><int>KalmanResult(result)
            self._c.sensors[i].rejecting = bool(rejecting)
        self._c.baroInitialised = bool(baro_initialised)
        self._c.gpsInitialised = bool(gps_initialised)
        self._c.gapCount = gap_count
        self._c.sinceFused = since_fused

    def __copy__(self):
        cdef KalmanEstimator clone = KalmanEstimator.__new__(KalmanEstimator)
        clone._c = self._c
        return clone

    def __deepcopy__(self, memo):
        return self.__copy__()

    def __reduce__(self):
        return (_restore, (self._get_state(),))

    def __repr__(self):
        return (f"KalmanEstimator(height_above_ground={self.height_above_ground!r}, altitude={self.altitude!r}, "
                f"vertical_velocity={self.vertical_velocity!r}, accel_bias={self.accel_bias!r})")


def _restore(state):
    cdef KalmanEstimator estimator = KalmanEstimator.__new__(KalmanEstimator)
    estimator._set_state(state)
    return estimator
