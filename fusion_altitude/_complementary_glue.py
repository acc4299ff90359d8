"""Glue of the two-stage complementary filter shared by its binding
(``_complementary.pyx``) and its reference (``reference/complementary.py``).
"""

from __future__ import annotations

import enum
import math
from typing import NamedTuple, Optional, Sequence

import numpy as np

from ._common import as_float


class ComplementaryStatus(enum.IntEnum):
    """Status codes, equal to the C enum ``FusionAltitudeComplementaryStatus``."""

    OK = 0
    INVALID_ACCEL = 1
    INVALID_BARO_ALTITUDE = 2
    INVALID_DT = 3
    INVALID_TIME_CONSTANT = 4
    INVALID_COEFFICIENT = 5
    INVALID_GAP_PERIOD = 6


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
#: kind "t": time constant s (finite, >= 0); "c": coefficient in [0, 1]; "b": bool; "g": gap period s (> 0).
COMPLEMENTARY_SETTINGS = (
    ("accel_time_constant", 0.02, "t"),
    ("baro_time_constant", 0.05, "t"),
    ("per_sample_coefficients", False, "b"),
    ("velocity_coefficient", 0.999, "c"),
    ("altitude_coefficient", 0.998, "c"),
    ("velocity_time_constant", 9.99, "t"),
    ("altitude_time_constant", 4.99, "t"),
    ("gap_period", 0.5, "g"),
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
        if kind == "g" and status == ComplementaryStatus.INVALID_GAP_PERIOD:
            raise ValueError(f"{name} must be > 0 (s; inf: never a gap), got {value!r}")
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
