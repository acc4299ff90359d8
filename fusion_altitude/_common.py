"""Python-side helpers shared by every binding and reference: argument conversion.

Nothing here is part of an algorithm; the algorithms live in ``csrc/`` and,
for reading, in :mod:`fusion_altitude.reference`.
"""

from __future__ import annotations

import numpy as np


#: Standard gravity, m/s². Multiply an acceleration in g by this.
GRAVITY = 9.80665


def as_float(value: object, name: str) -> float:
    """Return ``value`` as a Python float, or raise TypeError naming ``name``."""
    if isinstance(value, float):
        return value
    kind = type(value)
    if hasattr(kind, "__float__") or hasattr(kind, "__index__"):  # as CPython's PyFloat_AsDouble
        return float(value)  # type: ignore[arg-type]
    raise TypeError(f"{name} must be a real number, got {kind.__name__}")


def as_float32_vector(value: object, name: str) -> np.ndarray:
    """A 1-D array-like of reals as a contiguous float32 array, or TypeError/ValueError naming it."""
    array = np.asarray(value)
    if array.dtype.kind not in "fiub":
        raise TypeError(f"{name} must be an array of real numbers, got dtype {array.dtype}")
    if array.ndim != 1:
        raise ValueError(f"{name} must be 1-D, got shape {array.shape}")
    with np.errstate(over="ignore"):
        return np.ascontiguousarray(array, dtype=np.float32)
