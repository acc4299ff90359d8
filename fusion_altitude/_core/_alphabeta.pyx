# cython: language_level=3, boundscheck=False, wraparound=False, initializedcheck=False, cdivision=True
"""Cython binding of the quality-weighted alpha-beta fusion in csrc/fusion_altitude_alphabeta.h: see ``_core/__init__.py`` for what a binding does."""

import math

from libc.math cimport NAN
from libc.stdint cimport int32_t

include "_alphabeta_fields.pxi"

from fusion_altitude._core._alphabeta_glue import ALPHABETA_SENSORS, AlphaBetaBatch, AlphaBetaSensors, AlphaBetaSensorSettings

C_SENSOR_COUNT = FUSION_ALTITUDE_ALPHABETA_SENSORS
C_MAX_QUALITY = FUSION_ALTITUDE_ALPHABETA_MAX_QUALITY
status_message = c_status_message

#: An argument left out (update's keywords default to it, so that a name given twice in the deprecated
#: positional order is caught).
cdef object _UNSET = _common.UNSET
_UPDATE_KEYWORDS = ("baro_altitude", "dt", "lidar_altitude", "sonar_altitude", "gps_altitude")
_BATCH_KEYWORDS = _UPDATE_KEYWORDS + ("out",)


cdef object _float_or_nan(object value):
    return math.nan if value is _UNSET else float(value)


def gains(int quality):
    """(alpha, beta) of the least-squares alpha-beta filter of depth ``quality`` (C FusionAltitudeAlphaBetaGains)."""
    cdef float alpha, beta
    FusionAltitudeAlphaBetaGains(<int32_t>quality, &alpha, &beta)
    return alpha, beta


def _settings_dict(values):
    """{"sensors": [{field: value} per sensor], other field: value} (from C) → {sensor: AlphaBetaSensorSettings,
    other field: value}, as ``AlphaBetaSettings.as_dict()``."""
    result = {name: AlphaBetaSensorSettings(**fields) for name, fields in zip(ALPHABETA_SENSORS, values["sensors"])}
    result.update((name, value) for name, value in values.items() if name != "sensors")
    return result


def c_default_settings():
    """The header's FusionAltitudeAlphaBetaSettingsDefault() as {sensor: AlphaBetaSensorSettings}."""
    return _settings_dict(_c_default_settings())


def c_sensor_settings_check(sensor):
    """FusionAltitudeAlphaBetaSensorSettingsCheck of one sensor's settings (an AlphaBetaSensorSettings), from C."""
    cdef FusionAltitudeAlphaBetaSensorSettings c
    c.threshold, c.qualityMin, c.qualityMax, c.confidence = sensor[0], sensor[1], sensor[2], sensor[3]
    c.altitudeMin, c.altitudeMax, c.gapMax, c.timeout = sensor[4], sensor[5], sensor[6], sensor[7]
    return int(FusionAltitudeAlphaBetaSensorSettingsCheck(&c))


def c_gap_period_check(float gap_period):
    """FusionAltitudeAlphaBetaSettingsCheck of the default sensors with ``gap_period`` (s), from C: the status."""
    cdef FusionAltitudeAlphaBetaSettings c = FusionAltitudeAlphaBetaSettingsDefault()
    c.gapPeriod = gap_period
    return int(FusionAltitudeAlphaBetaSettingsCheck(&c))


_alphabeta_glue.C_SETTINGS_FUNCTIONS.update(check_sensor=c_sensor_settings_check, check_gap_period=c_gap_period_check)


def _c_values(settings):
    """AlphaBetaSettings (or a {sensor: ...} dict, checked) → what ``_settings_to_c`` takes."""
    if not isinstance(settings, AlphaBetaSettings):
        settings = AlphaBetaSettings.coerce(settings) if hasattr(settings, "as_dict") else AlphaBetaSettings(**settings)
    values = settings.as_dict()
    result = {name: value for name, value in values.items() if name not in ALPHABETA_SENSORS}
    result["sensors"] = [values[name]._asdict() for name in ALPHABETA_SENSORS]
    return result


_settings_out, _checked_settings = _settings_dict, _c_values  # a checkpoint holds {sensor: AlphaBetaSensorSettings}


cdef class AlphaBetaFusion(_AlphaBetaFusionGetters):
    __doc__ = DOC_AlphaBetaFusion  # generated from the reference's docstring (_alphabeta_fields.pxi)


    def __init__(self, settings=None):
        cdef FusionAltitudeAlphaBetaSettings c
        FusionAltitudeAlphaBetaInitialise(&self._c)
        if settings is not None:
            c = _settings_to_c(_c_values(settings))
            FusionAltitudeAlphaBetaInitialiseWith(&self._c, &c)

    def update(self, accel, *args, baro_altitude=_UNSET, dt=_UNSET, lidar_altitude=_UNSET, sonar_altitude=_UNSET,
               gps_altitude=_UNSET):
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
        # Parsed here, not by a Python wrapper: keywords after accel (the contract) are the fast path;
        # update(accel, baro_altitude, dt=...) is the contract too; other positional arguments after accel
        # are the deprecated old order (_common.positional_after_accel: the same rules as the reference).
        if args:
            baro_altitude, dt, lidar_altitude, sonar_altitude, gps_altitude = _common.positional_after_accel(
                type(self).__name__, "update", _UPDATE_KEYWORDS, _alphabeta_glue.ALPHABETA_INPUTS[1:], args,
                (baro_altitude, dt, lidar_altitude, sonar_altitude, gps_altitude), _UNSET)
        self._update(accel, baro_altitude, dt, lidar_altitude, sonar_altitude, gps_altitude)

    cdef int _update(self, accel, baro_altitude, dt, lidar_altitude, sonar_altitude, gps_altitude) except -1:
        """update() after argument parsing: _UNSET is an argument left out (NaN: no sample; dt: None)."""
        cdef double a = _as_double(accel, "accel")
        cdef double t = _as_double(None if dt is _UNSET else dt, "dt")
        cdef FusionAltitudeAlphaBetaMeasurements m
        m.baroAltitude = NAN if baro_altitude is _UNSET else <float>_as_double(baro_altitude, "baro_altitude")
        m.lidarAltitude = NAN if lidar_altitude is _UNSET else <float>_as_double(lidar_altitude, "lidar_altitude")
        m.sonarAltitude = NAN if sonar_altitude is _UNSET else <float>_as_double(sonar_altitude, "sonar_altitude")
        m.gpsAltitude = NAN if gps_altitude is _UNSET else <float>_as_double(gps_altitude, "gps_altitude")
        cdef FusionAltitudeAlphaBetaStatus status = FusionAltitudeAlphaBetaUpdate(&self._c, <float>a, <float>t, &m)
        if status != FusionAltitudeAlphaBetaStatusOk:
            _alphabeta_glue.raise_alphabeta_update_error(status, {
                "accel": float(a), "dt": float(t), "baro_altitude": _float_or_nan(baro_altitude),
                "lidar_altitude": _float_or_nan(lidar_altitude), "sonar_altitude": _float_or_nan(sonar_altitude),
                "gps_altitude": _float_or_nan(gps_altitude)})
        return 0

    def update_batch(self, accel, *args, baro_altitude=_UNSET, dt=_UNSET, lidar_altitude=_UNSET,
                     sonar_altitude=_UNSET, gps_altitude=_UNSET, out=_UNSET):
        values = (baro_altitude, dt, lidar_altitude, sonar_altitude, gps_altitude, out)
        if args:  # as in update
            values = _common.positional_after_accel(type(self).__name__, "update_batch", _BATCH_KEYWORDS,
                                                    _alphabeta_glue.ALPHABETA_INPUTS[1:] + ("out",), args, values,
                                                    _UNSET)
        baro_altitude, dt, lidar_altitude, sonar_altitude, gps_altitude, out = [
            None if value is _UNSET else value for value in values]  # left out: None (no samples)
        n, inputs, steps, result = _alphabeta_glue.prepare_alphabeta_batch(accel, dt, baro_altitude, lidar_altitude,
                                                                    sonar_altitude, gps_altitude, out)
        cdef FusionAltitudeAlphaBetaMeasurements m
        bad = _batch_into(&self._c, n, inputs, steps, result)  # the loop: _alphabeta_fields.pxi
        if bad >= 0:
            values = {name: float(array[bad * steps[name]]) for name, array in inputs.items()}  # the first bad step's
            m.baroAltitude = values["baro_altitude"]
            m.lidarAltitude = values["lidar_altitude"]
            m.sonarAltitude = values["sonar_altitude"]
            m.gpsAltitude = values["gps_altitude"]
            status = FusionAltitudeAlphaBetaCheckInputs(values["accel"], values["dt"], &m)
            _alphabeta_glue.raise_alphabeta_update_error(status, values, bad, {k: bool(s) for k, s in steps.items()})
        return result if out is None else out  # out=: the caller's object itself, filled

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
    def timed_out(self):
        """Each sensor's timeout flag: it had samples, then none for longer than its ``timeout`` (s), until its next
        sample (FusionAltitudeAlphaBetaIsTimedOut)."""
        return AlphaBetaSensors(*[bool(self._c.filters[i].timedOut) for i in range(5)])

    @property
    def timeout_counts(self):
        """Each sensor's number of timeouts so far, each silence longer than its ``timeout`` counted once."""
        return AlphaBetaSensors(*[int(self._c.filters[i].timeouts) for i in range(5)])

    @property
    def settings(self):
        """The settings; assign new :class:`AlphaBetaSettings` to retune (qualities clamped to the new ranges)."""
        return AlphaBetaSettings(**_settings_dict(_settings_from_c(&self._c.settings)))

    @settings.setter
    def settings(self, settings):
        cdef FusionAltitudeAlphaBetaSettings c = _settings_to_c(_c_values(settings))
        FusionAltitudeAlphaBetaSetSettings(&self._c, &c)

    def _set_state(self, state):
        state = tuple(state)
        if len(state) > 1 and state[1] and len(state[1][0]) == 7:  # from before the interval and timeout fields
            state = (state[0], tuple((*row[:3], 0.0, *row[3:6], 0, row[6], False) for row in state[1]), *state[2:])
        _state_set(&self._c, state, _c_values)

    def __repr__(self):
        return (f"AlphaBetaFusion(altitude={self.altitude!r}, vertical_velocity={self.vertical_velocity!r}, "
                f"weights={tuple(self.weights)!r})")


_common.share_signatures(AlphaBetaFusion, _alphabeta_glue.AlphaBetaContract, ("update", "update_batch"))
_common.share_docstrings(AlphaBetaFusion, _alphabeta_glue.AlphaBetaContract)  # update_batch

