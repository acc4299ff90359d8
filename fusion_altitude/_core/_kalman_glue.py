"""Glue of the multi-sensor Kalman filter shared by its binding (``_kalman.pyx``)
and its reference (``reference/kalman.py``): statuses, the settings table,
error messages that name the argument, batch conversion and result types.
"""

from __future__ import annotations

import math
from typing import NamedTuple, Optional, Sequence

import numpy as np

from . import _c_tables
from ._c_tables import KalmanResult, KalmanStatus
from ._common import (ACCEL_FINITE, DT_POSITIVE, SAMPLE_OR_NAN, as_float, input_rules, optional_inputs, output_arrays,
                      raise_input_error)


#: The positional order of ``update`` after accel before 0.2 (still accepted, deprecated).
KALMAN_LEGACY_ORDER = ("dt", "baro_altitude", "range_distance", "gps_altitude", "gps_satellites",
                       "gps_vertical_accuracy", "ground_effect")


class KalmanSensors(NamedTuple):
    """One value per altitude sensor."""

    baro: object
    range: object
    gps: object


def _rule(terms: tuple) -> Optional[str]:
    """The message of a field's rule terms (``_c_tables.KALMAN_RULES``, from the header): ">0", ">=0", ">=1",
    ">range_min", "gap" (> 0, +inf allowed) or None (no rule)."""
    if "any" in terms:
        return None
    if "finite" not in terms and (">", 0) in terms:
        return "gap"
    for term, rule in (((">", "range_min"), ">range_min"), ((">=", 1), ">=1"), ((">", 0), ">0")):
        if term in terms:
            return rule
    return ">=0"


#: Kalman settings: (Python name, default, kind, status group, rule), in the order of the C struct
#: FusionAltitudeKalmanSettings. kind: "f" float32, "b" bool, "i" int32; the status group and rule are the
#: ``[rule: ...]`` of the field's comment in the header (:data:`fusion_altitude._c_tables.KALMAN_RULES`).
KALMAN_SETTINGS = tuple((name, default, kind, _c_tables.KALMAN_RULES[name][0], _rule(_c_tables.KALMAN_RULES[name][1]))
                        for name, _, kind, default, _ in _c_tables.KALMAN_SETTINGS)


KALMAN_SETTINGS_NAMES = tuple(name for name, *_ in KALMAN_SETTINGS)


#: The C settings functions ``KalmanSettings`` calls instead of the reference's arithmetic twins, once the binding
#: (``_kalman.pyx``) registers them at import: ``"check"`` → ``c_settings_check``. Without the compiled extension
#: it stays empty and the reference's twin checks (``tests/test_kalman.py`` holds it equal to C).
C_SETTINGS_FUNCTIONS: dict = {}


#: FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING: the largest accepted float setting.
KALMAN_MAXIMUM_SETTING = _c_tables.FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING


KALMAN_SETTINGS_DEFAULTS = {name: default for name, default, *_ in KALMAN_SETTINGS}


#: Names of the state vector entries, in the C index order.
KALMAN_STATE_NAMES = ("height_above_ground", "vertical_velocity", "baro_offset", "gps_offset", "accel_bias")


def convert_kalman_settings(kwargs: dict) -> dict:
    """Settings keyword arguments → dict of Python values of the C types (float32-rounded floats, bool, int)."""
    unknown = set(kwargs) - set(KALMAN_SETTINGS_NAMES)
    if unknown:
        raise TypeError(f"unknown Kalman setting(s): {', '.join(sorted(unknown))}")
    values = {}
    for name, default, kind, _, _ in KALMAN_SETTINGS:
        value = kwargs.get(name, default)
        if kind == "f":
            with np.errstate(over="ignore"):
                values[name] = float(np.float32(as_float(value, name)))
        elif kind == "b":
            if not isinstance(value, (bool, np.bool_)):
                raise TypeError(f"{name} must be a bool, got {type(value).__name__}")
            values[name] = bool(value)
        else:
            if isinstance(value, (bool, np.bool_)) or not hasattr(type(value), "__index__"):
                raise TypeError(f"{name} must be an int, got {type(value).__name__}")
            index = int(value)
            if not -2**31 <= index < 2**31:
                raise ValueError(f"{name} must fit in int32, got {index}")
            values[name] = index
    return values


def raise_kalman_settings_error(status: int, values: dict) -> None:
    """Raise the ValueError for rejected Kalman settings, naming the first bad field of the status's group."""
    for name, _, kind, group, rule in KALMAN_SETTINGS:
        if group != status:
            continue
        value = values[name]
        if rule == "gap":
            ok, text = value > 0, "must be > 0 (s; inf: never a gap)"
        elif kind == "f" and math.isfinite(value) and value > KALMAN_MAXIMUM_SETTING:
            ok, text = False, f"must be finite and <= {KALMAN_MAXIMUM_SETTING:g}"
        elif rule == ">range_min":
            ok = math.isfinite(value) and value > values["range_min"]
            text = f"must be finite and > range_min ({values['range_min']!r})"
        elif rule == ">0":
            ok = math.isfinite(value) and value > 0
            text = "must be finite and > 0"
        elif rule == ">=1":
            ok = math.isfinite(value) and value >= 1
            text = "must be finite and >= 1"
        else:
            ok = math.isfinite(value) and value >= 0
            text = "must be finite and >= 0"
        if not ok:
            raise ValueError(f"{name} {text}, got {value!r}")
    if status == KalmanStatus.INVALID_GPS:
        raise ValueError("gps_noise_base + gps_noise_satellite must be > 0")
    if status == KalmanStatus.INVALID_GROUND_EFFECT:
        raise ValueError(f"baro_noise * ground_effect_noise_scale must be <= {KALMAN_MAXIMUM_SETTING:g}, got "
                         f"{values['baro_noise']!r} * {values['ground_effect_noise_scale']!r}")
    raise ValueError(f"invalid Kalman settings (status {status})")


_KALMAN_UPDATE_RULES = input_rules(
    KalmanStatus, accel=ACCEL_FINITE, dt=DT_POSITIVE, baro_altitude=SAMPLE_OR_NAN, gps_altitude=SAMPLE_OR_NAN,
    gps_vertical_accuracy=("INVALID_GPS_ACCURACY", "must be finite and > 0 (m), or None/NaN if not reported"))


def raise_kalman_update_error(status: int, values: dict, index: Optional[int] = None,
                              is_array: Optional[dict] = None) -> None:
    """Raise the ValueError for a rejected Kalman update, naming the argument (and index in a batch)."""
    raise_input_error(_KALMAN_UPDATE_RULES, status, values, index, is_array)


def kalman_satellites(value: object) -> int:
    """gps_satellites of a per-sample update as a C int32: None or NaN (unknown) → -1; a count is a whole number
    >= 0 (a negative count is refused: it is no count, and C reads it as "unknown")."""
    if value is None:
        return -1
    if isinstance(value, (bool, np.bool_)):
        raise TypeError("gps_satellites must be an int or None, got bool")
    if isinstance(value, (float, np.floating)):
        if math.isnan(value):
            return -1
        if not float(value).is_integer():
            raise ValueError(f"gps_satellites must be a whole number, got {value!r}")
        value = int(value)
    if not hasattr(type(value), "__index__"):
        raise TypeError(f"gps_satellites must be an int or None, got {type(value).__name__}")
    n = int(value)  # type: ignore[call-overload]
    if n < 0:
        raise ValueError(f"gps_satellites must be >= 0 (None or NaN: unknown), got {value!r}")
    return min(n, 2**31 - 1)


class KalmanBatch(NamedTuple):
    """Per-sample outputs of ``KalmanEstimator.update_batch``.

    Attributes
    ----------
    height_above_ground, altitude, vertical_velocity, accel_bias, baro_offset, gps_offset : numpy.ndarray
        float32, shape (n,): the state after each sample (m, m, m/s, m/s², m, m).
    covariance_diagonal : numpy.ndarray
        float32, shape (n, 5): variances of (h, v, baro_offset, gps_offset, accel_bias).
    innovation, nis : numpy.ndarray
        float32, shape (n, 3): innovation (m) and NIS per sensor (baro, range, gps);
        NaN where a sensor had no tested sample.
    result : numpy.ndarray
        uint8, shape (n, 3): :class:`KalmanResult` per sensor.
    """

    height_above_ground: np.ndarray
    altitude: np.ndarray
    vertical_velocity: np.ndarray
    accel_bias: np.ndarray
    baro_offset: np.ndarray
    gps_offset: np.ndarray
    covariance_diagonal: np.ndarray
    innovation: np.ndarray
    nis: np.ndarray
    result: np.ndarray


def _kalman_output_layout(n: int):
    """(shape, dtype) of each KalmanBatch field for n samples."""
    vector, per_sensor = ((n,), np.float32), ((n, 3), np.float32)
    return [vector] * 6 + [((n, 5), np.float32), per_sensor, per_sensor, ((n, 3), np.uint8)]


def new_kalman_batch(n: int) -> KalmanBatch:
    """Uninitialised output arrays for n samples."""
    return output_arrays(KalmanBatch, _kalman_output_layout(n), None)


def kalman_output_arrays(n: int, out: Optional[Sequence[np.ndarray]]) -> KalmanBatch:
    """New output arrays for n samples, or the caller's ``out`` (a KalmanBatch of preallocated arrays) after checking it."""
    return output_arrays(KalmanBatch, _kalman_output_layout(n), out)


def prepare_kalman_batch(accel, dt, baro_altitude, range_distance, gps_altitude, gps_satellites,
                         gps_vertical_accuracy, ground_effect, out=None):
    """Convert ``update_batch`` inputs. Returns (n, inputs, steps, output): ``inputs``
    maps each argument name to a contiguous array (float32; int32 satellites,
    uint8 ground effect) of length n, or of length 1 for a scalar or None
    (then its entry in ``steps`` is 0, else 1)."""
    n, inputs, steps = optional_inputs({
        "accel": accel, "dt": dt, "baro_altitude": baro_altitude, "range_distance": range_distance,
        "gps_altitude": gps_altitude, "gps_vertical_accuracy": gps_vertical_accuracy})
    if gps_satellites is None or np.ndim(gps_satellites) == 0:
        satellites = np.array([kalman_satellites(gps_satellites)], dtype=np.int32)
    else:
        raw = np.asarray(gps_satellites)
        if raw.ndim != 1 or raw.shape[0] != n:
            raise ValueError(f"gps_satellites must be 1-D with {n} samples, got shape {raw.shape}")
        if raw.dtype.kind == "f":
            bad = ~np.isnan(raw) & (raw != np.floor(raw))
            if bad.any():
                index = int(np.argmax(bad))
                raise ValueError(f"gps_satellites[{index}] must be a whole number, got {raw[index]!r}")
            negative = ~np.isnan(raw) & (raw < 0)
            raw = np.where(np.isnan(raw), -1, raw)
        elif raw.dtype.kind not in "iu":
            raise TypeError(f"gps_satellites must be an array of integers, got dtype {raw.dtype}")
        else:
            negative = raw < 0
        if negative.any():
            index = int(np.argmax(negative))
            raise ValueError(f"gps_satellites[{index}] must be >= 0 (NaN: unknown), got {raw[index].item()!r}")
        satellites = np.ascontiguousarray(np.clip(raw, -1, 2**31 - 1), dtype=np.int32)
    inputs["gps_satellites"] = satellites
    if ground_effect is None or np.ndim(ground_effect) == 0:
        flags = np.array([bool(ground_effect)], dtype=np.uint8)
    else:
        flags = np.ascontiguousarray(np.asarray(ground_effect, dtype=bool), dtype=np.uint8)
        if flags.ndim != 1 or flags.shape[0] != n:
            raise ValueError(f"ground_effect must be 1-D with {n} samples, got shape {flags.shape}")
    inputs["ground_effect"] = flags
    for name, value in (("gps_satellites", gps_satellites), ("ground_effect", ground_effect)):
        steps[name] = int(value is not None and np.ndim(value) != 0)
    return n, inputs, steps, kalman_output_arrays(n, out)


class KalmanContract:
    """The public methods whose signature (and docstring) the KalmanEstimator binding and reference share, written
    once here: ``_common.share_signatures``/``share_docstrings`` give them to both classes."""

    def update(self, accel: float, baro_altitude: float, dt: float, *, range_distance: float = math.nan,
               gps_altitude: float = math.nan, gps_satellites: Optional[int] = None,
               gps_vertical_accuracy: Optional[float] = None, ground_effect: bool = False) -> None:
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
        raise NotImplementedError

    def update_batch(self, accel, baro_altitude, dt, *, range_distance=None, gps_altitude=None,
                     gps_satellites=None, gps_vertical_accuracy=None, ground_effect=None, out=None) -> KalmanBatch:
        """See the estimator class."""
        raise NotImplementedError
