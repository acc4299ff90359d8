"""Glue of the complementary observer shared by its binding (``_observer.pyx``)
and its reference (``reference/observer.py``): presets, statuses, error
messages that name the argument, batch argument conversion and the result type.
"""

from __future__ import annotations

import enum
import math
import warnings
from typing import NamedTuple, Optional, Sequence, Tuple

import numpy as np

from ._common import as_float, as_float32_vector


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
    INVALID_GAP_PERIOD = 10


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
    if status == Status.INVALID_GAP_PERIOD:
        raise ValueError("gap_period must be > 0 s (inf: never a gap)")
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
