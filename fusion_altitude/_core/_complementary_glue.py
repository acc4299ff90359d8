"""Glue of the two-stage complementary filter shared by its binding
(``_complementary.pyx``) and its reference (``reference/complementary.py``).
"""

from __future__ import annotations

import math
from typing import NamedTuple, Optional, Sequence

import numpy as np

from . import _c_tables
from ._c_tables import ComplementaryStatus
from ._common import (ACCEL_FINITE, BARO_SAMPLE_OR_NAN, DT_POSITIVE, as_float, batch_raises_and_notes, input_rules,
                      output_arrays, raise_input_error)


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


#: The kind of a setting by the status its rule gives (``_c_tables.COMPLEMENTARY_RULES``, from the header).
_KINDS = {ComplementaryStatus.INVALID_TIME_CONSTANT: "t", ComplementaryStatus.INVALID_COEFFICIENT: "c",
          ComplementaryStatus.INVALID_GAP_PERIOD: "g", ComplementaryStatus.INVALID_BARO_TIMEOUT: "o", None: "b"}

#: Complementary settings in the order of the C struct: (name, default, kind), the defaults and rules read from
#: the header (:mod:`fusion_altitude._c_tables`). kind "t": time constant s (finite, >= 0); "c":
#: coefficient in [0, 1]; "b": bool; "g": gap period s (> 0, inf: never a gap); "o": baro timeout s (> 0, inf:
#: never times out).
COMPLEMENTARY_SETTINGS = tuple((name, default, _KINDS[_c_tables.COMPLEMENTARY_RULES[name][0]])
                               for name, _, _, default, _ in _c_tables.COMPLEMENTARY_SETTINGS)


COMPLEMENTARY_SETTINGS_NAMES = tuple(name for name, _, _ in COMPLEMENTARY_SETTINGS)


COMPLEMENTARY_SETTINGS_DEFAULTS = {name: default for name, default, _ in COMPLEMENTARY_SETTINGS}


#: The C settings functions the settings class calls instead of the reference's arithmetic twins, once the
#: binding (``_complementary.pyx``) registers them at import: ``"check"`` → ``c_settings_check`` (the twin:
#: ``reference/complementary.py``'s ``_check``). Without the compiled extension it stays empty
#: (``tests/test_settings_checks.py`` holds each twin equal to C).
C_SETTINGS_FUNCTIONS: dict = {}


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
        if kind == "o" and status == ComplementaryStatus.INVALID_BARO_TIMEOUT:
            raise ValueError(f"{name} must be > 0 (s; inf: never times out), got {value!r}")
    raise ValueError(f"invalid complementary settings (status {status})")


_COMPLEMENTARY_UPDATE_RULES = input_rules(ComplementaryStatus, accel=ACCEL_FINITE, baro_altitude=BARO_SAMPLE_OR_NAN,
                                          dt=DT_POSITIVE)


def raise_complementary_update_error(status: int, accel: float, baro_altitude: float, dt: float,
                                     index: Optional[int] = None, dt_is_array: bool = False) -> None:
    """Raise the ValueError for a rejected complementary update, naming the argument (and index)."""
    raise_input_error(_COMPLEMENTARY_UPDATE_RULES, status, {"accel": accel, "baro_altitude": baro_altitude, "dt": dt},
                      index, {"dt": dt_is_array})


def complementary_outputs(n: int, out: Optional[Sequence[np.ndarray]]) -> ComplementaryBatch:
    """New float32 output arrays of length n, or the caller's ``out`` after checking it."""
    return output_arrays(ComplementaryBatch, [((n,), np.float32)] * 4, out)


class ComplementaryContract:
    """The ``update_batch`` docstring of the ComplementaryFilter binding (its Raises and Notes shared with the other
    bindings through ``_common.batch_raises_and_notes``): ``_common.share_docstrings`` gives it to the binding."""

    def update_batch(self, accel, baro_altitude, dt, out=None) -> ComplementaryBatch:
        raise NotImplementedError

    update_batch.__doc__ = """Process arrays of samples, continuing from the current state.

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
        ComplementaryBatch""" + batch_raises_and_notes("sample")
