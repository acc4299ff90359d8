"""Sensor conversions: pressure ↔ altitude and body-frame accel → vertical accel.

Everything here is vectorised over numpy arrays and uses SI units unless a
name or argument says otherwise. Vertical is +up in every output.

Frames and signs
----------------
An accelerometer measures *specific force*: acceleration minus gravity. At rest
and level it reads +1 g along the body axis that points **up**:

* ``"NED"`` (body x forward, y right, z **down**): at rest it reads
  (0, 0, −9.81) m/s²;
* ``"ENU"`` / ``"NWU"`` (body z **up**): at rest it reads (0, 0, +9.81) m/s².

:func:`vertical_acceleration` rotates the body-frame specific force into the
earth frame with the attitude, adds gravity back and returns the *upward*
component, so a vehicle at rest gives 0 and a vehicle accelerating upward
gives a positive value in every frame.
"""

from __future__ import annotations

import math

import numpy as np

from ._core._common import GRAVITY

__all__ = [
    "ISA_SEA_LEVEL_PRESSURE",
    "ISA_SEA_LEVEL_TEMPERATURE",
    "ISA_LAPSE_RATE",
    "ISA_TROPOPAUSE_ALTITUDE",
    "pressure_to_altitude",
    "altitude_to_pressure",
    "isa_temperature",
    "height_above_ground",
    "euler_to_quaternion",
    "quaternion_to_matrix",
    "quaternion_multiply",
    "vertical_acceleration",
    "gyro_attitude",
]

#: ISA sea-level pressure, Pa.
ISA_SEA_LEVEL_PRESSURE = 101325.0
#: ISA sea-level temperature, K.
ISA_SEA_LEVEL_TEMPERATURE = 288.15
#: ISA troposphere temperature lapse rate, K/m (temperature falls with height).
ISA_LAPSE_RATE = 0.0065
#: Top of the ISA troposphere, m. The formulas here are exact only below it.
ISA_TROPOPAUSE_ALTITUDE = 11000.0
#: Specific gas constant of dry air, J/(kg·K).
_GAS_CONSTANT_AIR = 287.05287
#: Exponent g / (R·L) of the ISA troposphere formula (≈ 5.2559); other lapse rates use their own.
_EXPONENT = GRAVITY / (_GAS_CONSTANT_AIR * ISA_LAPSE_RATE)


def _check_atmosphere(sea_level_pa: float, sea_level_temperature_k: float, lapse_rate_k_per_m: float,
                      names=("sea_level_pa", "sea_level_temperature_k", "lapse_rate_k_per_m")) -> None:
    for name, value in zip(names, (sea_level_pa, sea_level_temperature_k)):
        if not (np.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be a positive number, got {float(value):g}")
    if not np.isfinite(lapse_rate_k_per_m):
        raise ValueError(f"{names[2]} must be finite, got {float(lapse_rate_k_per_m):g}")


def pressure_to_altitude(pressure_pa, sea_level_pa: float = ISA_SEA_LEVEL_PRESSURE,
                         sea_level_temperature_k: float = ISA_SEA_LEVEL_TEMPERATURE,
                         lapse_rate_k_per_m: float = ISA_LAPSE_RATE) -> np.ndarray:
    """Barometric altitude from static pressure (ISA troposphere).

    ``h = T0/L · (1 − (p/p0)^(R·L/g))`` (the exponent R·L/g follows the
    lapse rate L; L = 0 gives the isothermal ``h = R·T0/g · ln(p0/p)``).

    Parameters
    ----------
    pressure_pa : array_like
        Static pressure, Pa. NaN passes through as NaN.
    sea_level_pa : float, default 101325.0
        Pressure at altitude 0, Pa. Pass the pressure measured on the ground
        (e.g. the launch pad) to get height above that point (QFE), or the
        local QNH to get altitude above mean sea level.
    sea_level_temperature_k : float, default 288.15
        Temperature at altitude 0, K.
    lapse_rate_k_per_m : float, default 0.0065
        Temperature lapse rate, K/m.

    Returns
    -------
    numpy.ndarray
        Altitude, m, +up (float64, same shape as ``pressure_pa``).

    Notes
    -----
    The formula is the ISA troposphere and is exact only up to 11 km
    (p ≈ 22 632 Pa with ISA sea-level values). Above that the real atmosphere
    is isothermal (216.65 K) but this function keeps extrapolating the
    troposphere's lapse rate: it returns a finite altitude that is **too
    low**, by about 0.23 km at 15 km, 1.1 km at 20 km and roughly
    4.5 km at 30 km. It does not raise
    or clip; callers flying higher (balloons) should use a layered model.
    Non-positive pressures give NaN.

    Raises
    ------
    ValueError
        ``sea_level_pa`` or ``sea_level_temperature_k`` not a positive
        number, or a non-finite lapse rate.
    """
    _check_atmosphere(sea_level_pa, sea_level_temperature_k, lapse_rate_k_per_m)
    pressure = np.asarray(pressure_pa, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(pressure > 0, pressure / sea_level_pa, np.nan)
        if lapse_rate_k_per_m == 0.0:
            return _GAS_CONSTANT_AIR * sea_level_temperature_k / GRAVITY * -np.log(ratio)
        exponent = _GAS_CONSTANT_AIR * lapse_rate_k_per_m / GRAVITY
        return sea_level_temperature_k / lapse_rate_k_per_m * (1.0 - np.power(ratio, exponent))


def altitude_to_pressure(altitude_m, sea_level_pa: float = ISA_SEA_LEVEL_PRESSURE,
                         sea_level_temperature_k: float = ISA_SEA_LEVEL_TEMPERATURE,
                         lapse_rate_k_per_m: float = ISA_LAPSE_RATE) -> np.ndarray:
    """Static pressure at an altitude (ISA troposphere); the inverse of :func:`pressure_to_altitude`.

    ``p = p0 · (1 − L·h/T0)^(g/(R·L))``.

    Parameters
    ----------
    altitude_m : array_like
        Altitude, m, +up.
    sea_level_pa, sea_level_temperature_k, lapse_rate_k_per_m : float
        As for :func:`pressure_to_altitude` (Pa, K, K/m).

    Returns
    -------
    numpy.ndarray
        Pressure, Pa.

    Notes
    -----
    Exact to 11 km. Above, the troposphere formula is extrapolated (the same
    model as :func:`pressure_to_altitude`, so the round trip stays exact), and
    the pressure it gives is lower than the real atmosphere's. Altitudes at or
    above T0/L ≈ 44.3 km give NaN.

    Raises
    ------
    ValueError
        As :func:`pressure_to_altitude`.
    """
    _check_atmosphere(sea_level_pa, sea_level_temperature_k, lapse_rate_k_per_m)
    altitude = np.asarray(altitude_m, dtype=float)
    if lapse_rate_k_per_m == 0.0:
        return sea_level_pa * np.exp(-GRAVITY * altitude / (_GAS_CONSTANT_AIR * sea_level_temperature_k))
    exponent = GRAVITY / (_GAS_CONSTANT_AIR * lapse_rate_k_per_m)
    base = 1.0 - lapse_rate_k_per_m * altitude / sea_level_temperature_k
    with np.errstate(invalid="ignore"):
        return np.where(base > 0, sea_level_pa * np.power(np.maximum(base, 0.0), exponent), np.nan)


def isa_temperature(altitude_m) -> np.ndarray:
    """ISA (1976 U.S. Standard Atmosphere) air temperature in the troposphere, K.

    ``T = 288.15 − 0.0065·h`` (h geopotential altitude, m, up to 11 km; the
    isothermal 216.65 K above).
    """
    altitude = np.asarray(altitude_m, dtype=float)
    return np.maximum(ISA_SEA_LEVEL_TEMPERATURE - ISA_LAPSE_RATE * altitude, 216.65)


def height_above_ground(pressure_pa, ground_pressure_pa: float, ground_temperature_k=None,
                        temperature_k=None, lapse_rate_k_per_m: float = ISA_LAPSE_RATE) -> np.ndarray:
    """Height above the ground (pad) from pressure, with the ground's own temperature (hypsometric).

    Setting ``sea_level_pa`` of :func:`pressure_to_altitude` to the pad's
    pressure keeps the sea-level temperature 288.15 K, which scales heights
    by T_pad/288.15 (≈ 3 % at a 1.3 km pad). This function starts the
    atmosphere at the pad instead:

    * with ``temperature_k`` (the air temperature on each sample, e.g. a
      log's temperature column) the hypsometric equation with the mean
      layer temperature: ``h = R·(T_ground + T)/2 / g · ln(p_ground/p)``;
    * otherwise a layer whose temperature falls from ``T_ground`` with the
      lapse rate: ``h = T_ground/L · (1 − (p/p_ground)^(R·L/g))``.

    Parameters
    ----------
    pressure_pa : array_like
        Static pressure, Pa. NaN passes through; non-positive gives NaN.
    ground_pressure_pa : float
        Pressure on the ground / pad, Pa (e.g. the median before launch).
    ground_temperature_k : float, optional
        Air temperature on the ground, K. Default: the ISA temperature at
        the pressure altitude of ``ground_pressure_pa``.
    temperature_k : array_like, optional
        Air temperature on each sample, K (broadcast with ``pressure_pa``).
    lapse_rate_k_per_m : float, default 0.0065
        Lapse rate above the ground, K/m (without ``temperature_k``).

    Returns
    -------
    numpy.ndarray
        Height above the ground, m, +up.

    Raises
    ------
    ValueError
        A ground pressure or temperature that is not a positive number, or
        a temperature column with a non-positive value (naming its index).
    """
    if ground_temperature_k is None:
        _check_atmosphere(ground_pressure_pa, 1.0, 0.0, names=("ground_pressure_pa", "", ""))
        ground_temperature_k = float(isa_temperature(pressure_to_altitude(ground_pressure_pa)))
    _check_atmosphere(ground_pressure_pa, ground_temperature_k, lapse_rate_k_per_m,
                      names=("ground_pressure_pa", "ground_temperature_k", "lapse_rate_k_per_m"))
    if temperature_k is None:
        return pressure_to_altitude(pressure_pa, ground_pressure_pa, ground_temperature_k, lapse_rate_k_per_m)
    temperature = np.asarray(temperature_k, dtype=float)
    bad = np.flatnonzero(~(temperature.ravel() > 0) & np.isfinite(temperature.ravel()))
    if bad.size:
        raise ValueError(f"temperature_k[{int(bad[0])}] must be positive (K), got {float(temperature.ravel()[bad[0]]):g}")
    pressure = np.asarray(pressure_pa, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(pressure > 0, ground_pressure_pa / pressure, np.nan)
        return _GAS_CONSTANT_AIR * 0.5 * (ground_temperature_k + temperature) / GRAVITY * np.log(ratio)


def euler_to_quaternion(roll, pitch, yaw) -> np.ndarray:
    """Quaternion (w, x, y, z) of the ZYX (yaw, pitch, roll) rotation, body → earth.

    Parameters
    ----------
    roll, pitch, yaw : array_like
        Angles, rad (broadcast together).

    Returns
    -------
    numpy.ndarray
        Unit quaternions, shape ``(..., 4)``.
    """
    roll, pitch, yaw = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (roll, pitch, yaw)))
    cr, sr = np.cos(roll / 2), np.sin(roll / 2)
    cp, sp = np.cos(pitch / 2), np.sin(pitch / 2)
    cy, sy = np.cos(yaw / 2), np.sin(yaw / 2)
    return np.stack([cr * cp * cy + sr * sp * sy,
                     sr * cp * cy - cr * sp * sy,
                     cr * sp * cy + sr * cp * sy,
                     cr * cp * sy - sr * sp * cy], axis=-1)


def quaternion_multiply(q, r) -> np.ndarray:
    """Hamilton product q ⊗ r of quaternions (w, x, y, z), shape ``(..., 4)``."""
    q = np.asarray(q, dtype=float)
    r = np.asarray(r, dtype=float)
    w1, x1, y1, z1 = np.moveaxis(q, -1, 0)
    w2, x2, y2, z2 = np.moveaxis(r, -1, 0)
    return np.stack([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
                     w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
                     w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2], axis=-1)


def quaternion_to_matrix(quaternion) -> np.ndarray:
    """Rotation matrices (body → earth) of quaternions (w, x, y, z).

    Parameters
    ----------
    quaternion : array_like
        Shape ``(..., 4)``; normalised here.

    Returns
    -------
    numpy.ndarray
        Shape ``(..., 3, 3)``; ``v_earth = R @ v_body``.
    """
    q = np.asarray(quaternion, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    w, x, y, z = np.moveaxis(q, -1, 0)
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1),
    ], axis=-2)


_FRAMES = ("NED", "ENU", "NWU")
_UNITS = {"m/s^2": 1.0, "m/s²": 1.0, "g": GRAVITY}


def vertical_acceleration(accel_body, attitude, frame: str = "NED", accel_units: str = "m/s^2") -> np.ndarray:
    """Gravity-removed earth-frame vertical acceleration, +up, from body specific force.

    Parameters
    ----------
    accel_body : array_like, shape (..., 3)
        Accelerometer reading (specific force) in the body frame, in
        ``accel_units``. A level vehicle at rest reads (0, 0, −1 g) in a NED
        body frame and (0, 0, +1 g) in an ENU or NWU body frame.
    attitude : array_like, shape (..., 4) or (..., 3)
        Body → earth attitude: a quaternion (w, x, y, z) if the last axis has 4
        entries, otherwise roll, pitch, yaw in rad (ZYX Euler angles about the
        axes of ``frame``). Broadcast against ``accel_body``.
    frame : {"NED", "ENU", "NWU"}, default "NED"
        Convention of the earth frame and of the body frame.
    accel_units : {"m/s^2", "g"}, default "m/s^2"
        Units of ``accel_body`` (1 g = 9.80665 m/s²).

    Returns
    -------
    numpy.ndarray, shape (...)
        Vertical acceleration, m/s², earth frame, **+up**, gravity removed:
        0 at rest, positive when accelerating upward, whatever the frame.

    Raises
    ------
    ValueError
        Unknown ``frame`` or ``accel_units``, or a bad last-axis length.
    """
    if frame not in _FRAMES:
        raise ValueError(f"frame must be one of {', '.join(_FRAMES)}; got {frame!r}")
    if accel_units not in _UNITS:
        raise ValueError(f"accel_units must be 'm/s^2' or 'g'; got {accel_units!r}")
    accel = np.asarray(accel_body, dtype=float)
    if _UNITS[accel_units] != 1.0:  # m/s²: the values as they are (× 1.0 would copy them unchanged)
        accel = accel * _UNITS[accel_units]
    if accel.shape[-1:] != (3,):
        raise ValueError(f"accel_body must have 3 components on its last axis, got shape {accel.shape}")
    att = np.asarray(attitude, dtype=float)
    if att.shape[-1:] == (4,):
        third_row = _quaternion_third_row(att)
    elif att.shape[-1:] == (3,):
        roll, pitch = att[..., 0], att[..., 1]
        cos_pitch = np.cos(pitch)
        third_row = (-np.sin(pitch), np.sin(roll) * cos_pitch, np.cos(roll) * cos_pitch)
    else:
        raise ValueError(f"attitude must be a quaternion (w, x, y, z) or roll, pitch, yaw on its last axis, "
                         f"got shape {att.shape}")
    accel_x, accel_y, accel_z = _components(accel)
    earth_z = third_row[0] * accel_x  # specific force along the frame's z axis: the row · accel, summed in order
    earth_z += third_row[1] * accel_y
    earth_z += third_row[2] * accel_z
    if frame == "NED":
        return -(earth_z + GRAVITY)  # z down: specific force at rest is −g; flip to +up
    return earth_z - GRAVITY


def _components(values: np.ndarray) -> np.ndarray:
    """``values`` (shape (..., k)) with its last axis first, a view: ``numpy.moveaxis(values, -1, 0)``, by the
    transpose when that is the same (at most 2 axes; moveaxis is a Python wrapper, the transpose an attribute)."""
    return values.T if values.ndim <= 2 else np.moveaxis(values, -1, 0)


def _quaternion_third_row(quaternion: np.ndarray) -> tuple:
    """The third row of :func:`quaternion_to_matrix` of quaternions (w, x, y, z) (shape (..., 4), normalised
    here): ``2(xz − wy), 2(yz + wx), 1 − 2(x² + y²)``, each of shape (...), in the matrix's operation order (so
    its bits), computed on one contiguous copy with the products in place."""
    q = _components(quaternion).copy()
    square = q * q
    q /= np.sqrt(square[0] + square[1] + square[2] + square[3])  # |q| as numpy.linalg.norm sums it, in order
    w, x, y, z = q
    first = x * z
    first -= w * y
    first *= 2
    second = y * z
    second += w * x
    second *= 2
    third = x * x
    third += y * y
    third *= -2
    third += 1  # 1 − 2(x² + y²): the same rounding as the subtraction
    return first, second, third


def _rotation_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Shortest-arc unit quaternion (w, x, y, z) rotating unit vector a onto unit vector b."""
    a = a / np.linalg.norm(a)
    b = b / np.linalg.norm(b)
    cross = np.cross(a, b)
    dot = float(np.dot(a, b))
    if dot < -1.0 + 1e-12:  # opposite: rotate by π about any axis perpendicular to a
        axis = np.cross(a, [1.0, 0.0, 0.0])
        if np.linalg.norm(axis) < 1e-6:
            axis = np.cross(a, [0.0, 1.0, 0.0])
        axis /= np.linalg.norm(axis)
        return np.concatenate([[0.0], axis])
    q = np.concatenate([[1.0 + dot], cross])
    return q / np.linalg.norm(q)


def gyro_attitude(gyro_dps, dt, accel_at_rest, gyro_bias_dps=None) -> np.ndarray:
    """Attitude by strapdown gyro integration from an initial attitude levelled on gravity.

    The initial attitude rotates the body-frame specific force measured at
    rest (which points **up**) onto the earth z axis, with the heading left
    arbitrary: the result is body → earth for a **z-up** earth frame (use
    ``frame="ENU"`` with :func:`vertical_acceleration`). Each step multiplies
    by the exact rotation of the bias-corrected rate over dt.

    Parameters
    ----------
    gyro_dps : array_like, shape (n, 3)
        Body angular rate, °/s.
    dt : float or array_like, shape (n,)
        Time from the previous sample, s (the rate of sample i acts over dt[i]).
    accel_at_rest : array_like, shape (3,)
        Mean body-frame specific force while at rest (any unit, any sign
        convention whose vector points up).
    gyro_bias_dps : array_like, shape (3,), optional
        Gyro bias, °/s, subtracted before integration (e.g. the pre-launch
        mean rate).

    Returns
    -------
    numpy.ndarray, shape (n, 4)
        Quaternions (w, x, y, z), body → earth (z up), one per sample, after
        applying that sample's rate.
    """
    gyro = np.radians(np.asarray(gyro_dps, dtype=float))
    if gyro_bias_dps is not None:
        gyro = gyro - np.radians(np.asarray(gyro_bias_dps, dtype=float))
    n = gyro.shape[0]
    dt = np.broadcast_to(np.asarray(dt, dtype=float), (n,))
    angle = np.linalg.norm(gyro, axis=1) * dt
    with np.errstate(invalid="ignore", divide="ignore"):
        axis = np.where(angle[:, None] > 0, gyro * dt[:, None] / angle[:, None], 0.0)
    steps = np.concatenate([np.cos(angle / 2)[:, None], axis * np.sin(angle / 2)[:, None]], axis=1)
    initial = _rotation_between(np.asarray(accel_at_rest, dtype=float), np.array([0.0, 0.0, 1.0]))
    return _integrate_steps(initial, steps)


def _integrate_steps(initial: np.ndarray, steps: np.ndarray) -> np.ndarray:
    """The running product of the rotation ``steps`` (n×4) onto ``initial`` (4,), renormalised each step: in
    C (:func:`fusion_altitude._core._strapdown.integrate_steps`, bit for bit :func:`_integrate_steps_python`)
    where the extension is built, else in Python."""
    try:
        from ._core._strapdown import integrate_steps
    except ImportError:
        return _integrate_steps_python(initial, steps)
    return integrate_steps(initial, steps)


def _integrate_steps_python(initial: np.ndarray, steps: np.ndarray) -> np.ndarray:
    """The reference of the integration loop: q ← q ⊗ step (Hamilton product, w first), q ← q / |q|, in float64
    in this operation order (which the C loop follows, so both give the same bits)."""
    w, x, y, z = (float(value) for value in initial)
    out = []
    for w2, x2, y2, z2 in np.asarray(steps, dtype=float).tolist():
        w, x, y, z = (w * w2 - x * x2 - y * y2 - z * z2,
                      w * x2 + x * w2 + y * z2 - z * y2,
                      w * y2 - x * z2 + y * w2 + z * x2,
                      w * z2 + x * y2 - y * x2 + z * w2)
        norm = math.sqrt(w * w + x * x + y * y + z * z)
        w, x, y, z = w / norm, x / norm, y / norm, z / norm
        out.append((w, x, y, z))
    return np.array(out, dtype=float).reshape(len(out), 4)
