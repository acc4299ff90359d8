"""AltOS CSV exports (Altus Metrum TeleMega, TeleMetrum, EasyMega, EasyMini…), recognised by their header."""

from __future__ import annotations

import os
from typing import Callable, Optional, Union

import numpy as np

from .._core._common import GRAVITY
from ..sensors import height_above_ground
from ._checks import ALTITUDE_RANGE, ALTOS_MISSING, PRESSURE_RANGE, absurd_columns, dead_message, is_dead
from ._data import LogData, LogError, fmt, finish, merge_repeated_timestamps
from ._table import check_finite, read_columns, read_text, split_header

#: The header line of an AltOS CSV starts with this (after an optional BOM and ``#`` comment lines).
HEADER_START = "#version,serial,flight"
#: Every column name AltosUI has written (``altoslib/AltosCSV.java``, CSV versions 4–6 and the current one),
#: for repairing the AltOS 1.4 header defect (a missing comma glues two names together).
KNOWN_COLUMNS = frozenset((
    "version", "serial", "flight", "call", "time", "clock", "rssi", "lqi", "state", "state_name", "acceleration",
    "pressure", "altitude", "height", "speed", "accel_speed", "baro_speed", "temperature", "battery_voltage",
    "drogue_voltage", "main_voltage", "accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z", "gyro_roll",
    "gyro_pitch", "gyro_yaw", "mag_x", "mag_y", "mag_z", "tilt", "pyro", "connected", "locked", "nsat", "latitude",
    "longitude", "year", "month", "day", "hour", "minute", "second", "pad_dist", "pad_range", "pad_az", "pad_el",
    "pdop", "hdop", "vdop", "mode", "companion_id", "companion_time", "companion_update", "companion_channels"))
#: Full scale of the TeleMega / EasyMega IMU accelerometer, m/s² (±16 g); a sample at 97 % of it is clipped.
IMU_RANGE = 16 * GRAVITY
CLIP_FRACTION = 0.97


def _first_lines(head: str):
    """The header line of ``head`` (after ``#`` comment lines) and the comment lines before it."""
    preamble = []
    for line in head.lstrip("\ufeff").split("\n"):
        stripped = line.strip()
        if not stripped:
            continue
        if stripped.startswith("#") and not stripped.startswith(HEADER_START):
            preamble.append(stripped)
            continue
        return stripped, preamble
    return "", preamble


def looks_like_altos(head: str) -> bool:
    """True if ``head`` starts with an AltOS CSV header (``#`` comment lines, e.g. AltOS 1.4's, may precede it)."""
    if HEADER_START not in head:  # the header line starts with it: not an AltOS log, without splitting its lines
        return False
    first, _ = _first_lines(head)
    return first.startswith(HEADER_START) and "state_name" in first and ",time," in first


def read_altos_csv(path: str, ground_temperature_k: Union[None, float, str] = None,
                   progress: Optional[Callable[[int, int], None]] = None) -> LogData:
    """Read an AltOS CSV export (AltosUI "Export data" / ``altosui`` CSV) with no column options.

    The header line starts ``#version,serial,flight,call,time,…`` — with
    ``clock,rssi,lqi`` after ``time`` in ground-station telemetry exports —
    and names ``altitude`` twice: the first is the flight computer's pressure
    altitude (m above sea level), the second (after ``latitude,longitude``)
    the GPS altitude. ``#`` comment lines before it (AltOS 1.4: ``# Config
    version``, ``# Serial number``, ``# Software version``) are skipped and
    the software version noted; AltOS 1.4's header defect (a missing comma:
    ``main_voltageaccel_x``, one name fewer than cells) is repaired with a
    one-line warning. Columns used:

    * ``time`` (s from launch, negative on the pad) → ``time``;
    * ``acceleration`` (m/s², along the rocket's axis from the high-g
      accelerometer; AltOS removes the pad's 1 g, so ≈ 0 on the pad) →
      ``axial_acceleration`` (specific force, + g: ≈ +9.81 on the pad) and
      ``vertical_acceleration`` (the rocket taken as vertical, as AltOS
      does), in preference to the IMU. EasyMini (no accelerometer: the column
      absent, empty, the AltOS "missing" value or dead) → ``baro_only``;
    * ``altitude`` (first) → ``baro_altitude`` (datum "sea level"), or with
      ``ground_temperature_k`` the hypsometric height above the pad from
      ``pressure`` (datum "pad");
    * ``height`` (m above the pad) → ``reference_altitude`` (+ the pad's
      altitude, so it shares the baro's datum), ``speed`` (or
      ``accel_speed``, else ``baro_speed``) → ``reference_velocity``;
      ``ground_altitude`` = median(altitude − height);
    * ``pressure`` (Pa), ``temperature`` (°C → K), ``state_name`` →
      ``flight_state``; TeleMega / EasyMega ``accel_x/y/z`` (m/s²) and
      ``gyro_roll/pitch/yaw`` or ``gyro_x/y/z`` (°/s → rad/s) →
      ``accel``/``gyro`` (``imu_frame="sensor"``) when alive: an IMU whose
      three axes are all constant (all zero) is dead and not used (one
      warning); rows where all three read exactly 0 (no IMU sample yet) hold
      the next live row; samples at ≥ 97 % of ±16 g are ``clipped`` (one
      warning: the IMU saturates in boost; the along-axis ``acceleration``
      does not);
    * GPS: the second ``altitude`` where the fix is locked (``locked`` = 1, or
      ``nsat`` ≥ 4 without that column) and the position changed since the
      row before (AltOS repeats the last fix on every row); ``nsat``.

    Several rows often share one time stamp (one per telemetry packet):
    they are merged by the rule of :func:`merge_repeated_timestamps`
    (numbers averaged, the state: last) and counted in a warning. Absurd
    altitudes and pressures are dropped with a warning naming the file line
    (:mod:`fusion_altitude.logs._checks`).

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
    time, column, dropped, repeated, messages, notes = _read_columns(path, progress)
    pad = time < 0
    if not pad.any():
        pad = time <= time[0] + 1.0
    notes.insert(0, "time, acceleration, altitude (first), pressure")
    temperature = column["temperature"] + 273.15 if "temperature" in column else None
    baro, altitude_reference, ground_altitude, reference, velocity = _baro_and_reference(
        path, column, temperature, pad, ground_temperature_k, notes)
    vertical, axial, baro_only, accel_message = _axial(source, column.get("acceleration"), pad, notes)
    if accel_message is not None:
        messages.append(accel_message)
    imu, clipped, imu_messages = _imu(source, time, [column.get(f"accel_{axis}") for axis in "xyz"], pad, notes)
    messages += imu_messages
    gyro = [column.get(f"gyro_{axis}") for axis in "xyz"]
    gyro = np.radians(np.column_stack(gyro)) if imu is not None and all(g is not None for g in gyro) else None
    if baro_only and imu is not None:  # no along-axis accelerometer: the IMU axis is the rocket estimator's to choose
        notes.append("no along-axis 'acceleration': vertical acceleration 0 m/s² (baro only); the IMU is raw")
    log = LogData(
        source, time, vertical, baro, reference_altitude=reference, reference_velocity=velocity,
        reference_name="AltOS flight computer (height, speed)" if reference is not None else "",
        clipped=clipped, notes=notes, gps_altitude=column.get("gps_altitude"), gps_satellites=column.get("nsat"),
        accel=imu, gyro=gyro, imu_frame="sensor" if imu is not None else "",
        pressure=column["pressure"], temperature=temperature, flight_state=column.get("state"), vehicle="rocket",
        altitude_reference=altitude_reference, ground_altitude=ground_altitude, repeated_timestamps=repeated,
        axial_acceleration=axial, baro_only=baro_only)
    if dropped is not None:
        log.warn(f"{path}: line {dropped}: the last line is cut short (no newline at the end); dropped")
    for message in messages:
        log.warn(message)
    return finish(log)


def _baro_and_reference(path: str, column: dict, temperature: Optional[np.ndarray], pad: np.ndarray,
                        ground_temperature_k, notes: list):
    """(baro altitude m, its datum, the pad's altitude m or None, the flight computer's height m in the baro's
    datum or None, its velocity m/s or None): the first ``altitude`` (datum "sea level"), or with
    ``ground_temperature_k`` the hypsometric height above the pad (datum "pad"); ``height`` + the pad's
    altitude, ``speed`` (else ``accel_speed``, ``baro_speed``)."""
    if ground_temperature_k is not None:
        baro = _hypsometric_height(path, column["pressure"], temperature, pad, ground_temperature_k, notes)
        altitude_reference, ground_altitude = "pad", 0.0
    else:
        baro, altitude_reference, ground_altitude = column["altitude"], "sea level", None
    if "height" not in column:
        return baro, altitude_reference, ground_altitude, None, None
    if altitude_reference == "sea level":
        ground_altitude = _ground_altitude(column["altitude"], column["height"], pad)
    reference = column["height"] + (ground_altitude or 0.0)
    velocity = next((column[name] for name in ("speed", "accel_speed", "baro_speed") if name in column), None)
    return baro, altitude_reference, ground_altitude, reference, velocity


def _filled(values: np.ndarray) -> np.ndarray:
    """NaN samples hold the last finite one (the first finite one before it starts); all NaN → zeros."""
    finite = np.isfinite(values)
    if not finite.any():
        return np.zeros(values.shape)
    index = np.where(finite, np.arange(values.size), 0)
    np.maximum.accumulate(index, out=index)
    index[:np.flatnonzero(finite)[0]] = np.flatnonzero(finite)[0]
    return values[index]


def _axial(source: str, acceleration: Optional[np.ndarray], pad: np.ndarray, notes: list):
    """(vertical acceleration m/s², axial specific force m/s² or None, baro_only, warning or None) from the
    ``acceleration`` column (m/s², AltOS: ≈ 0 on the pad; a column reading ≈ +1 g on the pad is specific force)."""
    n = pad.size
    if acceleration is None:
        return np.zeros(n), None, True, f"{source}: no 'acceleration' column (an EasyMini: baro only)"
    values = np.where(np.abs(acceleration) >= ALTOS_MISSING, np.nan, acceleration)
    if not np.isfinite(values).any():
        return np.zeros(n), None, True, (f"{source}: column 'acceleration' has no value (no accelerometer, as on an "
                                         f"EasyMini): baro only, vertical acceleration 0 m/s²")
    if is_dead(values):
        return np.zeros(n), None, True, dead_message(source, "column 'acceleration'", values, "m/s²",
                                                     "baro only, vertical acceleration 0 m/s²")
    at_rest = pad & np.isfinite(values)
    rest = float(np.median(values[at_rest])) if at_rest.any() else 0.0
    if 0.75 * GRAVITY < rest < 1.25 * GRAVITY:  # specific force, gravity still in it
        axial, vertical = values, values - GRAVITY
        notes.append("'acceleration' reads +1 g on the pad: specific force; vertical = acceleration − g")
    else:
        axial, vertical = values + GRAVITY, values
    message = None
    missing = ~np.isfinite(vertical)
    if missing.any():
        message = (f"{source}: column 'acceleration' is empty on {int(missing.sum())} of {n} samples; the last value "
                   f"is held there")
    return _filled(vertical), axial, False, message


def _imu(source: str, time: np.ndarray, axes: list, pad: np.ndarray, notes: list):
    """(accel (N, 3) m/s² or None, clipped or None, warnings) from ``accel_x/y/z``: None when absent, dead or not
    reading about 1 g on the pad (raw counts, another unit)."""
    if any(axis is None for axis in axes):
        return None, None, []
    accel = np.column_stack(axes)
    if is_dead(accel) or not np.isfinite(accel).any():
        return None, None, [dead_message(source, "the IMU (accel_x, accel_y, accel_z)", accel, "m/s²",
                                         "the along-axis 'acceleration' is used; no INS on this log")]
    messages = []
    silent = np.all(accel == 0, axis=1) | ~np.all(np.isfinite(accel), axis=1)
    rest = pad & ~silent
    if rest.any():
        norm = float(np.median(np.linalg.norm(accel[rest], axis=1)))
        if not 0.5 * GRAVITY < norm < 1.5 * GRAVITY:
            return None, None, [f"{source}: the IMU (accel_x, accel_y, accel_z) reads {fmt(norm)} on the pad, not "
                                f"about 9.81 m/s² (raw counts or another unit?): not used; the along-axis "
                                f"'acceleration' is used; no INS on this log"]
    if silent.any():
        live = np.flatnonzero(~silent)
        index = live[np.clip(np.searchsorted(live, np.arange(time.size)), 0, live.size - 1)]
        index = np.where(silent, index, np.arange(time.size))
        accel = accel[index]
        notes.append(f"IMU: {int(silent.sum())} samples without an IMU reading (all axes 0 or empty) hold the "
                     f"nearest live one")
    clipped = np.any(np.abs(accel) >= CLIP_FRACTION * IMU_RANGE, axis=1)
    if clipped.any():
        first, last = np.flatnonzero(clipped)[[0, -1]]
        messages.append(f"{source}: the IMU accelerometer saturates (±16 g) on {int(clipped.sum())} samples "
                        f"({fmt(time[first])}–{fmt(time[last])} s): marked clipped; the along-axis 'acceleration' "
                        f"(high-g) gives the vertical acceleration")
    return accel, clipped, messages


def _repair_header(path: str, table) -> Optional[str]:
    """Split header names that are two known AltOS names glued together (AltOS 1.4's missing comma) when the
    first data line has that many more cells; returns the warning line or None."""
    first = next((line for line in table.body.split("\n") if line.strip()), "")
    extra = first.count(",") + 1 - len(table.header)
    if extra <= 0:
        return None
    repaired, glued = [], []
    for name in table.header:
        split = None
        if name not in KNOWN_COLUMNS and len(glued) < extra:
            split = next(((name[:k], name[k:]) for k in range(1, len(name))
                          if name[:k] in KNOWN_COLUMNS and name[k:] in KNOWN_COLUMNS), None)
        if split is None:
            repaired.append(name)
        else:
            repaired.extend(split)
            glued.append(f"{name!r} → {split[0]!r}, {split[1]!r}")
    if not glued:
        return None
    table.header[:] = repaired
    return (f"{path}: header defect of AltOS 1.4 (a missing comma; {len(repaired) - len(glued)} names for "
            f"{len(repaired)} cells): {'; '.join(glued)}; repaired")


def _read_columns(path: str, progress):
    """Read the columns of an AltOS CSV that :func:`read_altos_csv` uses.

    Returns time (s, repeated stamps merged), role → column (units as in the
    file; ``gps_altitude`` NaN where there is no new locked fix; ``state``
    the ``state_name`` text), the line number of a cut-short last line (or
    None), the count of repeated time stamps, warning lines and notes.
    """
    text = read_text(path, "AltOS CSV")
    if not looks_like_altos(text[:8192]):
        raise LogError(f"{path}: not an AltOS CSV (no line starting with {HEADER_START!r} after its comments)")
    table = split_header(path, text, header_prefix="#", header_start=HEADER_START)
    messages, notes = [], []
    repair = _repair_header(path, table)
    if repair is not None:
        messages.append(repair)
    version = next((line.partition(":")[2].strip() for line in table.preamble
                    if line.lower().startswith("# software version")), None)
    if version:
        notes.append(f"AltOS {version}")
    roles = {"time": table.index("time"), "pressure": table.index("pressure"), "altitude": table.index("altitude")}
    optional = {"rssi": ("rssi", 0), "acceleration": ("acceleration", 0), "height": ("height", 0),
                "speed": ("speed", 0),
                "accel_speed": ("accel_speed", 0), "baro_speed": ("baro_speed", 0),
                "temperature": ("temperature", 0),
                "accel_x": ("accel_x", 0), "accel_y": ("accel_y", 0), "accel_z": ("accel_z", 0),
                "nsat": ("nsat", 0), "locked": ("locked", 0), "latitude": ("latitude", 0),
                "longitude": ("longitude", 0), "gps_altitude": ("altitude", 1)}
    gyro_names = ("gyro_roll", "gyro_pitch", "gyro_yaw") if "gyro_roll" in table.header else ("gyro_x", "gyro_y",
                                                                                               "gyro_z")
    optional.update({f"gyro_{axis}": (name, 0) for axis, name in zip("xyz", gyro_names)})
    for role, (name, occurrence) in optional.items():
        if sum(column == name for column in table.header) > occurrence:
            roles[role] = table.index(name, occurrence)
    order = sorted(set(roles.values()))
    state = [table.index("state_name")] if "state_name" in table.header else []
    read = read_columns(table, order, state, progress)  # the state names in the same pass
    data, lines, dropped = read.numbers, read.lines, read.dropped
    if data.shape[0] < 2:
        raise LogError(f"{path}: need at least 2 data rows, got {data.shape[0]}")
    column = {role: data[:, order.index(position)] for role, position in roles.items()}
    check_finite(path, "time", column["time"], lines)
    rssi = column.pop("rssi", None)
    if rssi is not None and np.any(np.nan_to_num(rssi) != 0):  # flight-computer downloads write rssi 0
        notes.append("ground-station telemetry recording (rssi, lqi): packets lost, the time steps are irregular")
    messages += absurd_columns(path, column, lines, [
        ("altitude", "altitude", *ALTITUDE_RANGE, "m", "baro altitude", True),
        ("height", "height", *ALTITUDE_RANGE, "m", "height", True),
        ("pressure", "pressure", *PRESSURE_RANGE, "Pa", "pressure", False)])
    if "gps_altitude" in column:
        column["gps_altitude"] = _new_gps_fixes(column)
    if state:
        column["state"] = read.text[0]
    time, column, repeated = merge_repeated_timestamps(column.pop("time"), column, path, lines, "time")
    return time, column, dropped, repeated, messages, notes


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
    notes.append(f"height above {fmt(ground_pa)} Pa at {fmt(ground_temperature_k)} K (hypsometric)")
    return baro


def _ground_altitude(altitude: np.ndarray, height: np.ndarray, pad: np.ndarray) -> Optional[float]:
    """The pad's altitude, m: median(altitude − height) on the pad (or anywhere), None if never both known."""
    both = np.isfinite(height) & np.isfinite(altitude)
    early = both & pad if (both & pad).any() else both
    return float(np.median(altitude[early] - height[early])) if early.any() else None
