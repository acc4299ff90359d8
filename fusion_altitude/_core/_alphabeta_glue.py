"""Glue of the quality-weighted alpha-beta fusion shared by its binding
(``_alphabeta.pyx``) and its reference (``reference/alphabeta.py``).
"""

from __future__ import annotations

import math
from typing import NamedTuple, Optional

import numpy as np

from . import _c_tables
from ._c_tables import AlphaBetaStatus
from ._common import (DT_POSITIVE, SAMPLE_OR_NAN, as_float, batch_raises_and_notes, input_rules, optional_inputs,
                      output_arrays, raise_input_error)


#: Sensor channels of the alpha-beta fusion, in the C index order.
ALPHABETA_SENSORS = _c_tables.ALPHABETA_SENSORS


#: Largest accepted quality (FUSION_ALTITUDE_ALPHABETA_MAX_QUALITY).
ALPHABETA_MAX_QUALITY = _c_tables.FUSION_ALTITUDE_ALPHABETA_MAX_QUALITY


class AlphaBetaSensorSettings(NamedTuple):
    """One sensor's settings in the alpha-beta fusion (C ``FusionAltitudeAlphaBetaSensorSettings``).

    Attributes
    ----------
    threshold : float
        m, > 0: a sample within this of the predicted fused altitude raises the quality by one; else it falls by one.
    quality_min, quality_max : int
        Range of the quality Q (the α-β filter depth, samples), 2 <= min <= max <= 10000.
    confidence : float
        >= 0: the sensor's weight is Q · confidence.
    altitude_min, altitude_max : float
        m: the band of predicted fused altitude in which the sensor is used (infinite allowed).
    gap_max : float
        m, > 0: the sensor is not used while its filtered altitude is further than this from the prediction.
    timeout : float
        s, > 0: not used after this long without a sample; the next sample restarts its filter.
    """

    threshold: float
    quality_min: int
    quality_max: int
    confidence: float
    altitude_min: float
    altitude_max: float
    gap_max: float
    timeout: float


#: FusionAltitudeAlphaBetaSettingsDefault(), read from the header: the write-up's tables, plus the
#: values it does not give (see csrc/fusion_altitude_alphabeta.h).
ALPHABETA_DEFAULTS = {sensor: AlphaBetaSensorSettings(**fields) for sensor, fields in _c_tables.ALPHABETA_DEFAULTS.items()}
ALPHABETA_DEFAULTS.update({name: default for name, _, _, default, _ in _c_tables.ALPHABETA_SETTINGS})

#: Default gap period of the alpha-beta fusion, s (the sensor timeouts).
ALPHABETA_GAP_PERIOD = ALPHABETA_DEFAULTS["gap_period"]


class AlphaBetaSensors(NamedTuple):
    """One value per alpha-beta sensor channel."""

    imu: object
    baro: object
    lidar: object
    sonar: object
    gps: object


def _as_int32(value: object, name: str) -> int:
    if isinstance(value, (bool, np.bool_)) or not hasattr(type(value), "__index__"):
        raise TypeError(f"{name} must be an int, got {type(value).__name__}")
    index = int(value)  # type: ignore[call-overload]
    if not -2**31 <= index < 2**31:
        raise ValueError(f"{name} must fit in int32, got {index}")
    return index


#: The C settings functions the settings class calls instead of the reference's arithmetic twins, once the
#: binding (``_alphabeta.pyx``) registers them at import: ``"check_sensor"`` → ``c_sensor_settings_check``,
#: ``"check_gap_period"`` → ``c_gap_period_check`` (the twins: ``reference/alphabeta.py``'s ``_sensor_status`` and
#: ``_gap_period_status``). Without the compiled extension it stays empty
#: (``tests/test_settings_checks.py`` holds each twin equal to C).
C_SETTINGS_FUNCTIONS: dict = {}


def convert_alphabeta_settings(kwargs: dict) -> dict:
    """``AlphaBetaSettings(**kwargs)`` arguments → {sensor: AlphaBetaSensorSettings of C-typed values,
    "gap_period": float32-rounded float (s, default 1.5)}.

    Each sensor's argument is None (defaults), an AlphaBetaSensorSettings, or
    a mapping of the fields to change from the defaults.
    """
    unknown = set(kwargs) - set(ALPHABETA_SENSORS) - {"gap_period"}
    if unknown:
        raise TypeError(f"unknown alpha-beta sensor(s): {', '.join(sorted(unknown))}; "
                        f"choose from {', '.join(ALPHABETA_SENSORS)}")
    result = {}
    for sensor in ALPHABETA_SENSORS:
        value = kwargs.get(sensor)
        base = ALPHABETA_DEFAULTS[sensor]._asdict()
        if value is None:
            fields = base
        elif isinstance(value, AlphaBetaSensorSettings):
            fields = value._asdict()
        elif hasattr(value, "keys"):
            extra = set(value) - set(AlphaBetaSensorSettings._fields)  # type: ignore[arg-type]
            if extra:
                raise TypeError(f"unknown {sensor} setting(s): {', '.join(sorted(extra))}")
            fields = {**base, **value}  # type: ignore[dict-item]
        else:
            raise TypeError(f"{sensor} must be None, a mapping or AlphaBetaSensorSettings, got {type(value).__name__}")
        converted = {}
        for name in AlphaBetaSensorSettings._fields:
            if name.startswith("quality"):
                converted[name] = _as_int32(fields[name], f"{sensor}.{name}")
            else:
                with np.errstate(over="ignore"):
                    converted[name] = float(np.float32(as_float(fields[name], f"{sensor}.{name}")))
        result[sensor] = AlphaBetaSensorSettings(**converted)
    with np.errstate(over="ignore"):
        result["gap_period"] = float(np.float32(as_float(kwargs.get("gap_period", ALPHABETA_GAP_PERIOD), "gap_period")))
    return result


def raise_alphabeta_settings_error(status: int, values: dict) -> None:
    """Raise the ValueError for rejected alpha-beta settings, naming the sensor and field (the C check's order)."""
    for sensor in ALPHABETA_SENSORS:
        s = values[sensor]
        where = sensor
        if not (math.isfinite(s.threshold) and s.threshold > 0):
            raise ValueError(f"{where}.threshold must be finite and > 0 (m), got {s.threshold!r}")
        if s.quality_min < 2:
            raise ValueError(f"{where}.quality_min must be >= 2 (Q = 1 is unstable), got {s.quality_min!r}")
        if s.quality_max < s.quality_min or s.quality_max > ALPHABETA_MAX_QUALITY:
            raise ValueError(f"{where}.quality_max must be in [quality_min, {ALPHABETA_MAX_QUALITY}], "
                             f"got {s.quality_max!r} (quality_min {s.quality_min!r})")
        if not (math.isfinite(s.confidence) and 0 <= s.confidence <= 1e6):
            raise ValueError(f"{where}.confidence must be finite and in [0, 1e6], got {s.confidence!r}")
        if not s.altitude_min < s.altitude_max:
            raise ValueError(f"{where}.altitude_min must be < altitude_max (m, infinite allowed), "
                             f"got {s.altitude_min!r} and {s.altitude_max!r}")
        if not s.gap_max > 0:
            raise ValueError(f"{where}.gap_max must be > 0 (m, inf: no limit), got {s.gap_max!r}")
        if not (math.isfinite(s.timeout) and s.timeout > 0):
            raise ValueError(f"{where}.timeout must be finite and > 0 (s), got {s.timeout!r}")
    if status == AlphaBetaStatus.INVALID_GAP_PERIOD:
        raise ValueError(f"gap_period must be > 0 (s; inf: never a gap), got {values['gap_period']!r}")
    raise ValueError(f"invalid alpha-beta settings (status {status})")


_ALPHABETA_UPDATE_RULES = input_rules(
    AlphaBetaStatus, accel="must be finite, or NaN for no IMU sample (m/s²)", dt=DT_POSITIVE,
    **{f"{sensor}_altitude": SAMPLE_OR_NAN for sensor in ("baro", "lidar", "sonar", "gps")})


#: update_batch's per-step inputs, in the order of the C call.
ALPHABETA_INPUTS = ("accel", "dt", "baro_altitude", "lidar_altitude", "sonar_altitude", "gps_altitude")


def raise_alphabeta_update_error(status: int, values: dict, index: Optional[int] = None,
                                 is_array: Optional[dict] = None) -> None:
    """Raise the ValueError for a rejected alpha-beta update, naming the argument (and index in a batch)."""
    raise_input_error(_ALPHABETA_UPDATE_RULES, status, values, index, is_array)


class AlphaBetaBatch(NamedTuple):
    """Per-step outputs of ``AlphaBetaFusion.update_batch``.

    Attributes
    ----------
    altitude, vertical_velocity : numpy.ndarray
        float32, shape (n,): fused altitude (m) and vertical velocity (m/s).
    weight : numpy.ndarray
        float32, shape (n, 5): each sensor's weight (imu, baro, lidar, sonar, gps); 0 = not used.
    quality : numpy.ndarray
        int32, shape (n, 5): each sensor's quality Q.
    """

    altitude: np.ndarray
    vertical_velocity: np.ndarray
    weight: np.ndarray
    quality: np.ndarray


def prepare_alphabeta_batch(accel, dt, baro_altitude, lidar_altitude, sonar_altitude, gps_altitude, out=None):
    """Convert ``update_batch`` inputs. Returns (n, inputs, steps, output): ``inputs`` maps each
    name of :data:`ALPHABETA_INPUTS` to a contiguous float32 array of length n, or of length 1 for a
    scalar or None (then its entry in ``steps`` is 0, else 1); ``output`` is ``out`` checked, or new arrays."""
    n, inputs, steps = optional_inputs(dict(zip(ALPHABETA_INPUTS, (accel, dt, baro_altitude, lidar_altitude,
                                                                   sonar_altitude, gps_altitude))))
    layout = [((n,), np.float32)] * 2 + [((n, 5), np.float32), ((n, 5), np.int32)]
    return n, inputs, steps, output_arrays(AlphaBetaBatch, layout, out)


class AlphaBetaContract:
    """The public methods whose signature (and docstring) the AlphaBetaFusion binding and reference share, written
    once here: ``_common.share_signatures``/``share_docstrings`` give them to both classes."""

    def update(self, accel: float, baro_altitude: float, dt: float, *, lidar_altitude: float = math.nan,
               sonar_altitude: float = math.nan, gps_altitude: float = math.nan) -> None:
        """See the estimator class."""
        raise NotImplementedError

    def update_batch(self, accel, baro_altitude, dt, *, lidar_altitude=None, sonar_altitude=None,
                     gps_altitude=None, out=None) -> AlphaBetaBatch:
        raise NotImplementedError

    update_batch.__doc__ = """Process arrays of steps, continuing from the current state.

        Parameters
        ----------
        accel : array_like
            Vertical acceleration per step, m/s² (NaN: no IMU sample).
        dt : float or array_like
            Step period, s: one value or one per step.
        baro_altitude, lidar_altitude, sonar_altitude, gps_altitude : array_like, float or None
            Per step, m; NaN where a sensor has no sample. A scalar applies to
            every step; None means no samples.
        out : AlphaBetaBatch, optional
            Preallocated contiguous output arrays of the right shapes and dtypes.

        Returns
        -------
        AlphaBetaBatch""" + batch_raises_and_notes("step")
