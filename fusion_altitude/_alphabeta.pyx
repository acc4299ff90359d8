# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Cython binding of the quality-weighted alpha-beta fusion in csrc/fusion_altitude_alphabeta.h.

This module converts and checks Python arguments, calls the C functions and
raises for the statuses they return. It holds no copy of the algorithm.
"""

import math

from fusion_altitude._convert cimport as_double as _as_double
from libc.stdint cimport int32_t

from fusion_altitude.calphabeta cimport *

from fusion_altitude import _alphabeta_glue
from fusion_altitude._alphabeta_glue import ALPHABETA_SENSORS, AlphaBetaBatch, AlphaBetaSensors, AlphaBetaSensorSettings

#: The C enum values, for checking that :class:`AlphaBetaStatus` matches.
C_STATUS_VALUES = {
    "OK": FusionAltitudeAlphaBetaStatusOk,
    "INVALID_ACCEL": FusionAltitudeAlphaBetaStatusInvalidAccel,
    "INVALID_DT": FusionAltitudeAlphaBetaStatusInvalidDt,
    "INVALID_BARO_ALTITUDE": FusionAltitudeAlphaBetaStatusInvalidBaroAltitude,
    "INVALID_LIDAR_ALTITUDE": FusionAltitudeAlphaBetaStatusInvalidLidarAltitude,
    "INVALID_SONAR_ALTITUDE": FusionAltitudeAlphaBetaStatusInvalidSonarAltitude,
    "INVALID_GPS_ALTITUDE": FusionAltitudeAlphaBetaStatusInvalidGpsAltitude,
    "INVALID_THRESHOLD": FusionAltitudeAlphaBetaStatusInvalidThreshold,
    "INVALID_QUALITY": FusionAltitudeAlphaBetaStatusInvalidQuality,
    "INVALID_CONFIDENCE": FusionAltitudeAlphaBetaStatusInvalidConfidence,
    "INVALID_ALTITUDE_BAND": FusionAltitudeAlphaBetaStatusInvalidAltitudeBand,
    "INVALID_GAP_MAX": FusionAltitudeAlphaBetaStatusInvalidGapMax,
    "INVALID_TIMEOUT": FusionAltitudeAlphaBetaStatusInvalidTimeout,
    "INVALID_GAP_PERIOD": FusionAltitudeAlphaBetaStatusInvalidGapPeriod,
}
C_SENSOR_COUNT = FUSION_ALTITUDE_ALPHABETA_SENSORS
C_MAX_QUALITY = FUSION_ALTITUDE_ALPHABETA_MAX_QUALITY


def c_default_settings():
    """The header's FusionAltitudeAlphaBetaSettingsDefault() as {sensor: AlphaBetaSensorSettings}."""
    cdef FusionAltitudeAlphaBetaSettings c = FusionAltitudeAlphaBetaSettingsDefault()
    return _settings_to_dict(&c)


def status_message(int status):
    """The C header's message for a status code."""
    return FusionAltitudeAlphaBetaStatusMessage(<FusionAltitudeAlphaBetaStatus>status).decode("ascii")


def gains(int quality):
    """(alpha, beta) of the least-squares alpha-beta filter of depth ``quality`` (C FusionAltitudeAlphaBetaGains)."""
    cdef float alpha, beta
    FusionAltitudeAlphaBetaGains(<int32_t>quality, &alpha, &beta)
    return alpha, beta


cdef dict _settings_to_dict(const FusionAltitudeAlphaBetaSettings *c):
    cdef int i
    result = {}
    for i in range(5):
        s = &c.sensors[i]
        result[ALPHABETA_SENSORS[i]] = AlphaBetaSensorSettings(s.threshold, s.qualityMin, s.qualityMax, s.confidence,
                                                               s.altitudeMin, s.altitudeMax, s.gapMax, s.timeout)
    result["gap_period"] = c.gapPeriod
    return result


cdef class AlphaBetaSettings:
    """Settings of the quality-weighted alpha-beta fusion: one :class:`AlphaBetaSensorSettings` per sensor.

    Parameters
    ----------
    imu, baro, lidar, sonar, gps : AlphaBetaSensorSettings or mapping, optional
        A sensor's settings, or a mapping of the fields to change from its
        defaults, e.g. ``AlphaBetaSettings(gps={"gap_max": 30.0})``.
    gap_period : float, default 1.5
        s: an update whose dt exceeds this is a gap, not integrated (the
        fusion restarts from the next samples), and the longest dead
        reckoning before it re-acquires; ``inf`` never detects a gap.

    Notes
    -----
    The defaults are the write-up's tables (threshold m, Q min, Q max,
    confidence, altitude min m, gap max m): IMU 1, 2, 4, 5, −1, 4; baro 1, 10,
    60, 2, −4, 10; lidar 0.5, 2, 8, 10, 0, 6; GPS 10, 10, 120, 1, −10, 20.
    The sonar copies the lidar; altitude max is 40 m (lidar), 5 m (sonar),
    infinite otherwise; every timeout is 1.5 s.

    Raises
    ------
    ValueError
        A field out of range, naming ``sensor.field``.
    """

    cdef FusionAltitudeAlphaBetaSettings _c

    def __init__(self, **sensors):
        values = _alphabeta_glue.convert_alphabeta_settings(sensors)
        cdef int i
        for i in range(5):
            s = values[ALPHABETA_SENSORS[i]]
            self._c.sensors[i].threshold = s.threshold
            self._c.sensors[i].qualityMin = s.quality_min
            self._c.sensors[i].qualityMax = s.quality_max
            self._c.sensors[i].confidence = s.confidence
            self._c.sensors[i].altitudeMin = s.altitude_min
            self._c.sensors[i].altitudeMax = s.altitude_max
            self._c.sensors[i].gapMax = s.gap_max
            self._c.sensors[i].timeout = s.timeout
        self._c.gapPeriod = values["gap_period"]
        cdef FusionAltitudeAlphaBetaStatus status = FusionAltitudeAlphaBetaSettingsCheck(&self._c)
        if status != FusionAltitudeAlphaBetaStatusOk:
            _alphabeta_glue.raise_alphabeta_settings_error(status, values)

    @staticmethod
    cdef AlphaBetaSettings _wrap(FusionAltitudeAlphaBetaSettings c):
        cdef AlphaBetaSettings settings = AlphaBetaSettings.__new__(AlphaBetaSettings)
        settings._c = c
        return settings

    def __getattr__(self, name):
        values = self.as_dict()
        if name in values:
            return values[name]
        raise AttributeError(f"'AlphaBetaSettings' object has no attribute {name!r}")

    def as_dict(self):
        """{sensor: AlphaBetaSensorSettings} in the C sensor order."""
        return _settings_to_dict(&self._c)

    def replace(self, **sensors):
        """A copy with some sensors' fields changed (mappings of fields, or whole AlphaBetaSensorSettings)."""
        current = self.as_dict()
        merged = {}
        for name, value in current.items():
            change = sensors.get(name)
            if change is None:
                merged[name] = value
            elif name == "gap_period":
                merged[name] = change
            elif isinstance(change, AlphaBetaSensorSettings):
                merged[name] = change
            else:
                merged[name] = value._replace(**change)
        unknown = set(sensors) - set(current)
        if unknown:
            raise TypeError(f"unknown alpha-beta sensor(s): {', '.join(sorted(unknown))}")
        return AlphaBetaSettings(**merged)

    def __eq__(self, other):
        if not hasattr(other, "as_dict") or not hasattr(other, "sonar"):
            return NotImplemented
        return self.as_dict() == other.as_dict()

    def __hash__(self):
        return hash(tuple(self.as_dict().items()))

    def __repr__(self):
        return "AlphaBetaSettings(" + ", ".join(f"{k}={v!r}" for k, v in self.as_dict().items()) + ")"

    def __reduce__(self):
        return (_settings_from_dict, (self.as_dict(),))


def _settings_from_dict(values):
    return AlphaBetaSettings(**values)


cdef AlphaBetaSettings _as_settings(object settings):
    if isinstance(settings, AlphaBetaSettings):
        return settings
    if hasattr(settings, "as_dict") and hasattr(settings, "sonar"):
        return AlphaBetaSettings(**settings.as_dict())
    raise TypeError(f"settings must be AlphaBetaSettings, got {type(settings).__name__}")


cdef Py_ssize_t _run(FusionAltitudeAlphaBeta *state, Py_ssize_t n,
                     const float *accel, Py_ssize_t sa, const float *dt, Py_ssize_t sd,
                     const float *baro, Py_ssize_t sb, const float *lidar, Py_ssize_t sl,
                     const float *sonar, Py_ssize_t ss, const float *gps, Py_ssize_t sg,
                     float *h, float *v, float *weight, int32_t *quality) noexcept nogil:
    """Run n steps on a private copy of *state; commit it only if all succeed.

    Returns the index of the first rejected step, or -1.
    """
    cdef FusionAltitudeAlphaBeta local = state[0]
    cdef FusionAltitudeAlphaBetaMeasurements m
    cdef Py_ssize_t i
    cdef int j
    for i in range(n):
        m.baroAltitude = baro[i * sb]
        m.lidarAltitude = lidar[i * sl]
        m.sonarAltitude = sonar[i * ss]
        m.gpsAltitude = gps[i * sg]
        if FusionAltitudeAlphaBetaUpdate(&local, accel[i * sa], dt[i * sd], &m) != FusionAltitudeAlphaBetaStatusOk:
            return i
        h[i] = local.altitude
        v[i] = local.verticalVelocity
        for j in range(5):
            weight[i * 5 + j] = local.filters[j].weight
            quality[i * 5 + j] = local.filters[j].quality
    state[0] = local
    return -1


cdef class AlphaBetaFusion:
    """Quality-weighted alpha-beta fusion of IMU-integrated altitude, baro, lidar, sonar and GPS.

    Each sensor runs an alpha-beta filter of depth Q (its quality), which
    rises by one while the sensor agrees with the fused prediction within its
    threshold and falls by one otherwise; alpha = 2(2Q−1)/(Q(Q+1)), beta =
    6/(Q(Q+1)). The output is the mean of the filters weighted by
    Q · confidence, a sensor's weight zeroed outside its altitude band, while
    its latest sample is further than its gap maximum from the prediction, or
    after its timeout.

    Parameters
    ----------
    settings : AlphaBetaSettings, optional
        Default: the write-up's tables.

    Notes
    -----
    NaN means "no sample this step" for every input, accel (the IMU channel)
    included. No offsets are estimated: every sensor is taken to measure the
    same altitude. Copies and pickles carry the full state.
    """

    cdef FusionAltitudeAlphaBeta _c

    def __init__(self, settings=None):
        cdef AlphaBetaSettings checked
        FusionAltitudeAlphaBetaInitialise(&self._c)
        if settings is not None:
            checked = _as_settings(settings)
            FusionAltitudeAlphaBetaInitialiseWith(&self._c, &checked._c)

    def update(self, accel, dt, baro_altitude=math.nan, lidar_altitude=math.nan, sonar_altitude=math.nan,
               gps_altitude=math.nan):
        """Process one step.

        Parameters
        ----------
        accel : float
            Vertical acceleration, m/s², +up, gravity removed; NaN: no IMU sample.
        dt : float
            Time since the previous step, s.
        baro_altitude, lidar_altitude, sonar_altitude, gps_altitude : float
            Each sensor's altitude, m; NaN (the default): no sample this step.

        Raises
        ------
        ValueError
            An infinite input or dt not finite and > 0, naming it; the state is unchanged.
        """
        cdef double a = _as_double(accel, "accel")
        cdef double t = _as_double(dt, "dt")
        cdef FusionAltitudeAlphaBetaMeasurements m
        m.baroAltitude = <float>_as_double(baro_altitude, "baro_altitude")
        m.lidarAltitude = <float>_as_double(lidar_altitude, "lidar_altitude")
        m.sonarAltitude = <float>_as_double(sonar_altitude, "sonar_altitude")
        m.gpsAltitude = <float>_as_double(gps_altitude, "gps_altitude")
        cdef FusionAltitudeAlphaBetaStatus status = FusionAltitudeAlphaBetaUpdate(&self._c, <float>a, <float>t, &m)
        if status != FusionAltitudeAlphaBetaStatusOk:
            _alphabeta_glue.raise_alphabeta_update_error(status, {
                "accel": float(a), "dt": float(t), "baro_altitude": float(baro_altitude),
                "lidar_altitude": float(lidar_altitude), "sonar_altitude": float(sonar_altitude),
                "gps_altitude": float(gps_altitude)})

    def update_batch(self, accel, dt, baro_altitude=None, lidar_altitude=None, sonar_altitude=None,
                     gps_altitude=None):
        """Process arrays of steps, continuing from the current state.

        Parameters
        ----------
        accel : array_like
            Vertical acceleration per step, m/s² (NaN: no IMU sample).
        dt : float or array_like
            Step period, s: one value or one per step.
        baro_altitude, lidar_altitude, sonar_altitude, gps_altitude : array_like, float or None
            Per step, m; NaN where a sensor has no sample. A scalar applies to
            every step; None means no samples.

        Returns
        -------
        AlphaBetaBatch

        Raises
        ------
        ValueError
            A bad step, naming the argument and its first bad index; nothing
            is applied to the state.

        Notes
        -----
        Equal, bit for bit, to calling :meth:`update` for each step. The loop
        runs with the GIL released.
        """
        n, inputs, steps, result = _alphabeta_glue.prepare_alphabeta_batch(accel, dt, baro_altitude, lidar_altitude,
                                                                    sonar_altitude, gps_altitude)
        cdef const float[::1] a = inputs["accel"]
        cdef const float[::1] t = inputs["dt"]
        cdef const float[::1] zb = inputs["baro_altitude"]
        cdef const float[::1] zl = inputs["lidar_altitude"]
        cdef const float[::1] zs = inputs["sonar_altitude"]
        cdef const float[::1] zg = inputs["gps_altitude"]
        cdef float[::1] h = result.altitude
        cdef float[::1] v = result.vertical_velocity
        cdef float[:, ::1] w = result.weight
        cdef int32_t[:, ::1] q = result.quality
        cdef Py_ssize_t count = n
        cdef Py_ssize_t bad = -1
        cdef Py_ssize_t sa = steps["accel"], sd = steps["dt"], sb = steps["baro_altitude"]
        cdef Py_ssize_t sl = steps["lidar_altitude"], ss = steps["sonar_altitude"], sg = steps["gps_altitude"]
        cdef FusionAltitudeAlphaBetaMeasurements m
        if count == 0:
            return result
        with nogil:
            bad = _run(&self._c, count, &a[0], sa, &t[0], sd, &zb[0], sb, &zl[0], sl, &zs[0], ss, &zg[0], sg,
                       &h[0], &v[0], &w[0, 0], &q[0, 0])
        if bad >= 0:
            m.baroAltitude = zb[bad * sb]
            m.lidarAltitude = zl[bad * sl]
            m.sonarAltitude = zs[bad * ss]
            m.gpsAltitude = zg[bad * sg]
            status = FusionAltitudeAlphaBetaCheckInputs(a[bad * sa], t[bad * sd], &m)
            values = {"accel": float(a[bad * sa]), "dt": float(t[bad * sd]), "baro_altitude": float(zb[bad * sb]),
                      "lidar_altitude": float(zl[bad * sl]), "sonar_altitude": float(zs[bad * ss]),
                      "gps_altitude": float(zg[bad * sg])}
            _alphabeta_glue.raise_alphabeta_update_error(status, values, bad, {k: bool(s) for k, s in steps.items()})
        return result

    @property
    def altitude(self):
        """Fused altitude h, m (0 until started)."""
        return FusionAltitudeAlphaBetaGetAltitude(&self._c)

    @property
    def vertical_velocity(self):
        """Fused vertical velocity v, m/s, +up."""
        return FusionAltitudeAlphaBetaGetVerticalVelocity(&self._c)

    @property
    def started(self):
        """Whether the fusion has started (first baro, lidar, sonar or GPS sample)."""
        return FusionAltitudeAlphaBetaIsStarted(&self._c)

    @property
    def total_weight(self):
        """Sum of the weights of the latest step (0: dead reckoning)."""
        return self._c.totalWeight

    @property
    def weights(self):
        """Each sensor's weight in the latest step (0: not used)."""
        return AlphaBetaSensors(*[self._c.filters[i].weight for i in range(5)])

    @property
    def qualities(self):
        """Each sensor's quality Q (filter depth, samples)."""
        return AlphaBetaSensors(*[int(self._c.filters[i].quality) for i in range(5)])

    @property
    def filter_altitudes(self):
        """Each sensor's filtered altitude x, m."""
        return AlphaBetaSensors(*[self._c.filters[i].altitude for i in range(5)])

    @property
    def gaps(self):
        """Each sensor's gap z − predicted fused altitude at its latest sample, m."""
        return AlphaBetaSensors(*[self._c.filters[i].gap for i in range(5)])

    @property
    def gap_count(self):
        """Number of time gaps so far: updates whose dt exceeded ``settings.gap_period`` once started."""
        return FusionAltitudeAlphaBetaGetGapCount(&self._c)

    @property
    def settings(self):
        """The settings; assign new :class:`AlphaBetaSettings` to retune (qualities clamped to the new ranges)."""
        return AlphaBetaSettings._wrap(self._c.settings)

    @settings.setter
    def settings(self, settings):
        cdef AlphaBetaSettings checked = _as_settings(settings)
        FusionAltitudeAlphaBetaSetSettings(&self._c, &checked._c)

    def _get_state(self):
        cdef int i
        filters = []
        for i in range(5):
            filters.append((self._c.filters[i].altitude, self._c.filters[i].velocity, self._c.filters[i].sinceSample,
                            self._c.filters[i].gap, self._c.filters[i].weight, int(self._c.filters[i].quality),
                            bool(self._c.filters[i].started)))
        filters = tuple(filters)
        return (self.settings.as_dict(), filters, self._c.altitude, self._c.verticalVelocity, self._c.totalWeight,
                bool(self._c.started), self._c.coastingFor, self._c.gapTime, self._c.gapCount)

    def _set_state(self, state):
        values, filters, h, v, total, started = state[:6]
        coasting, gap_time, gap_count = state[6:] if len(state) > 6 else (0.0, 0.0, 0)
        cdef AlphaBetaSettings settings = AlphaBetaSettings(**values)
        self._c.settings = settings._c
        cdef int i
        for i in range(5):
            x, vi, since, gap, weight, quality, filter_started = filters[i]
            self._c.filters[i].altitude = x
            self._c.filters[i].velocity = vi
            self._c.filters[i].sinceSample = since
            self._c.filters[i].gap = gap
            self._c.filters[i].weight = weight
            self._c.filters[i].quality = quality
            self._c.filters[i].started = filter_started
        self._c.altitude = h
        self._c.verticalVelocity = v
        self._c.totalWeight = total
        self._c.started = bool(started)
        self._c.coastingFor = coasting
        self._c.gapTime = gap_time
        self._c.gapCount = gap_count

    def __copy__(self):
        cdef AlphaBetaFusion clone = AlphaBetaFusion.__new__(AlphaBetaFusion)
        clone._c = self._c
        return clone

    def __deepcopy__(self, memo):
        return self.__copy__()

    def __reduce__(self):
        return (_restore, (self._get_state(),))

    def __repr__(self):
        return (f"AlphaBetaFusion(altitude={self.altitude!r}, vertical_velocity={self.vertical_velocity!r}, "
                f"weights={tuple(self.weights)!r})")


def _restore(state):
    cdef AlphaBetaFusion fusion = AlphaBetaFusion.__new__(AlphaBetaFusion)
    fusion._set_state(state)
    return fusion
