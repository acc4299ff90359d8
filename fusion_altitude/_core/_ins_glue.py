"""Glue of the inertial navigation filter shared by its binding (``_ins.pyx``)
and its reference (``reference/ins.py``): the settings rules (the table and the
status enum are generated from the header into ``_c_tables``), unit
conversion, input checks with messages that name the argument (and the first
bad index), and the batch result type. No algorithm here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, Optional, Tuple

import numpy as np

from . import _c_tables
from ._c_tables import InsStatus
from ._common import GRAVITY, as_float, check_no_overlap

#: Largest accepted setting and input magnitude (FUSION_ALTITUDE_INS_MAXIMUM).
MAXIMUM = np.float32(_c_tables.FUSION_ALTITUDE_INS_MAXIMUM)


#: Settings the C check wants > 0 (FusionAltitudeInsSettingsCheck); the others >= 0, all finite and <= 1e6: the
#: ``[rule: ...]`` of each field's comment in the header (:data:`fusion_altitude._c_tables.INS_RULES`).
POSITIVE_SETTINGS = frozenset(name for name, (_, terms) in _c_tables.INS_RULES.items() if (">", 0) in terms)

#: INS settings: (Python name, C name, default, rule), in the order of the C struct FusionAltitudeInsSettings,
#: the defaults read from the header (:mod:`fusion_altitude._c_tables`). Rules: ">=0" finite in [0, 1e6],
#: ">0" in (0, 1e6].
INS_SETTINGS = tuple((name, c_name, default, ">0" if name in POSITIVE_SETTINGS else ">=0")
                     for name, c_name, _, default, _ in _c_tables.INS_SETTINGS)

INS_SETTINGS_NAMES = tuple(row[0] for row in INS_SETTINGS)

#: Units accepted for the inputs, and their factor to rad/s and m/s².
GYRO_UNITS = {"rad/s": 1.0, "deg/s": math.pi / 180.0, "°/s": math.pi / 180.0, "dps": math.pi / 180.0}
ACCEL_UNITS = {"m/s^2": 1.0, "m/s²": 1.0, "g": GRAVITY}


#: The C settings functions the settings class calls instead of the twins here, once the binding (``_ins.pyx``)
#: registers them at import: ``"check"`` → ``c_settings_check`` (the twin: :func:`check_ins_settings`). Without
#: the compiled extension it stays empty (``tests/test_settings_checks.py`` holds the twin equal to C).
C_SETTINGS_FUNCTIONS: dict = {}


def _in_range(value: np.float32, rule: str) -> bool:
    """A setting's rule: finite in [0, 1e6] (">=0") or in (0, 1e6] (">0")."""
    return bool(np.isfinite(value)) and value <= MAXIMUM and bool(value > 0 if rule == ">0" else value >= 0)


def check_ins_settings(values: Dict[str, np.float32]) -> InsStatus:
    """The twin of FusionAltitudeInsSettingsCheck on float32 values."""
    ok = all(_in_range(values[name], rule) for name, _, _, rule in INS_SETTINGS)
    return InsStatus.OK if ok else InsStatus.INVALID_SETTINGS


def convert_ins_settings(values: Dict[str, object]) -> Dict[str, np.float32]:
    """Defaults filled in, every value float32 and in range; ValueError/TypeError naming the first bad setting."""
    unknown = sorted(set(values) - set(INS_SETTINGS_NAMES))
    if unknown:
        raise TypeError(f"unknown INS setting {unknown[0]!r}; valid: {', '.join(INS_SETTINGS_NAMES)}")
    result = {name: np.float32(as_float(values.get(name, default), name)) for name, _, default, _ in INS_SETTINGS}
    if C_SETTINGS_FUNCTIONS.get("check", check_ins_settings)(result) != InsStatus.OK:
        for name, _, _, rule in INS_SETTINGS:
            if not _in_range(result[name], rule):
                bound = "(0, 1e6]" if rule == ">0" else "[0, 1e6]"
                raise ValueError(f"{name} must be finite in {bound}, got {float(result[name])!r}")
        raise ValueError("invalid INS settings")
    return result


def unit_scale(units: str, table: Dict[str, float], name: str) -> float:
    """Factor from ``units`` to the SI unit, or ValueError naming the argument."""
    if units not in table:
        raise ValueError(f"{name} must be one of {', '.join(repr(k) for k in table)}; got {units!r}")
    return table[units]


def _bounded(array: np.ndarray) -> np.ndarray:
    with np.errstate(invalid="ignore"):
        return np.isfinite(array) & (np.abs(array) <= MAXIMUM)


def as_vector(value: object, scale: float, name: str) -> np.ndarray:
    """One 3-vector as float32 (value × scale computed in double), TypeError/ValueError naming it."""
    array = np.asarray(value)
    if array.dtype.kind not in "fiub":
        raise TypeError(f"{name} must be 3 real numbers, got dtype {array.dtype}")
    if array.shape != (3,):
        raise ValueError(f"{name} must have 3 components (x, y, z), got shape {array.shape}")
    with np.errstate(over="ignore", invalid="ignore"):
        return (array.astype(np.float64) * scale).astype(np.float32)


def check_step(gyro: np.ndarray, accel: np.ndarray, mag: np.ndarray, baro: np.float32, dt: np.float32) -> InsStatus:
    """The C FusionAltitudeInsCheckInputs on float32 values (the first bad input decides)."""
    if not _bounded(gyro).all():
        return InsStatus.INVALID_GYRO
    if not _bounded(accel).all():
        return InsStatus.INVALID_ACCEL
    if not (np.isnan(mag).all() or _bounded(mag).all()):
        return InsStatus.INVALID_MAG
    if not (np.isnan(baro) or _bounded(np.asarray(baro))):
        return InsStatus.INVALID_BARO_ALTITUDE
    if not (np.isfinite(dt) and dt > 0):
        return InsStatus.INVALID_DT
    return InsStatus.OK


_MESSAGES = {
    InsStatus.INVALID_GYRO: ("gyro", "components must be finite with magnitude <= 1e6 rad/s"),
    InsStatus.INVALID_ACCEL: ("accel", "components must be finite with magnitude <= 1e6 m/s²"),
    InsStatus.INVALID_MAG: ("mag", "must be None / all NaN (no sample) or 3 finite components with magnitude <= 1e6"),
    InsStatus.INVALID_BARO_ALTITUDE: ("baro_altitude", "must be finite with magnitude <= 1e6 m, or NaN for no sample"),
    InsStatus.INVALID_DT: ("dt", "must be finite and > 0 s"),
}


def raise_step_error(status: InsStatus, values: Dict[str, object], index: Optional[int] = None) -> None:
    """ValueError naming the argument (``name[index]`` of the first bad step in a batch); the state is unchanged."""
    name, rule = _MESSAGES[InsStatus(status)]
    where = f"{name}[{index}]" if index is not None else name
    raise ValueError(f"{where} {rule}; got {values[name]!r} (state unchanged)")


def step_inputs(gyro, accel, dt, baro_altitude, mag, gyro_scale, accel_scale):
    """Convert one step's arguments to float32 (gyro, accel, mag 3-vectors, baro, dt) and check them."""
    g = as_vector(gyro, gyro_scale, "gyro")
    a = as_vector(accel, accel_scale, "accel")
    m = np.full(3, np.nan, dtype=np.float32) if mag is None else as_vector(mag, 1.0, "mag")
    b = np.float32(as_float(baro_altitude, "baro_altitude"))
    t = np.float32(as_float(dt, "dt"))
    status = check_step(g, a, m, b, t)
    if status != InsStatus.OK:
        raise_step_error(status, {"gyro": g.tolist(), "accel": a.tolist(), "mag": m.tolist(),
                                  "baro_altitude": float(b), "dt": float(t)})
    return g, a, m, b, t


def _matrix(value: object, n: Optional[int], scale: float, name: str) -> np.ndarray:
    array = np.asarray(value)
    if array.dtype.kind not in "fiub":
        raise TypeError(f"{name} must be an array of real numbers, got dtype {array.dtype}")
    if array.ndim != 2 or array.shape[1] != 3 or (n is not None and array.shape[0] != n):
        expected = f"({n}, 3)" if n is not None else "(N, 3)"
        raise ValueError(f"{name} must have shape {expected}, got {array.shape}")
    if scale == 1.0 and array.dtype == np.float32:  # x * 1.0 in double, back to float32: the same bits
        return np.ascontiguousarray(array)
    with np.errstate(over="ignore", invalid="ignore"):
        return np.ascontiguousarray(array.astype(np.float64) * scale, dtype=np.float32)


def _column(value: object, n: int, name: str, default: float) -> np.ndarray:
    if value is None:
        return np.full(n, default, dtype=np.float32)
    array = np.asarray(value)
    if array.dtype.kind not in "fiub":
        raise TypeError(f"{name} must be real numbers, got dtype {array.dtype}")
    if array.ndim == 0:
        array = np.full(n, array)
    if array.shape != (n,):
        raise ValueError(f"{name} must be a scalar or have shape ({n},), got {array.shape}")
    with np.errstate(over="ignore", invalid="ignore"):
        return np.ascontiguousarray(array, dtype=np.float32)


@dataclass
class InsBatch:
    """The INS state after each step of a batch (float32 unless stated).

    Attributes
    ----------
    height_above_start : numpy.ndarray
        Height above the reference d (≈ 0 at the first baro sample), m, +up, shape (N,).
    vertical_velocity : numpy.ndarray
        m/s, +up, shape (N,).
    quaternion : numpy.ndarray
        Local attitude (w, x, y, z), body → local NWU earth, shape (N, 4).
    global_quaternion : numpy.ndarray
        Global attitude (yaw from the magnetometer), shape (N, 4).
    gyro_bias : numpy.ndarray
        rad/s, body frame, shape (N, 3).
    accel_z_bias : numpy.ndarray
        m/s², body z, shape (N,).
    baro_bias : numpy.ndarray
        m (baro altitude at d = 0), shape (N,).
    is_stationary : numpy.ndarray
        bool, shape (N,).
    baro_timed_out : numpy.ndarray
        bool, shape (N,): not baro-aided, no baro reading for longer than ``baro_timeout`` s
        (``InsEstimator.baro_timed_out`` after each step).

    Notes
    -----
    ``altitude`` (a property, not a field) is in the baro's datum, ``height_above_start + baro_bias``, as every
    estimator's; in 0.1.0 the first field was named ``altitude`` and held the height (docs/ins.md). The fields, and
    so ``tuple(batch)`` and the sequence ``out=`` takes, are the state the C loop writes.
    """

    height_above_start: np.ndarray
    vertical_velocity: np.ndarray
    quaternion: np.ndarray
    global_quaternion: np.ndarray
    gyro_bias: np.ndarray
    accel_z_bias: np.ndarray
    baro_bias: np.ndarray
    is_stationary: np.ndarray
    baro_timed_out: np.ndarray

    def __iter__(self):
        """The arrays in field order, as for the other estimators' batch results (``tuple(batch)``)."""
        return iter((self.height_above_start, self.vertical_velocity, self.quaternion, self.global_quaternion,
                     self.gyro_bias, self.accel_z_bias, self.baro_bias, self.is_stationary, self.baro_timed_out))

    @property
    def altitude(self) -> np.ndarray:
        """Altitude in the baro's datum, m, +up, shape (N,): ``height_above_start + baro_bias`` (float32), as
        ``run -o`` writes it; a new array on each access."""
        return self.height_above_start + self.baro_bias

    @property
    def baro_datum_altitude(self) -> np.ndarray:
        """The same as :attr:`altitude` (altitude in the baro's datum, m, shape (N,)), kept from the release that
        added it."""
        return self.altitude

    @classmethod
    def empty(cls, n: int) -> "InsBatch":
        """Newly allocated outputs for n steps."""
        f = np.float32
        return cls(np.empty(n, f), np.empty(n, f), np.empty((n, 4), f), np.empty((n, 4), f), np.empty((n, 3), f),
                   np.empty(n, f), np.empty(n, f), np.empty(n, np.bool_), np.empty(n, np.bool_))

    @property
    def euler(self) -> np.ndarray:
        """Local roll, pitch, yaw, degrees, shape (N, 3) (ZYX convention, as imufusion)."""
        return quaternion_to_euler(self.quaternion)

    @property
    def global_euler(self) -> np.ndarray:
        """Global roll, pitch, yaw (yaw from the magnetometer), degrees, shape (N, 3)."""
        return quaternion_to_euler(self.global_quaternion)


_SHAPES = {"height_above_start": ((), np.float32), "vertical_velocity": ((), np.float32),
           "quaternion": ((4,), np.float32), "global_quaternion": ((4,), np.float32), "gyro_bias": ((3,), np.float32), "accel_z_bias": ((), np.float32),
           "baro_bias": ((), np.float32), "is_stationary": ((), np.bool_), "baro_timed_out": ((), np.bool_)}


def prepare_batch(gyro, accel, dt, baro_altitude, mag, out, gyro_scale, accel_scale, check=True):
    """Convert and check a batch; returns (n, inputs dict of contiguous float32 arrays, InsBatch).

    Every step is checked before any is applied, so a bad one raises naming
    the argument and its first bad index with the state untouched. check=False
    (the compiled estimator) leaves the per-step checks to the C loop, which
    makes the same ones in the same order (see step_error).
    """
    g = _matrix(gyro, None, gyro_scale, "gyro")
    n = g.shape[0]
    a = _matrix(accel, n, accel_scale, "accel")
    m = np.full((n, 3), np.nan, dtype=np.float32) if mag is None else _matrix(mag, n, 1.0, "mag")
    b = _column(baro_altitude, n, "baro_altitude", np.nan)
    t = _column(dt, n, "dt", np.nan)
    if not check:
        return n, {"gyro": g, "accel": a, "mag": m, "baro_altitude": b, "dt": t}, _check_out(out, n)
    bad = {
        "gyro": ~_bounded(g).all(axis=1),
        "accel": ~_bounded(a).all(axis=1),
        "mag": ~(np.isnan(m).all(axis=1) | _bounded(m).all(axis=1)),
        "baro_altitude": ~(np.isnan(b) | _bounded(b)),
        "dt": ~(np.isfinite(t) & (t > 0)),
    }
    statuses = {"gyro": InsStatus.INVALID_GYRO, "accel": InsStatus.INVALID_ACCEL, "mag": InsStatus.INVALID_MAG,
                "baro_altitude": InsStatus.INVALID_BARO_ALTITUDE, "dt": InsStatus.INVALID_DT}
    any_bad = np.zeros(n, dtype=bool)
    for flags in bad.values():
        any_bad |= flags
    if any_bad.any():
        index = int(np.argmax(any_bad))
        for name, flags in bad.items():  # the C check order: gyro, accel, mag, baro, dt
            if flags[index]:
                values = {"gyro": g[index].tolist(), "accel": a[index].tolist(), "mag": m[index].tolist(),
                          "baro_altitude": float(b[index]), "dt": float(t[index])}
                raise_step_error(statuses[name], values, index)
    return n, {"gyro": g, "accel": a, "mag": m, "baro_altitude": b, "dt": t}, _check_out(out, n)


def _check_out(out, n: int) -> "InsBatch":
    """out, checked (shapes, dtypes, C-contiguous, writeable), or new arrays when None."""
    if out is None:
        return InsBatch.empty(n)
    if not isinstance(out, InsBatch):  # any sequence of the nine arrays, in InsBatch's order, as for every batch
        try:
            fields = list(out)
        except TypeError:
            raise TypeError(f"out must be an InsBatch or a sequence of its 9 arrays, got {type(out).__name__}") \
                from None
        if len(fields) != 9:
            raise TypeError(f"out must be an InsBatch or a sequence of its 9 arrays, got {len(fields)} items")
        out = InsBatch(*fields)
    for field, (tail, dtype) in _SHAPES.items():
        array = getattr(out, field)
        if not (isinstance(array, np.ndarray) and array.shape == (n, *tail) and array.dtype == dtype
                and array.flags.c_contiguous and array.flags.writeable):
            raise ValueError(f"out.{field} must be a writeable C-contiguous {np.dtype(dtype).name} array of shape "
                             f"{(n, *tail)}")
    check_no_overlap({field: getattr(out, field) for field in _SHAPES})
    return out


def batch_step_error(status: int, inputs: Dict[str, np.ndarray], index: int) -> None:
    """The ValueError of prepare_batch for step index rejected with status by the C loop (its first bad step: the
    loop stops there, and the C check order gyro, accel, mag, baro, dt is prepare_batch's)."""
    values = {"gyro": inputs["gyro"][index].tolist(), "accel": inputs["accel"][index].tolist(),
              "mag": inputs["mag"][index].tolist(), "baro_altitude": float(inputs["baro_altitude"][index]),
              "dt": float(inputs["dt"][index])}
    raise_step_error(InsStatus(status), values, index)


def quaternion_to_euler(quaternion) -> np.ndarray:
    """Roll, pitch, yaw (degrees, ZYX) of quaternions (w, x, y, z), in double; shape (..., 3)."""
    q = np.asarray(quaternion, dtype=np.float64)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    roll = np.arctan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    pitch = np.arcsin(np.clip(2.0 * (w * y - z * x), -1.0, 1.0))
    yaw = np.arctan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return np.degrees(np.stack([roll, pitch, yaw], axis=-1))


def units_tuple(gyro_units: str, accel_units: str) -> Tuple[float, float]:
    """(gyro factor to rad/s, accel factor to m/s²), ValueError naming a bad unit."""
    return unit_scale(gyro_units, GYRO_UNITS, "gyro_units"), unit_scale(accel_units, ACCEL_UNITS, "accel_units")
