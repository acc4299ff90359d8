"""Generic CSV logs: the caller names the columns."""

from __future__ import annotations

import os
from typing import Callable, Optional, Sequence, Union

import numpy as np

from .._core._common import GRAVITY
from ..sensors import height_above_ground, pressure_to_altitude, vertical_acceleration
from ._checks import ALTITUDE_RANGE, PRESSURE_RANGE as PLAUSIBLE_PRESSURE, absurd_columns, check_time_units, column_dead
from ._data import LogData, LogError, fmt, finish, merge_repeated_timestamps
from ._table import check_finite, numeric_columns, read_table

ACCEL_UNITS = {"m/s^2": 1.0, "m/s²": 1.0, "g": GRAVITY}
GYRO_UNITS = {"rad/s": 1.0, "deg/s": float(np.pi / 180.0)}
ALTITUDE_UNITS = {"m": 1.0, "ft": 0.3048}
ATTITUDE_CONVENTIONS = ("quaternion", "euler_deg", "euler_rad")
FRAMES = {"NED": "FRD", "NWU": "FLU", "ENU": "RFU"}
TEMPERATURE_UNITS = ("C", "K")
#: Time units → seconds per unit.
TIME_UNITS = {"s": 1.0, "ms": 1e-3, "us": 1e-6}
#: Seconds at the start of a log taken as "at rest" for the gravity check and ground values.
REST_SECONDS = 1.0
#: Plausible static pressure, Pa (1 kPa ≈ 31 km up; 120 kPa below the Dead Sea); a pressure column
#: whose median is outside gets a warning.
PRESSURE_RANGE = (1_000.0, 120_000.0)


def _rest(time: np.ndarray) -> np.ndarray:
    return time <= time[0] + REST_SECONDS


def gravity_check(source: str, name: str, accel: np.ndarray, time: np.ndarray, remove_gravity: bool) -> np.ndarray:
    """Refuse (or, with ``remove_gravity``, remove) gravity left in a vertical-acceleration column.

    At rest (the first second) a gravity-removed column averages ≈ 0. A mean
    within 0.75–1.25 g of ±g means gravity is still in it, and a mean of
    0.9–1.1 m/s² that hardly varies (σ < 0.05) a column in g with gravity:
    LogError, unless
    ``remove_gravity`` — then +g at rest is taken as upward specific force
    (``a − g``) and −g at rest as downward specific force (``−(a + g)``).
    """
    finite = np.isfinite(accel) & _rest(time)
    mean = float(np.mean(accel[finite])) if finite.any() else 0.0
    holds_gravity = 0.75 * GRAVITY < abs(mean) < 1.25 * GRAVITY
    steady = finite.sum() > 1 and float(np.std(accel[finite])) < 0.05
    if not remove_gravity and 0.9 < abs(mean) < 1.1 and steady:
        raise LogError(f"{source}: column {name!r}: mean {fmt(mean)} m/s² over the first {fmt(REST_SECONDS)} s "
                       f"looks like 1 g: the column is probably in g with gravity still in it; say so with "
                       f"accel_units='g' (--accel-units g) and remove_gravity=True (--remove-gravity)")
    if remove_gravity:
        if not holds_gravity:
            raise LogError(f"{source}: column {name!r}: remove_gravity asked, but its mean over the first "
                           f"{fmt(REST_SECONDS)} s is {fmt(mean)} m/s², not about ±{fmt(GRAVITY)} (±1 g)")
        return accel - GRAVITY if mean > 0 else -(accel + GRAVITY)
    if holds_gravity:
        raise LogError(f"{source}: column {name!r}: mean {fmt(mean)} m/s² over the first {fmt(REST_SECONDS)} s "
                       f"looks like gravity is still in it (the observer needs +up, gravity removed); "
                       f"remove it with remove_gravity=True (--remove-gravity) or check the units")
    return accel


def read_csv_log(path: str, time_column: str, accel_column: Optional[str] = None,
                 baro_column: Optional[str] = None, pressure_column: Optional[str] = None,
                 reference_column: Optional[str] = None, accel_units: str = "m/s^2", altitude_units: str = "m",
                 sea_level_pa: float = 101325.0, remove_gravity: bool = False,
                 accel_body_columns: Optional[Sequence[str]] = None,
                 attitude_columns: Optional[Sequence[str]] = None, attitude_convention: str = "quaternion",
                 frame: str = "NED", gps_column: Optional[str] = None, rangefinder_column: Optional[str] = None,
                 temperature_column: Optional[str] = None,
                 temperature_units: str = "C", ground_temperature_k: Union[None, float, str] = None,
                 progress: Optional[Callable[[int, int], None]] = None,
                 gyro_body_columns: Optional[Sequence[str]] = None, gyro_units: str = "rad/s",
                 time_units: str = "s") -> LogData:
    """Read a CSV log with a header row; the caller names the columns.

    Parameters
    ----------
    path : str
        CSV file: comma separated, header on the first non-empty line; a
        UTF-8 BOM (Excel's "CSV UTF-8") is accepted. Empty cells, ``nan``,
        ``NA``, ``null`` mean "no value".
    time_column : str
        Time, s. Rows that repeat the previous row's time are merged (see
        :func:`fusion_altitude.logs.merge_repeated_timestamps`: numeric
        columns averaged) and counted in a warning; a time that goes
        backwards is an error naming the line.
    accel_column : str, optional
        Vertical acceleration, earth frame, +up, gravity removed, in
        ``accel_units``. If its mean over the first second is ≈ ±1 g, the
        reader refuses it unless ``remove_gravity``. Give this or
        ``accel_body_columns``.
    baro_column : str, optional
        Baro altitude in ``altitude_units``; an empty cell means no baro that
        row. Give this or ``pressure_column``.
    pressure_column : str, optional
        Static pressure, Pa, converted to altitude: with
        :func:`fusion_altitude.sensors.pressure_to_altitude` relative to
        ``sea_level_pa`` (ISA temperature), or — with
        ``ground_temperature_k`` — to height above the first second's
        pressure with :func:`fusion_altitude.sensors.height_above_ground`.
        A median outside 1,000–120,000 Pa gets a warning (an altitude column?).
    reference_column : str, optional
        A better altitude (RTK GPS, motion capture, the flight computer's
        own estimate), in ``altitude_units``; empty = unknown.
    accel_units : {"m/s^2", "g"}
        Units of the acceleration column(s).
    altitude_units : {"m", "ft"}
        Units of the baro, reference and GPS altitude columns (output in m).
    sea_level_pa : float
        Reference pressure for ``pressure_column``, Pa.
    remove_gravity : bool
        The vertical-acceleration column still holds gravity: subtract it
        (+g at rest: ``a − g``; −g at rest, a +down column: ``−(a + g)``).
    accel_body_columns : (str, str, str), optional
        Body-frame accelerometer (specific force) x, y, z columns in
        ``accel_units``, axes as ``frame`` says; needs ``attitude_columns``.
        Turned into vertical acceleration with
        :func:`fusion_altitude.sensors.vertical_acceleration`.
    attitude_columns : sequence of str, optional
        Body → earth attitude: 4 columns, a quaternion (w, x, y, z), with
        ``attitude_convention="quaternion"``; or 3 columns roll, pitch, yaw
        (ZYX Euler angles about the ``frame`` axes) with ``"euler_deg"`` or
        ``"euler_rad"``.
    attitude_convention : {"quaternion", "euler_deg", "euler_rad"}
    frame : {"NED", "ENU", "NWU"}
        Earth frame of the attitude and body frame of the accelerometer
        (NED: body x forward, y right, z down). A result averaging more than
        ½ g over the first second (the frame or attitude is wrong) is refused.
    gps_column : str, optional
        GPS altitude (``altitude_units``), empty between fixes.
    rangefinder_column : str, optional
        Distance to the ground (``altitude_units``), empty without a reading.
    temperature_column : str, optional
        Temperature in ``temperature_units`` (stored in K).
    temperature_units : {"C", "K"}
    ground_temperature_k : float or "log", optional
        Air temperature on the ground, K, for the hypsometric conversion of
        ``pressure_column`` to height above the start (datum "pad"); ``"log"``
        takes it from ``temperature_column`` over the first second.
    progress : callable(done, total), optional
        Called while reading (units: characters of the file).
    gyro_body_columns : (str, str, str), optional
        Body-frame gyroscope x, y, z columns in ``gyro_units``, the axes of
        ``accel_body_columns`` (needs them): with both, the log has a raw
        IMU (``LogData.gyro``, ``LogData.accel``) and ``run`` picks the INS.
    gyro_units : {"rad/s", "deg/s"}
    time_units : {"s", "ms", "us"}
        Units of ``time_column`` (converted to s). A time column that does
        not look like seconds (median step > 2 s, or ≥ 1 s over more than a
        day; see :mod:`fusion_altitude.logs._checks`) is refused with a
        LogError naming this option.

    Plausibility (:mod:`fusion_altitude.logs._checks`): a baro, reference or
    pressure cell that is infinite or absurd (altitude outside −1 km…100 km,
    pressure ≤ 0 or > 120 kPa) is dropped (NaN: no sample) with one warning
    naming its file line; a constant or all-zero acceleration is a dead
    sensor: warned, and the log runs baro-only.

    Returns
    -------
    LogData
        ``altitude_reference`` is ``"sea level"`` for pressure converted
        with ``sea_level_pa`` = 101325 Pa, ``"pad"`` for the hypsometric
        conversion, else ``""`` (the column's own datum).

    Raises
    ------
    LogError
        Missing file or column, a bad cell (naming file line and column),
        time going backwards, gravity left in the acceleration, bad options.
    """
    _check_options(baro_column, pressure_column, accel_column, accel_body_columns, accel_units, altitude_units,
                   temperature_units, sea_level_pa, attitude_columns, attitude_convention, frame,
                   ground_temperature_k, temperature_column, gyro_body_columns, gyro_units)
    if time_units not in TIME_UNITS:
        raise LogError(f"time units must be 's', 'ms' or 'us', got {time_units!r}")
    source = f"{os.path.basename(path)} (CSV)"
    roles = _column_roles(time_column, accel_column, baro_column or pressure_column, accel_body_columns,
                          attitude_columns, reference_column, gps_column, rangefinder_column, temperature_column,
                          gyro_body_columns)
    altitude_scale = ALTITUDE_UNITS[altitude_units]
    time, column, lines, dropped, repeated, implausible = _read_columns(
        path, roles, progress, TIME_UNITS[time_units], _plausibility_checks(reference_column, pressure_column,
                                                                            baro_column, altitude_units))
    notes = [f"time {time_column!r}"]
    if accel_column is not None:
        accel, accel_body, dead = _vertical_column(path, source, accel_column, _scaled(
            column["accel"], ACCEL_UNITS[accel_units]), time, remove_gravity, notes, accel_units)
        implausible += [dead] if dead is not None else []
    else:
        accel, accel_body = _body_to_vertical(path, source, column, time, ACCEL_UNITS[accel_units],
                                              accel_body_columns, attitude_columns, attitude_convention, frame)
        dead = None
        notes.append(f"accel body {', '.join(accel_body_columns)} ({accel_units}, {frame}) rotated by "
                     f"{', '.join(attitude_columns)} ({attitude_convention})")
    gyro, temperature = _gyro_and_temperature(column, gyro_body_columns, gyro_units, frame, temperature_column,
                                              temperature_units, notes)
    if pressure_column is not None:
        warning = _pressure_warning(pressure_column, column["baro"])
        baro, altitude_reference, ground_altitude = _pressure_altitude(
            path, pressure_column, column["baro"], time, sea_level_pa, ground_temperature_k, temperature_column,
            temperature, notes)
    else:
        baro, warning, altitude_reference, ground_altitude = _scaled(column["baro"], altitude_scale), None, "", None
        notes.append(f"baro {baro_column!r} ({altitude_units})")
    if not np.isfinite(baro).any():
        raise LogError(f"{path}: column {baro_column or pressure_column!r}: no usable value on any row")
    scaled = {role: _scaled(column[role], altitude_scale) if role in column else None
              for role in ("reference", "gps", "rangefinder")}
    log = LogData(source, time, accel, baro, reference_altitude=scaled["reference"], baro_only=dead is not None,
                  reference_name=f"column {reference_column!r}" if reference_column is not None else "",
                  notes=notes, gps_altitude=scaled["gps"], rangefinder=scaled["rangefinder"], accel=accel_body,
                  gyro=gyro, imu_frame=FRAMES[frame] if accel_body is not None else "",
                  pressure=column["baro"] if pressure_column is not None else None, temperature=temperature,
                  altitude_reference=altitude_reference, ground_altitude=ground_altitude, repeated_timestamps=repeated)
    _warn_read(log, path, dropped, warning, implausible)
    return finish(log)


def _scaled(values: np.ndarray, scale: float) -> np.ndarray:
    """``values * scale``; ``values`` itself for a scale of 1 (the same bits: a column of the scan is a contiguous
    view, and a copy of it one more array to allocate and fault in, a tenth of a large log's read)."""
    return values if scale == 1.0 else values * scale


def _gyro_and_temperature(column: dict, gyro_body_columns, gyro_units: str, frame: str, temperature_column,
                          temperature_units: str, notes: list):
    """The body-frame gyroscope, rad/s (``None`` without ``gyro_body_columns``; noted), and the temperature, K
    (``None`` without ``temperature_column``), from the columns read."""
    gyro = None
    if gyro_body_columns is not None:
        gyro = np.column_stack([column[f"gyro{i}"] for i in range(3)]) * GYRO_UNITS[gyro_units]
        notes.append(f"gyro body {', '.join(gyro_body_columns)} ({gyro_units}, {frame})")
    temperature = None
    if temperature_column is not None:
        temperature = column["temperature"] + (273.15 if temperature_units == "C" else 0.0)
    return gyro, temperature


def _plausibility_checks(reference_column, pressure_column, baro_column, altitude_units: str) -> list:
    """The plausibility checks of the reference and baro (or pressure) columns: (role, name, low, high, unit,
    what, low_inclusive), altitudes in ``altitude_units``."""
    altitude_scale = ALTITUDE_UNITS[altitude_units]
    low, high = ALTITUDE_RANGE
    altitude_check = (low / altitude_scale, high / altitude_scale, altitude_units)
    checks = [("reference", reference_column, *altitude_check, "reference altitude", True)]
    if pressure_column is not None:
        checks.append(("baro", pressure_column, *PLAUSIBLE_PRESSURE, "Pa", "pressure", False))
    else:
        checks.append(("baro", baro_column, *altitude_check, "baro altitude", True))
    return checks


def _vertical_column(path: str, source: str, accel_column: str, accel: np.ndarray, time: np.ndarray,
                     remove_gravity: bool, notes: list, accel_units: str):
    """A vertical-acceleration column (m/s²) checked for gravity (:func:`gravity_check`) and a dead sensor:
    (vertical acceleration m/s² — zeros when dead —, None, the dead-sensor warning or None); appends a note."""
    accel = gravity_check(source, accel_column, accel, time, remove_gravity)
    notes.append(f"accel {accel_column!r} ({accel_units})" + (", gravity removed" if remove_gravity else ""))
    dead = column_dead(path, accel_column, accel, "m/s²",
                       "the estimators track the baro alone (vertical acceleration 0 m/s²)")
    return (np.zeros(time.shape) if dead is not None else accel), None, dead


def _warn_read(log: LogData, path: str, dropped: Optional[int], warning: Optional[str], implausible) -> None:
    """The reader's warnings: a cut-short last line (file line ``dropped``), the pressure column's ``warning``,
    the ``implausible`` cells and a dead accelerometer."""
    if dropped is not None:
        log.warn(f"{path}: line {dropped}: the last line is cut short (no newline at the end); dropped")
    if warning is not None:
        log.warn(f"{path}: {warning}")
    for message in implausible:
        log.warn(message)


def _check_options(baro_column, pressure_column, accel_column, accel_body_columns, accel_units, altitude_units,
                   temperature_units, sea_level_pa, attitude_columns, attitude_convention, frame,
                   ground_temperature_k, temperature_column, gyro_body_columns, gyro_units) -> None:
    """Refuse a bad combination of :func:`read_csv_log` options (LogError), before the file is read."""
    if (baro_column is None) == (pressure_column is None):
        raise LogError("give exactly one of a baro altitude column or a pressure column")
    if (accel_column is None) == (accel_body_columns is None):
        raise LogError("give exactly one of a vertical acceleration column or body accelerometer columns")
    if accel_units not in ACCEL_UNITS:
        raise LogError(f"accel units must be 'm/s^2' or 'g', got {accel_units!r}")
    if altitude_units not in ALTITUDE_UNITS:
        raise LogError(f"altitude units must be 'm' or 'ft', got {altitude_units!r}")
    if temperature_units not in TEMPERATURE_UNITS:
        raise LogError(f"temperature units must be 'C' or 'K', got {temperature_units!r}")
    if not (np.isfinite(sea_level_pa) and sea_level_pa > 0):
        raise LogError(f"sea-level pressure must be a positive number of Pa, got {fmt(sea_level_pa)}")
    if accel_body_columns is not None:
        _check_body_options(accel_body_columns, attitude_columns, attitude_convention, frame)
    _check_gyro_options(gyro_body_columns, gyro_units, accel_body_columns)
    if ground_temperature_k is not None:
        if pressure_column is None:
            raise LogError("a ground temperature needs a pressure column")
        if isinstance(ground_temperature_k, str):
            if ground_temperature_k != "log" or temperature_column is None:
                raise LogError("ground temperature 'log' needs a temperature column")
        elif not (np.isfinite(ground_temperature_k) and ground_temperature_k > 0):
            raise LogError(f"ground temperature must be a positive number of K, got {fmt(ground_temperature_k)}")


def _check_gyro_options(gyro_body_columns, gyro_units, accel_body_columns) -> None:
    """Refuse bad body-gyroscope options of :func:`read_csv_log` (LogError)."""
    if gyro_body_columns is None:
        return
    if len(gyro_body_columns) != 3:
        raise LogError(f"body gyroscope columns: give 3 (x, y, z), got {len(gyro_body_columns)}")
    if accel_body_columns is None:
        raise LogError("body gyroscope columns need body accelerometer columns (the raw IMU, same axes)")
    if gyro_units not in GYRO_UNITS:
        raise LogError(f"gyro units must be 'rad/s' or 'deg/s', got {gyro_units!r}")


def _check_body_options(accel_body_columns, attitude_columns, attitude_convention, frame) -> None:
    """Refuse bad body-accelerometer / attitude options of :func:`read_csv_log` (LogError)."""
    if len(accel_body_columns) != 3:
        raise LogError(f"body accelerometer columns: give 3 (x, y, z), got {len(accel_body_columns)}")
    if attitude_columns is None:
        raise LogError("body accelerometer columns need attitude columns (quaternion or Euler angles)")
    if attitude_convention not in ATTITUDE_CONVENTIONS:
        raise LogError(f"attitude convention must be one of {', '.join(ATTITUDE_CONVENTIONS)}, "
                       f"got {attitude_convention!r}")
    wanted_count = 4 if attitude_convention == "quaternion" else 3
    if len(attitude_columns) != wanted_count:
        raise LogError(f"attitude convention {attitude_convention!r} needs {wanted_count} attitude columns, "
                       f"got {len(attitude_columns)}")
    if frame not in FRAMES:
        raise LogError(f"frame must be one of {', '.join(FRAMES)}, got {frame!r}")


def _column_roles(time_column, accel_column, baro_column, accel_body_columns, attitude_columns,
                  reference_column, gps_column, rangefinder_column, temperature_column,
                  gyro_body_columns) -> dict:
    """Role ("time", "accel", "body0", "att0", "gyro0", "baro", …) → column name, for the columns asked for."""
    roles = {"time": time_column, "baro": baro_column}
    if accel_column is not None:
        roles["accel"] = accel_column
    else:
        roles.update({f"body{i}": name for i, name in enumerate(accel_body_columns)})
        roles.update({f"att{i}": name for i, name in enumerate(attitude_columns)})
    roles.update({f"gyro{i}": name for i, name in enumerate(gyro_body_columns or ())})
    for role, name in (("reference", reference_column), ("gps", gps_column), ("rangefinder", rangefinder_column),
                       ("temperature", temperature_column)):
        if name is not None:
            roles[role] = name
    return roles


def _read_columns(path: str, roles: dict, progress, time_scale: float = 1.0, checks=()):
    """Read the columns of ``roles`` (role → name) from the CSV at ``path``.

    Returns time (s, repeated stamps merged), role → column, the file line of
    each row, the line number of a cut-short last line (or None) and the
    count of repeated time stamps, and the plausibility warnings. The time
    (× ``time_scale`` → s) and acceleration/attitude columns must be finite on
    every row (LogError naming the line), and the time in seconds
    (:func:`~fusion_altitude.logs._checks.check_time_units`); ``checks``
    (role, name, low, high, unit, what, low_inclusive) drop absurd cells
    before repeated time stamps are merged, so the warnings name file lines.
    """
    table = read_table(path)
    positions = {role: table.index(name) for role, name in roles.items()}
    unique = sorted(set(positions.values()))
    data, lines, dropped = numeric_columns(table, unique, progress)
    column = {role: data[:, unique.index(position)] for role, position in positions.items()}
    if data.shape[0] < 2:
        raise LogError(f"{path}: need at least 2 data rows, got {data.shape[0]}")
    check_finite(path, roles["time"], column["time"], lines)
    required = ["accel"] if "accel" in roles else [f"body{i}" for i in range(3)]
    if "accel" not in roles:
        required += [role for role in roles if role.startswith("att") or role.startswith("gyro")]
    for role in required:
        check_finite(path, roles[role], column[role], lines)
    column["time"] = _scaled(column["time"], time_scale)
    check_time_units(f"{os.path.basename(path)} (CSV)", column["time"],
                     f"column {roles['time']!r}: set time_units to 'ms' or 'us'")
    implausible = absurd_columns(path, column, lines, [c for c in checks if c[1] is not None])
    time, merged, repeated = merge_repeated_timestamps(column.pop("time"), column, path, lines, roles["time"])
    return time, merged, lines, dropped, repeated, implausible


def _body_to_vertical(path, source, column, time, scale, accel_body_columns, attitude_columns,
                      attitude_convention, frame):
    """Vertical acceleration (m/s², +up) and the body accelerometer (m/s², n×3) from body and attitude columns.

    A quaternion far from unit norm, or a result averaging more than ½ g over
    the first second (wrong frame or attitude), is a LogError.
    """
    accel_body = np.column_stack([column[f"body{i}"] for i in range(3)]) * scale
    attitude = np.column_stack([column[f"att{i}"] for i in range(len(attitude_columns))])
    if attitude_convention == "euler_deg":
        attitude = np.radians(attitude)
    if attitude_convention == "quaternion":
        norm = np.linalg.norm(attitude, axis=1)
        bad = np.flatnonzero(~(norm > 0.5) | ~(norm < 1.5))
        if bad.size:
            raise LogError(f"{path}: attitude columns {', '.join(attitude_columns)}: the quaternion at time "
                           f"{fmt(time[bad[0]])} s has norm {fmt(norm[bad[0]])}, not about 1")
    accel = vertical_acceleration(accel_body, attitude, frame=frame)
    rest = _rest(time)
    mean = float(np.mean(accel[rest]))
    if abs(mean) > 0.5 * GRAVITY:
        raise LogError(f"{source}: body accelerometer {', '.join(accel_body_columns)}: the vertical "
                       f"acceleration averages {fmt(mean)} m/s² over the first {fmt(REST_SECONDS)} s, not "
                       f"about 0: the frame {frame!r} looks wrong (NED bodies read −1 g on z at rest, "
                       f"ENU/NWU +1 g) or the attitude is not body → earth")
    return accel, accel_body


def _pressure_warning(pressure_column: str, pressure: np.ndarray) -> Optional[str]:
    """A warning if the median of a pressure column (Pa) is outside :data:`PRESSURE_RANGE`, else None."""
    finite = np.isfinite(pressure)
    median = float(np.median(pressure[finite])) if finite.any() else np.nan
    if finite.any() and not PRESSURE_RANGE[0] <= median <= PRESSURE_RANGE[1]:
        return (f"column {pressure_column!r}: median {fmt(median)} is far outside "
                f"{fmt(PRESSURE_RANGE[0])}–{fmt(PRESSURE_RANGE[1])} Pa; is it really a pressure in Pa?")
    return None


def _ground_median(path, column, values, time, quantity: str, unit: str) -> float:
    """The median of ``values`` over the first REST_SECONDS s (the ground pressure in Pa or temperature in K);
    a LogError naming the column when there is none or it is not > 0."""
    rest = np.isfinite(values) & _rest(time)
    if not rest.any():
        raise LogError(f"{path}: column {column!r}: no {quantity} in the first "
                       f"{fmt(REST_SECONDS)} s to take as the ground {quantity}")
    median = float(np.median(values[rest]))
    if not median > 0:
        raise LogError(f"{path}: column {column!r}: the ground {quantity} (median of the first "
                       f"{fmt(REST_SECONDS)} s) is {fmt(median)} {unit}; it must be > 0 {unit}")
    return median


def _pressure_altitude(path, pressure_column, pressure, time, sea_level_pa, ground_temperature_k,
                       temperature_column, temperature, notes):
    """Baro altitude (m) from pressure (Pa), its datum and the ground altitude (m); appends a note.

    With ``ground_temperature_k`` (K or "log"): height above the median
    pressure of the first second, datum "pad"; else the ISA altitude
    relative to ``sea_level_pa``.
    """
    if ground_temperature_k is None:
        baro = pressure_to_altitude(pressure, sea_level_pa)
        notes.append(f"pressure {pressure_column!r} (Pa, p0 {fmt(sea_level_pa)} Pa)")
        return baro, ("sea level" if sea_level_pa == 101325.0 else ""), None
    ground_pa = _ground_median(path, pressure_column, pressure, time, "pressure", "Pa")
    if ground_temperature_k == "log":
        ground_temperature_k = _ground_median(path, temperature_column, temperature, time, "temperature", "K")
    baro = height_above_ground(pressure, ground_pa, ground_temperature_k)
    notes.append(f"pressure {pressure_column!r} (Pa) → height above {fmt(ground_pa)} Pa at "
                 f"{fmt(ground_temperature_k)} K (hypsometric)")
    return baro, "pad", 0.0
