"""Python-side glue shared by the C binding and the pure-Python reference.

Nothing here is part of the algorithm: it converts and checks arguments, turns
status codes into exceptions with the argument's name, and defines the result
type of the batch functions. The algorithm lives in ``csrc/fusion_altitude.h``
and, for reading, in :mod:`fusion_altitude.reference`.
"""

from __future__ import annotations

import enum
import math
import warnings
from typing import NamedTuple, Optional, Sequence, Tuple

import numpy as np

#: Standard gravity, m/s². Multiply an acceleration in g by this.
GRAVITY = 9.80665

#: Preset names accepted by ``AltitudeSettings.preset`` and their position-loop
#: bandwidth ω (rad/s); each uses ζ = 0.7 and ω_b = ω/5.
PRESET_OMEGA = {"balloon": 0.2, "fixed_wing": 0.5, "vtol": 1.5, "racing": 5.0}
#: Index of each preset in the C enum ``FusionAltitudePreset``.
PRESET_INDEX = {name: index for index, name in enumerate(PRESET_OMEGA)}

#: ``ω·dt`` at or above this gets a :class:`DiscretisationWarning`.
OMEGA_DT_ADVICE = 0.1


class Status(enum.IntEnum):
    """Status codes, equal to the C enum ``FusionAltitudeStatus``."""

    OK = 0
    INVALID_ACCEL = 1
    INVALID_BARO_ALTITUDE = 2
    INVALID_DT = 3
    INVALID_ACCEL_BIAS = 4
    INVALID_GAIN = 5
    UNSTABLE_GAINS = 6
    UNSTABLE_DISCRETE = 7
    INVALID_BANDWIDTH = 8
    INVALID_PRESET = 9


class DiscretisationWarning(UserWarning):
    """The sample period is long for the observer's bandwidth (ω·dt ≥ 0.1).

    The semi-implicit Euler step then no longer follows the continuous-time
    response closely, although it may still be stable.
    """


class AltitudeBatch(NamedTuple):
    """Per-sample outputs of ``update_batch``, each a float32 array.

    Attributes
    ----------
    altitude : numpy.ndarray
        Altitude estimate h after each sample, m.
    vertical_velocity : numpy.ndarray
        Vertical velocity estimate v after each sample, m/s, +up.
    accel_bias : numpy.ndarray
        Accelerometer bias estimate b after each sample, m/s², +up.
    baro_residual : numpy.ndarray
        Baro residual z − h of each sample before its correction, m; NaN where
        the sample had no baro altitude, 0 where it set the reference.
    """

    altitude: np.ndarray
    vertical_velocity: np.ndarray
    accel_bias: np.ndarray
    baro_residual: np.ndarray


_UPDATE_RULES = {
    Status.INVALID_ACCEL: ("accel", "must be finite (m/s²)"),
    Status.INVALID_BARO_ALTITUDE: ("baro_altitude", "must be finite, or NaN for no baro sample (m)"),
    Status.INVALID_DT: ("dt", "must be finite and > 0 (s)"),
}


def as_float(value: object, name: str) -> float:
    """Return ``value`` as a Python float, or raise TypeError naming ``name``."""
    if isinstance(value, float):
        return value
    kind = type(value)
    if hasattr(kind, "__float__") or hasattr(kind, "__index__"):  # as CPython's PyFloat_AsDouble
        return float(value)  # type: ignore[arg-type]
    raise TypeError(f"{name} must be a real number, got {kind.__name__}")


def raise_update_error(status: int, accel: float, baro_altitude: float, dt: float, index: Optional[int] = None,
                       dt_is_array: bool = False) -> None:
    """Raise the ValueError for a rejected update, naming the argument (and index)."""
    name, rule = _UPDATE_RULES[Status(status)]
    value = {"accel": accel, "baro_altitude": baro_altitude, "dt": dt}[name]
    where = name if index is None or (name == "dt" and not dt_is_array) else f"{name}[{index}]"
    raise ValueError(f"{where} {rule}, got {value!r}")


def raise_reset_error(status: int, baro_altitude: float, accel_bias: float) -> None:
    """Raise the ValueError for a rejected reset, naming the argument."""
    if status == Status.INVALID_BARO_ALTITUDE:
        raise ValueError(f"baro_altitude must be finite (m), got {baro_altitude!r}")
    raise ValueError(f"accel_bias must be finite (m/s²), got {accel_bias!r}")


def raise_settings_error(status: int, gains: Tuple[float, float, float], dt: Optional[float] = None) -> None:
    """Raise the ValueError for rejected gains."""
    kh, kv, kb = gains
    if status == Status.INVALID_GAIN:
        for name, value in zip(("position_gain", "velocity_gain", "bias_gain"), gains):
            if not math.isfinite(value) or value < 0:
                raise ValueError(f"{name} must be finite and >= 0, got {value!r}")
    if status == Status.UNSTABLE_GAINS:
        raise ValueError(
            "gains are unstable: Routh-Hurwitz needs position_gain * velocity_gain > bias_gain "
            f"(and position_gain > 0 when velocity_gain > 0), got {kh!r} * {kv!r} vs {kb!r}")
    if status == Status.UNSTABLE_DISCRETE:
        raise ValueError(f"gains ({kh!r}, {kv!r}, {kb!r}) make the discrete update unstable at dt = {dt!r} s")
    if status == Status.INVALID_DT:
        raise ValueError(f"dt must be finite and > 0 (s), got {dt!r}")
    if status == Status.INVALID_BANDWIDTH:
        raise ValueError("omega and zeta must be finite and > 0, omega_b finite and >= 0, "
                         "and the resulting gains finite")
    raise ValueError(f"invalid settings (status {status})")


def check_preset(name: object) -> int:
    """Return the C preset index of ``name`` or raise ValueError listing the presets."""
    if not isinstance(name, str):
        raise TypeError(f"name must be a str, got {type(name).__name__}")
    try:
        return PRESET_INDEX[name]
    except KeyError:
        raise ValueError(f"name must be one of {', '.join(PRESET_OMEGA)}; got {name!r}") from None


def fastest_pole(position_gain: float, velocity_gain: float, bias_gain: float) -> float:
    """Largest magnitude of the roots of s³ + Kh·s² + Kv·s + Kb, rad/s."""
    roots = np.roots([1.0, position_gain, velocity_gain, bias_gain])
    return float(np.max(np.abs(roots))) if roots.size else 0.0


def warn_if_coarse(gains: Tuple[float, float, float], dt: float, stacklevel: int = 3) -> None:
    """Warn (DiscretisationWarning) when ω·dt ≥ 0.1 for the fastest observer pole ω."""
    omega = fastest_pole(*gains)
    if omega * dt >= OMEGA_DT_ADVICE:
        warnings.warn(
            f"omega * dt = {omega:.3g} * {dt:.3g} s = {omega * dt:.3g} >= {OMEGA_DT_ADVICE}: the discrete "
            "update departs from the continuous-time design; sample faster or lower the gains",
            DiscretisationWarning, stacklevel=stacklevel)


def as_float32_vector(value: object, name: str) -> np.ndarray:
    """A 1-D array-like of reals as a contiguous float32 array, or TypeError/ValueError naming it."""
    array = np.asarray(value)
    if array.dtype.kind not in "fiub":
        raise TypeError(f"{name} must be an array of real numbers, got dtype {array.dtype}")
    if array.ndim != 1:
        raise ValueError(f"{name} must be 1-D, got shape {array.shape}")
    with np.errstate(over="ignore"):
        return np.ascontiguousarray(array, dtype=np.float32)


def prepare_inputs(accel: object, baro_altitude: object, dt: object) -> Tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
    """Convert per-sample inputs to contiguous float32 vectors and check their lengths.

    Returns accel and baro_altitude (length n), dt (length n, or 1 for a
    scalar dt) and whether dt was given per sample.
    """
    accel32 = as_float32_vector(accel, "accel")
    baro32 = as_float32_vector(baro_altitude, "baro_altitude")
    n = accel32.shape[0]
    if baro32.shape[0] != n:
        raise ValueError(f"baro_altitude has {baro32.shape[0]} samples but accel has {n}")
    dt_is_array = np.ndim(dt) != 0
    if dt_is_array:
        dt32 = as_float32_vector(dt, "dt")
        if dt32.shape[0] != n:
            raise ValueError(f"dt has {dt32.shape[0]} samples but accel has {n}")
    else:
        with np.errstate(over="ignore"):
            dt32 = np.array([as_float(dt, "dt")], dtype=np.float32)
    return accel32, baro32, dt32, dt_is_array


def prepare_batch(accel: object, baro_altitude: object, dt: object,
                  out: Optional[Sequence[np.ndarray]]) -> Tuple[np.ndarray, np.ndarray, np.ndarray, bool, AltitudeBatch]:
    """Convert batch inputs to contiguous float32 and check their shapes.

    Returns
    -------
    accel, baro_altitude : numpy.ndarray
        Contiguous float32 vectors of one length n.
    dt : numpy.ndarray
        Contiguous float32 vector of length n, or of length 1 for a scalar dt.
    dt_is_array : bool
        Whether ``dt`` was given per sample.
    out : AltitudeBatch
        The caller's arrays, checked, or new ones.
    """
    accel32, baro32, dt32, dt_is_array = prepare_inputs(accel, baro_altitude, dt)
    n = accel32.shape[0]
    return accel32, baro32, dt32, dt_is_array, output_arrays((n,), out)


def output_arrays(shape: Tuple[int, ...], out: Optional[Sequence[np.ndarray]]) -> AltitudeBatch:
    """New float32 output arrays of ``shape``, or the caller's ``out`` after checking it."""
    if out is None:
        return AltitudeBatch(*(np.empty(shape, dtype=np.float32) for _ in range(4)))
    if len(out) != 4:
        raise ValueError(f"out must hold 4 arrays (altitude, vertical_velocity, accel_bias, baro_residual), got {len(out)}")
    for field, array in zip(AltitudeBatch._fields, out):
        if not isinstance(array, np.ndarray) or array.dtype != np.float32 or array.shape != shape \
                or not array.flags.c_contiguous or not array.flags.writeable:
            raise ValueError(f"out.{field} must be a writeable contiguous float32 array of shape {shape}")
    return AltitudeBatch(*out)


class SweepResult(NamedTuple):
    """What :func:`fusion_altitude.sweep` returns for K settings.

    Attributes
    ----------
    gains : numpy.ndarray
        (K, 3) float32: position_gain (1/s), velocity_gain (1/s²), bias_gain (1/s³).
    metric_samples : int
        Samples that entered the metrics (mask true and reference finite); 0
        without a reference.
    mean_error, rms_error, max_abs_error : numpy.ndarray or None
        (K,) float64 statistics of altitude − reference, m; None without a reference.
    sum_error, sum_squared_error : numpy.ndarray or None
        (K,) float32 sums they come from (m, m²), as the C kernel accumulated them.
    outputs : AltitudeBatch or None
        With ``outputs=True``: (T, K) float32 arrays, column k = setting k.
    """

    gains: np.ndarray
    metric_samples: int
    mean_error: Optional[np.ndarray]
    rms_error: Optional[np.ndarray]
    max_abs_error: Optional[np.ndarray]
    sum_error: Optional[np.ndarray]
    sum_squared_error: Optional[np.ndarray]
    outputs: Optional[AltitudeBatch]


def prepare_sweep(accel: object, baro_altitude: object, dt: object, settings: object, reference: object,
                  mask: object, outputs: bool):
    """Check and convert the arguments of ``sweep``.

    Returns (accel, baro_altitude, dt, dt_is_array, gains (K, 3) float32,
    reference float32 or None, mask uint8 or None).
    """
    accel32, baro32, dt32, dt_is_array = prepare_inputs(accel, baro_altitude, dt)
    n = accel32.shape[0]
    if reference is None and not outputs:
        raise ValueError("nothing to compute: give reference= (for metrics) or outputs=True")
    if isinstance(settings, np.ndarray) and settings.dtype.kind in "fiu":
        rows = settings
    else:
        try:
            rows = [s.as_tuple() if hasattr(s, "as_tuple") else s for s in settings]  # type: ignore[union-attr]
        except TypeError:
            raise TypeError("settings must be a sequence of AltitudeSettings or a (K, 3) gain array") from None
    with np.errstate(over="ignore"):
        gains = np.array(rows, dtype=np.float32).reshape(-1, 3) if len(rows) else np.zeros((0, 3), np.float32)
    if np.ndim(rows) not in (1, 2) or (np.ndim(rows) == 2 and np.shape(rows)[1] != 3):
        raise ValueError(f"settings must be a (K, 3) gain array, got shape {np.shape(rows)}")
    if gains.shape[0] == 0:
        raise ValueError("settings is empty")
    reference32 = None
    mask8 = None
    if reference is not None:
        reference32 = as_float32_vector(reference, "reference")
        if reference32.shape[0] != n:
            raise ValueError(f"reference has {reference32.shape[0]} samples but accel has {n}")
        if mask is not None:
            mask_array = np.asarray(mask)
            if mask_array.dtype != bool or mask_array.shape != (n,):
                raise ValueError(f"mask must be a boolean array of shape ({n},), got {mask_array.dtype} {mask_array.shape}")
            mask8 = np.ascontiguousarray(mask_array.view(np.uint8))
    elif mask is not None:
        raise ValueError("mask needs a reference")
    return accel32, baro32, dt32, dt_is_array, gains, reference32, mask8


def sweep_result(gains: np.ndarray, metric_samples: int, sums: Optional[Tuple[np.ndarray, np.ndarray, np.ndarray]],
                 outputs: Optional[AltitudeBatch]) -> SweepResult:
    """Assemble a SweepResult; mean and RMS in float64 from the float32 sums."""
    if sums is None:
        return SweepResult(gains, 0, None, None, None, None, None, outputs)
    sum_error, sum_squared, max_abs = sums
    with np.errstate(invalid="ignore", divide="ignore"):
        count = float(metric_samples)
        mean = sum_error.astype(np.float64) / count
        rms = np.sqrt(sum_squared.astype(np.float64) / count)
    if metric_samples == 0:
        max_abs = np.full_like(max_abs, np.nan)
    return SweepResult(gains, metric_samples, mean, rms, max_abs.astype(np.float64), sum_error, sum_squared, outputs)


# ----------------------------------------------------------------------------
# Multi-sensor Kalman filter (csrc/fusion_altitude_kalman.h): shared glue of
# fusion_altitude._kalman and fusion_altitude.reference.kalman.

class KalmanStatus(enum.IntEnum):
    """Status codes, equal to the C enum ``FusionAltitudeKalmanStatus``."""

    OK = 0
    INVALID_ACCEL = 1
    INVALID_DT = 2
    INVALID_BARO_ALTITUDE = 3
    INVALID_GPS_ALTITUDE = 4
    INVALID_GPS_ACCURACY = 5
    INVALID_NOISE = 6
    INVALID_RANGE = 7
    INVALID_GPS = 8
    INVALID_GATE = 9
    INVALID_GROUND_EFFECT = 10


class KalmanResult(enum.IntEnum):
    """What an update did with a sensor's sample (C ``FusionAltitudeKalmanResult``)."""

    NO_SAMPLE = 0
    FUSED = 1
    REJECTED = 2
    RESET = 3
    INITIALISED = 4
    UNUSABLE = 5


class KalmanSensors(NamedTuple):
    """One value per altitude sensor."""

    baro: object
    range: object
    gps: object


#: Kalman settings: (Python name, default, kind, status group, rule), in the
#: order of the C struct FusionAltitudeKalmanSettings. kind: "f" float32,
#: "b" bool, "i" int32. Rules: ">=0", ">0", ">=1".
KALMAN_SETTINGS = (
    ("accel_noise", 0.035, "f", KalmanStatus.INVALID_NOISE, ">=0"),
    ("accel_bias_random_walk", 0.003, "f", KalmanStatus.INVALID_NOISE, ">=0"),
    ("accel_bias_initial_sigma", 0.2, "f", KalmanStatus.INVALID_NOISE, ">=0"),
    ("estimate_accel_bias", True, "b", None, None),
    ("baro_noise", 0.5, "f", KalmanStatus.INVALID_NOISE, ">0"),
    ("baro_offset_random_walk", 0.05, "f", KalmanStatus.INVALID_NOISE, ">=0"),
    ("range_noise", 0.05, "f", KalmanStatus.INVALID_NOISE, ">0"),
    ("range_min", 0.1, "f", KalmanStatus.INVALID_RANGE, ">=0"),
    ("range_max", 8.0, "f", KalmanStatus.INVALID_RANGE, ">range_min"),
    ("gps_noise_base", 1.0, "f", KalmanStatus.INVALID_GPS, ">=0"),
    ("gps_noise_satellite", 1.0, "f", KalmanStatus.INVALID_GPS, ">=0"),
    ("gps_min_satellites", 4, "i", KalmanStatus.INVALID_GPS, ">=0"),
    ("gps_offset_random_walk", 0.1, "f", KalmanStatus.INVALID_NOISE, ">=0"),
    ("gate", 5.0, "f", KalmanStatus.INVALID_GATE, ">0"),
    ("rejection_timeout", 1.0, "f", KalmanStatus.INVALID_GATE, ">=0"),
    ("ground_effect_noise_scale", 3.0, "f", KalmanStatus.INVALID_GROUND_EFFECT, ">=1"),
    ("ground_effect_dead_zone", 0.5, "f", KalmanStatus.INVALID_GROUND_EFFECT, ">=0"),
    ("initial_height_sigma", 0.1, "f", KalmanStatus.INVALID_NOISE, ">=0"),
    ("initial_velocity_sigma", 1.0, "f", KalmanStatus.INVALID_NOISE, ">=0"),
)
KALMAN_SETTINGS_NAMES = tuple(name for name, *_ in KALMAN_SETTINGS)
#: FUSION_ALTITUDE_KALMAN_MAXIMUM_SETTING: the largest accepted float setting.
KALMAN_MAXIMUM_SETTING = 1e6
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
        if kind == "f" and math.isfinite(value) and value > KALMAN_MAXIMUM_SETTING:
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


_KALMAN_UPDATE_RULES = {
    KalmanStatus.INVALID_ACCEL: ("accel", "must be finite (m/s²)"),
    KalmanStatus.INVALID_DT: ("dt", "must be finite and > 0 (s)"),
    KalmanStatus.INVALID_BARO_ALTITUDE: ("baro_altitude", "must be finite, or NaN for no sample (m)"),
    KalmanStatus.INVALID_GPS_ALTITUDE: ("gps_altitude", "must be finite, or NaN for no sample (m)"),
    KalmanStatus.INVALID_GPS_ACCURACY: ("gps_vertical_accuracy", "must be finite and > 0 (m), or None/NaN if not reported"),
}


def raise_kalman_update_error(status: int, values: dict, index: Optional[int] = None,
                              is_array: Optional[dict] = None) -> None:
    """Raise the ValueError for a rejected Kalman update, naming the argument (and index in a batch)."""
    name, rule = _KALMAN_UPDATE_RULES[KalmanStatus(status)]
    where = name if index is None or not (is_array or {}).get(name, True) else f"{name}[{index}]"
    raise ValueError(f"{where} {rule}, got {values[name]!r}")


def kalman_satellites(value: object) -> int:
    """gps_satellites of a per-sample update as a C int32: None (unknown) → -1."""
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
    return max(-1, min(n, 2**31 - 1))


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
    return KalmanBatch(*(np.empty(shape, dtype=dtype) for shape, dtype in _kalman_output_layout(n)))


def kalman_output_arrays(n: int, out: Optional[Sequence[np.ndarray]]) -> KalmanBatch:
    """New output arrays for n samples, or the caller's ``out`` (a KalmanBatch of preallocated arrays) after checking it."""
    if out is None:
        return new_kalman_batch(n)
    layout = _kalman_output_layout(n)
    if len(out) != len(layout):
        raise ValueError(f"out must hold {len(layout)} arrays ({', '.join(KalmanBatch._fields)}), got {len(out)}")
    for field, array, (shape, dtype) in zip(KalmanBatch._fields, out, layout):
        if not isinstance(array, np.ndarray) or array.dtype != dtype or array.shape != shape \
                or not array.flags.c_contiguous or not array.flags.writeable:
            raise ValueError(f"out.{field} must be a writeable contiguous {np.dtype(dtype).name} array of shape {shape}")
    return KalmanBatch(*out)


def _kalman_input(value: object, name: str, n: Optional[int], fill: float) -> np.ndarray:
    """A float32 input: None → [fill] (broadcast), scalar → [value], else a contiguous vector of length n."""
    if value is None:
        return np.array([fill], dtype=np.float32)
    if np.ndim(value) == 0:
        with np.errstate(over="ignore"):
            return np.array([as_float(value, name)], dtype=np.float32)
    array = as_float32_vector(value, name)
    if n is not None and array.shape[0] != n:
        raise ValueError(f"{name} has {array.shape[0]} samples but accel has {n}")
    return array


def prepare_kalman_batch(accel, dt, baro_altitude, range_distance, gps_altitude, gps_satellites,
                         gps_vertical_accuracy, ground_effect, out=None):
    """Convert ``update_batch`` inputs. Returns (n, inputs, steps, output): ``inputs``
    maps each argument name to a contiguous array (float32; int32 satellites,
    uint8 ground effect) of length n, or of length 1 for a scalar or None
    (then its entry in ``steps`` is 0, else 1)."""
    accel32 = as_float32_vector(accel, "accel")
    n = accel32.shape[0]
    inputs = {
        "accel": accel32,
        "dt": _kalman_input(dt, "dt", n, math.nan),
        "baro_altitude": _kalman_input(baro_altitude, "baro_altitude", n, math.nan),
        "range_distance": _kalman_input(range_distance, "range_distance", n, math.nan),
        "gps_altitude": _kalman_input(gps_altitude, "gps_altitude", n, math.nan),
        "gps_vertical_accuracy": _kalman_input(gps_vertical_accuracy, "gps_vertical_accuracy", n, math.nan),
    }
    if dt is None:
        raise TypeError("dt must be a real number or an array, got None")
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
            raw = np.where(np.isnan(raw), -1, raw)
        elif raw.dtype.kind not in "iu":
            raise TypeError(f"gps_satellites must be an array of integers, got dtype {raw.dtype}")
        satellites = np.ascontiguousarray(np.clip(raw, -1, 2**31 - 1), dtype=np.int32)
    inputs["gps_satellites"] = satellites
    if ground_effect is None or np.ndim(ground_effect) == 0:
        flags = np.array([bool(ground_effect)], dtype=np.uint8)
    else:
        flags = np.ascontiguousarray(np.asarray(ground_effect, dtype=bool), dtype=np.uint8)
        if flags.ndim != 1 or flags.shape[0] != n:
            raise ValueError(f"ground_effect must be 1-D with {n} samples, got shape {flags.shape}")
    inputs["ground_effect"] = flags
    arguments = {"accel": accel, "dt": dt, "baro_altitude": baro_altitude, "range_distance": range_distance,
                 "gps_altitude": gps_altitude, "gps_satellites": gps_satellites,
                 "gps_vertical_accuracy": gps_vertical_accuracy, "ground_effect": ground_effect}
    steps = {name: 0 if arguments[name] is None or np.ndim(arguments[name]) == 0 else 1 for name in inputs}
    return n, inputs, steps, kalman_output_arrays(n, out)


# ----------------------------------------------------------------------------
# Two-stage complementary filter (csrc/fusion_altitude_complementary.h) and
# quality-weighted alpha-beta fusion (csrc/fusion_altitude_alphabeta.h):
# shared glue of their bindings and references.

class ComplementaryStatus(enum.IntEnum):
    """Status codes, equal to the C enum ``FusionAltitudeComplementaryStatus``."""

    OK = 0
    INVALID_ACCEL = 1
    INVALID_BARO_ALTITUDE = 2
    INVALID_DT = 3
    INVALID_TIME_CONSTANT = 4
    INVALID_COEFFICIENT = 5


class ComplementaryBatch(NamedTuple):
    """Per-sample outputs of ``ComplementaryFilter.update_batch``, each float32, shape (n,).

    Attributes
    ----------
    altitude : numpy.ndarray
        Altitude estimate h, m.
    vertical_velocity : numpy.ndarray
        Vertical velocity estimate v, m/s, +up.
    baro_filtered : numpy.ndarray
        Low-passed baro altitude, m.
    baro_velocity : numpy.ndarray
        Finite-difference baro velocity, m/s; NaN on steps without baro.
    """

    altitude: np.ndarray
    vertical_velocity: np.ndarray
    baro_filtered: np.ndarray
    baro_velocity: np.ndarray


#: Complementary settings in the order of the C struct: (name, default, kind).
#: kind "t": time constant s (finite, >= 0); "c": coefficient in [0, 1]; "b": bool.
COMPLEMENTARY_SETTINGS = (
    ("accel_time_constant", 0.02, "t"),
    ("baro_time_constant", 0.05, "t"),
    ("per_sample_coefficients", False, "b"),
    ("velocity_coefficient", 0.999, "c"),
    ("altitude_coefficient", 0.998, "c"),
    ("velocity_time_constant", 9.99, "t"),
    ("altitude_time_constant", 4.99, "t"),
)
COMPLEMENTARY_SETTINGS_NAMES = tuple(name for name, _, _ in COMPLEMENTARY_SETTINGS)
COMPLEMENTARY_SETTINGS_DEFAULTS = {name: default for name, default, _ in COMPLEMENTARY_SETTINGS}


def convert_complementary_settings(kwargs: dict) -> dict:
    """Settings keyword arguments → dict of Python values of the C types (float32-rounded floats, bool)."""
    unknown = set(kwargs) - set(COMPLEMENTARY_SETTINGS_NAMES)
    if unknown:
        raise TypeError(f"unknown complementary setting(s): {', '.join(sorted(unknown))}")
    values = {}
    for name, default, kind in COMPLEMENTARY_SETTINGS:
        value = kwargs.get(name, default)
        if kind == "b":
            if not isinstance(value, (bool, np.bool_)):
                raise TypeError(f"{name} must be a bool, got {type(value).__name__}")
            values[name] = bool(value)
        else:
            with np.errstate(over="ignore"):
                values[name] = float(np.float32(as_float(value, name)))
    return values


def raise_complementary_settings_error(status: int, values: dict) -> None:
    """Raise the ValueError for rejected complementary settings, naming the first bad field."""
    for name, _, kind in COMPLEMENTARY_SETTINGS:
        value = values[name]
        if kind == "t" and status == ComplementaryStatus.INVALID_TIME_CONSTANT:
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(f"{name} must be finite and >= 0 (s), got {value!r}")
        if kind == "c" and status == ComplementaryStatus.INVALID_COEFFICIENT:
            if not (math.isfinite(value) and 0 <= value <= 1):
                raise ValueError(f"{name} must be finite and in [0, 1], got {value!r}")
    raise ValueError(f"invalid complementary settings (status {status})")


_COMPLEMENTARY_UPDATE_RULES = {
    ComplementaryStatus.INVALID_ACCEL: ("accel", "must be finite (m/s²)"),
    ComplementaryStatus.INVALID_BARO_ALTITUDE: ("baro_altitude", "must be finite, or NaN for no baro sample (m)"),
    ComplementaryStatus.INVALID_DT: ("dt", "must be finite and > 0 (s)"),
}


def raise_complementary_update_error(status: int, accel: float, baro_altitude: float, dt: float,
                                     index: Optional[int] = None, dt_is_array: bool = False) -> None:
    """Raise the ValueError for a rejected complementary update, naming the argument (and index)."""
    name, rule = _COMPLEMENTARY_UPDATE_RULES[ComplementaryStatus(status)]
    value = {"accel": accel, "baro_altitude": baro_altitude, "dt": dt}[name]
    where = name if index is None or (name == "dt" and not dt_is_array) else f"{name}[{index}]"
    raise ValueError(f"{where} {rule}, got {value!r}")


def complementary_outputs(n: int, out: Optional[Sequence[np.ndarray]]) -> ComplementaryBatch:
    """New float32 output arrays of length n, or the caller's ``out`` after checking it."""
    if out is None:
        return ComplementaryBatch(*(np.empty(n, dtype=np.float32) for _ in range(4)))
    if len(out) != 4:
        raise ValueError(f"out must hold 4 arrays ({', '.join(ComplementaryBatch._fields)}), got {len(out)}")
    for field, array in zip(ComplementaryBatch._fields, out):
        if not isinstance(array, np.ndarray) or array.dtype != np.float32 or array.shape != (n,) \
                or not array.flags.c_contiguous or not array.flags.writeable:
            raise ValueError(f"out.{field} must be a writeable contiguous float32 array of shape ({n},)")
    return ComplementaryBatch(*out)


class AlphaBetaStatus(enum.IntEnum):
    """Status codes, equal to the C enum ``FusionAltitudeAlphaBetaStatus``."""

    OK = 0
    INVALID_ACCEL = 1
    INVALID_DT = 2
    INVALID_BARO_ALTITUDE = 3
    INVALID_LIDAR_ALTITUDE = 4
    INVALID_SONAR_ALTITUDE = 5
    INVALID_GPS_ALTITUDE = 6
    INVALID_THRESHOLD = 7
    INVALID_QUALITY = 8
    INVALID_CONFIDENCE = 9
    INVALID_ALTITUDE_BAND = 10
    INVALID_GAP_MAX = 11
    INVALID_TIMEOUT = 12


#: Sensor channels of the alpha-beta fusion, in the C index order.
ALPHABETA_SENSORS = ("imu", "baro", "lidar", "sonar", "gps")
#: Largest accepted quality (FUSION_ALTITUDE_ALPHABETA_MAX_QUALITY).
ALPHABETA_MAX_QUALITY = 10000


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


_INF = math.inf
#: The write-up's tables, plus the values it does not give (see csrc/fusion_altitude_alphabeta.h).
ALPHABETA_DEFAULTS = {
    "imu": AlphaBetaSensorSettings(1.0, 2, 4, 5.0, -1.0, _INF, 4.0, 1.5),
    "baro": AlphaBetaSensorSettings(1.0, 10, 60, 2.0, -4.0, _INF, 10.0, 1.5),
    "lidar": AlphaBetaSensorSettings(0.5, 2, 8, 10.0, 0.0, 40.0, 6.0, 1.5),
    "sonar": AlphaBetaSensorSettings(0.5, 2, 8, 10.0, 0.0, 5.0, 6.0, 1.5),
    "gps": AlphaBetaSensorSettings(10.0, 10, 120, 1.0, -10.0, _INF, 20.0, 1.5),
}


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


def convert_alphabeta_settings(kwargs: dict) -> dict:
    """``AlphaBetaSettings(**kwargs)`` arguments → {sensor: AlphaBetaSensorSettings of C-typed values}.

    Each sensor's argument is None (defaults), an AlphaBetaSensorSettings, or
    a mapping of the fields to change from the defaults.
    """
    unknown = set(kwargs) - set(ALPHABETA_SENSORS)
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
        if not (math.isfinite(s.confidence) and s.confidence >= 0):
            raise ValueError(f"{where}.confidence must be finite and >= 0, got {s.confidence!r}")
        if not s.altitude_min < s.altitude_max:
            raise ValueError(f"{where}.altitude_min must be < altitude_max (m, infinite allowed), "
                             f"got {s.altitude_min!r} and {s.altitude_max!r}")
        if not s.gap_max > 0:
            raise ValueError(f"{where}.gap_max must be > 0 (m, inf: no limit), got {s.gap_max!r}")
        if not (math.isfinite(s.timeout) and s.timeout > 0):
            raise ValueError(f"{where}.timeout must be finite and > 0 (s), got {s.timeout!r}")
    raise ValueError(f"invalid alpha-beta settings (status {status})")


_ALPHABETA_UPDATE_RULES = {
    AlphaBetaStatus.INVALID_ACCEL: ("accel", "must be finite, or NaN for no IMU sample (m/s²)"),
    AlphaBetaStatus.INVALID_DT: ("dt", "must be finite and > 0 (s)"),
    AlphaBetaStatus.INVALID_BARO_ALTITUDE: ("baro_altitude", "must be finite, or NaN for no sample (m)"),
    AlphaBetaStatus.INVALID_LIDAR_ALTITUDE: ("lidar_altitude", "must be finite, or NaN for no sample (m)"),
    AlphaBetaStatus.INVALID_SONAR_ALTITUDE: ("sonar_altitude", "must be finite, or NaN for no sample (m)"),
    AlphaBetaStatus.INVALID_GPS_ALTITUDE: ("gps_altitude", "must be finite, or NaN for no sample (m)"),
}
#: update_batch's per-step inputs, in the order of the C call.
ALPHABETA_INPUTS = ("accel", "dt", "baro_altitude", "lidar_altitude", "sonar_altitude", "gps_altitude")


def raise_alphabeta_update_error(status: int, values: dict, index: Optional[int] = None,
                                 is_array: Optional[dict] = None) -> None:
    """Raise the ValueError for a rejected alpha-beta update, naming the argument (and index in a batch)."""
    name, rule = _ALPHABETA_UPDATE_RULES[AlphaBetaStatus(status)]
    where = name if index is None or not (is_array or {}).get(name, True) else f"{name}[{index}]"
    raise ValueError(f"{where} {rule}, got {values[name]!r}")


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


def prepare_alphabeta_batch(accel, dt, baro_altitude, lidar_altitude, sonar_altitude, gps_altitude):
    """Convert ``update_batch`` inputs. Returns (n, inputs, steps, output): ``inputs`` maps each
    name of :data:`ALPHABETA_INPUTS` to a contiguous float32 array of length n, or of length 1 for a
    scalar or None (then its entry in ``steps`` is 0, else 1)."""
    if dt is None:
        raise TypeError("dt must be a real number or an array, got None")
    accel32 = as_float32_vector(accel, "accel")
    n = accel32.shape[0]
    arguments = {"accel": accel, "dt": dt, "baro_altitude": baro_altitude, "lidar_altitude": lidar_altitude,
                 "sonar_altitude": sonar_altitude, "gps_altitude": gps_altitude}
    inputs = {"accel": accel32}
    for name in ALPHABETA_INPUTS[1:]:
        value = arguments[name]
        if value is None:
            inputs[name] = np.array([math.nan], dtype=np.float32)
        elif np.ndim(value) == 0:
            with np.errstate(over="ignore"):
                inputs[name] = np.array([as_float(value, name)], dtype=np.float32)
        else:
            array = as_float32_vector(value, name)
            if array.shape[0] != n:
                raise ValueError(f"{name} has {array.shape[0]} samples but accel has {n}")
            inputs[name] = array
    steps = {name: 0 if arguments[name] is None or np.ndim(arguments[name]) == 0 else 1 for name in ALPHABETA_INPUTS}
    output = AlphaBetaBatch(np.empty(n, dtype=np.float32), np.empty(n, dtype=np.float32),
                            np.empty((n, 5), dtype=np.float32), np.empty((n, 5), dtype=np.int32))
    return n, inputs, steps, output
