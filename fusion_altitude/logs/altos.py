"""AltOS CSV exports (Altus Metrum TeleMega, TeleMetrum, EasyMega, EasyMini…), recognised by their header."""

from __future__ import annotations

import os
from typing import Callable, Optional, Union

import numpy as np

from ..sensors import height_above_ground
from ._data import LogData, LogError, _fmt, finish, merge_repeated_timestamps
from ._table import check_finite, numeric_columns, read_text, split_header, text_column

#: The header line of an AltOS CSV starts with this (after an optional BOM).
HEADER_START = "#version,serial,flight"


def looks_like_altos(head: str) -> bool:
    """True if the first line of ``head`` is an AltOS CSV header."""
    first = head.lstrip("\ufeff").lstrip().split("\n", 1)[0]
    return first.startswith(HEADER_START) and "state_name" in first and ",time," in first


def read_altos_csv(path: str, ground_temperature_k: Union[None, float, str] = None,
                   progress: Optional[Callable[[int, int], None]] = None) -> LogData:
    """Read an AltOS CSV export (AltosUI "Export data" / ``altosui`` CSV) with no column options.

    The header line starts ``#version,serial,flight,call,time,state,state_name,
    acceleration,pressure,altitude,height,speed,temperature,…`` and names
    ``altitude`` twice: the first is the flight computer's pressure altitude
    (m above sea level), the second (after ``latitude,longitude``) the GPS
    altitude. Columns used:

    * ``time`` (s from launch, negative on the pad) → ``time``;
    * ``acceleration`` (m/s², along the rocket's axis, the flight computer's
      own gravity-removed value: ≈ 0 on the pad) → ``vertical_acceleration``
      (the rocket is taken as vertical, as AltOS does);
    * ``altitude`` (first) → ``baro_altitude`` (datum "sea level"), or with
      ``ground_temperature_k`` the hypsometric height above the pad from
      ``pressure`` (datum "pad");
    * ``height`` (m above the pad) → ``reference_altitude`` (+ the pad's
      altitude, so it shares the baro's datum), ``speed`` →
      ``reference_velocity``; ``ground_altitude`` = median(altitude − height);
    * ``pressure`` (Pa), ``temperature`` (°C → K), ``state_name`` →
      ``flight_state``; ``accel_x/y/z`` (m/s²) and ``gyro_roll/pitch/yaw``
      (°/s → rad/s) → ``accel``/``gyro`` (``imu_frame="sensor"``) when present;
    * GPS: the second ``altitude`` where the fix is locked (``locked`` = 1, or
      ``nsat`` ≥ 4 without that column) and the position changed since the
      row before (AltOS repeats the last fix on every row); ``nsat``.

    Several rows often share one time stamp (one per telemetry packet):
    they are merged by the rule of :func:`merge_repeated_timestamps`
    (numbers averaged, the state: last) and counted in a warning.

    Parameters
    ----------
    path : str
        The CSV file.
    ground_temperature_k : float or "log", optional
        Air temperature on the pad, K, for the hypsometric height; ``"log"``
        takes the median ``temperature`` before launch.
    progress : callable(done, total), optional
        Called while reading.

    Raises
    ------
    LogError
        Not an AltOS header, a missing column, a bad cell (file line and
        column), time going backwards.
    """
    source = f"{os.path.basename(path)} (AltOS CSV)"
    time, column, dropped, repeated = _read_columns(path, progress)
    pressure = column["pressure"]
    pad = time < 0
    if not pad.any():
        pad = time <= time[0] + 1.0
    notes = ["time, acceleration, altitude (first), pressure"]
    temperature = column["temperature"] + 273.15 if "temperature" in column else None
    if ground_temperature_k is not None:
        baro = _hypsometric_height(path, pressure, temperature, pad, ground_temperature_k, notes)
        altitude_reference, ground_altitude = "pad", 0.0
    else:
        baro = column["altitude"]
        altitude_reference = "sea level"
        ground_altitude = None
    reference = velocity = None
    if "height" in column:
        if altitude_reference == "sea level":
            ground_altitude = _ground_altitude(column["altitude"], column["height"], pad)
        reference = column["height"] + (ground_altitude or 0.0)
        velocity = column.get("speed")
    imu = [column.get(f"accel_{axis}") for axis in "xyz"]
    gyro = [column.get(f"gyro_{axis}") for axis in "xyz"]
    log = LogData(
        source, time, column["acceleration"], baro, reference_altitude=reference, reference_velocity=velocity,
        reference_name="AltOS flight computer (height, speed)" if reference is not None else "",
        notes=notes, gps_altitude=column.get("gps_altitude"), gps_satellites=column.get("nsat"),
        accel=np.column_stack(imu) if all(a is not None for a in imu) else None,
        gyro=np.radians(np.column_stack(gyro)) if all(g is not None for g in gyro) else None,
        imu_frame="sensor" if all(a is not None for a in imu) else "",
        pressure=pressure, temperature=temperature, flight_state=column.get("state"), vehicle="rocket",
        altitude_reference=altitude_reference, ground_altitude=ground_altitude, repeated_timestamps=repeated)
    if dropped is not None:
        log.warn(f"{path}: line {dropped}: the last line is cut short (no newline at the end); dropped")
    return finish(log)


def _read_columns(path: str, progress):
    """Read the columns of an AltOS CSV that :func:`read_altos_csv` uses.

    Returns time (s, repeated stamps merged), role → column (units as in the
    file; ``gps_altitude`` NaN where there is no new locked fix; ``state``
    the ``state_name`` text), the line number of a cut-short last line (or
    None) and the count of repeated time stamps.
    """
    text = read_text(path, "AltOS CSV")
    if not looks_like_altos(text[:4096]):
        raise LogError(f"{path}: not an AltOS CSV (its first line does not start with {HEADER_START!r})")
    table = split_header(path, text, header_prefix="#")
    roles = {"time": table.index("time"), "acceleration": table.index("acceleration"),
             "pressure": table.index("pressure"), "altitude": table.index("altitude")}
    optional = {"height": ("height", 0), "speed": ("speed", 0), "temperature": ("temperature", 0),
                "accel_x": ("accel_x", 0), "accel_y": ("accel_y", 0), "accel_z": ("accel_z", 0),
                "gyro_x": ("gyro_roll", 0), "gyro_y": ("gyro_pitch", 0), "gyro_z": ("gyro_yaw", 0),
                "nsat": ("nsat", 0), "locked": ("locked", 0), "latitude": ("latitude", 0),
                "longitude": ("longitude", 0), "gps_altitude": ("altitude", 1)}
    for role, (name, occurrence) in optional.items():
        if sum(column == name for column in table.header) > occurrence:
            roles[role] = table.index(name, occurrence)
    order = sorted(set(roles.values()))
    data, lines, dropped = numeric_columns(table, order, progress)
    if data.shape[0] < 2:
        raise LogError(f"{path}: need at least 2 data rows, got {data.shape[0]}")
    column = {role: data[:, order.index(position)] for role, position in roles.items()}
    for role in ("time", "acceleration"):
        check_finite(path, role, column[role], lines)
    if "gps_altitude" in column:
        column["gps_altitude"] = _new_gps_fixes(column)
    if "state_name" in table.header:
        column["state"] = text_column(table, table.index("state_name"), lines)
    time, column, repeated = merge_repeated_timestamps(column.pop("time"), column, path, lines, "time")
    return time, column, dropped, repeated


def _new_gps_fixes(column: dict) -> np.ndarray:
    """GPS altitude (m) where the fix is locked and new (AltOS repeats the last fix on every row), else NaN."""
    fix = np.isfinite(column["gps_altitude"])
    if "locked" in column:
        fix &= column["locked"] == 1
    elif "nsat" in column:
        fix &= column["nsat"] >= 4
    moved = np.ones(fix.shape, dtype=bool)
    keys = [column[k] for k in ("gps_altitude", "latitude", "longitude") if k in column]
    same = np.all([np.concatenate([[False], key[1:] == key[:-1]]) for key in keys], axis=0)
    moved &= ~same
    return np.where(fix & moved, column["gps_altitude"], np.nan)


def _hypsometric_height(path, pressure, temperature, pad, ground_temperature_k, notes) -> np.ndarray:
    """Height above the pad, m, from pressure (Pa) and the ground temperature (K, or "log": the median
    ``temperature``, K, on the pad); appends a note."""
    good = pad & np.isfinite(pressure)
    if not good.any():
        raise LogError(f"{path}: column 'pressure': no value on the pad to start the hypsometric height from")
    ground_pa = float(np.median(pressure[good]))
    if ground_temperature_k == "log":
        warm = pad & np.isfinite(temperature) if temperature is not None else pad & False
        if not warm.any():
            raise LogError(f"{path}: column 'temperature': no value on the pad for the ground temperature")
        ground_temperature_k = float(np.median(temperature[warm]))
    elif not (isinstance(ground_temperature_k, (int, float)) and ground_temperature_k > 0):
        raise LogError(f"ground temperature must be a positive number of K or 'log', got {ground_temperature_k!r}")
    baro = height_above_ground(pressure, ground_pa, float(ground_temperature_k))
    notes.append(f"height above {_fmt(ground_pa)} Pa at {_fmt(ground_temperature_k)} K (hypsometric)")
    return baro


def _ground_altitude(altitude: np.ndarray, height: np.ndarray, pad: np.ndarray) -> Optional[float]:
    """The pad's altitude, m: median(altitude − height) on the pad (or anywhere), None if never both known."""
    both = np.isfinite(height) & np.isfinite(altitude)
    early = both & pad if (both & pad).any() else both
    return float(np.median(altitude[early] - height[early])) if early.any() else None
