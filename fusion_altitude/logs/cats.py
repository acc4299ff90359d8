"""CATS flight-computer CSV exports: split files ``*baro.csv``, ``*imu.csv`` (and ``*flight_info.csv``).

The CATS configurator exports one CSV per record type with a shared time
column ``ts`` (s, 0 = launch) and an ``id`` column naming the sensor
instance (``BARO0``, ``IMU0``, …). The reader is given the baro file, the
IMU file, the flight-info file or the directory holding them, and finds the
siblings by name (``<prefix>baro.csv`` ↔ ``<prefix>imu.csv`` ↔
``<prefix>flight_info.csv`` or ``<prefix>flightInfo.csv``).
"""

from __future__ import annotations

import os
from typing import Callable, Dict, Optional, Union

import numpy as np

from .._core._common import GRAVITY
from ..sensors import gyro_attitude, height_above_ground, vertical_acceleration
from ._checks import PRESSURE_RANGE, absurd_columns
from ._data import LogData, LogError, align, fmt, finish, merge_repeated_timestamps
from ._table import check_finite, read_columns, read_text, split_header

#: Accelerometer full scale for clip detection, m/s² (CATS Vega: ±16 g).
ACCEL_RANGE = 16 * GRAVITY
#: Samples this long before launch (s) are left out of the at-rest period (the launch itself).
REST_MARGIN = 0.2
_ROLES = {"baro": ("baro",), "imu": ("imu",), "info": ("flight_info", "flightinfo", "flight-info")}


def _split_name(path: str):
    """(directory, prefix, role) of a CATS file name, or None."""
    directory, name = os.path.split(path)
    lower = name.lower()
    if not lower.endswith(".csv"):
        return None
    stem = lower[:-4]
    for role, suffixes in _ROLES.items():
        for suffix in suffixes:
            if stem.endswith(suffix):
                return directory, name[:len(stem) - len(suffix)], role
    return None


def find_cats_files(path: str) -> Dict[str, str]:
    """The CATS files that belong together: ``{"baro": …, "imu": …, "info": …}`` (info optional).

    ``path`` is one of the files or a directory holding exactly one set.
    """
    candidates = []
    if os.path.isdir(path):
        for name in sorted(os.listdir(path)):
            split = _split_name(os.path.join(path, name))
            if split is not None and split[2] == "baro":
                candidates.append(split)
        if len(candidates) != 1:
            raise LogError(f"{path}: expected one CATS set (a *baro.csv with its *imu.csv) in the directory, "
                           f"found {len(candidates)}")
        directory, prefix, _ = candidates[0]
    else:
        split = _split_name(path)
        if split is None:
            raise LogError(f"{path}: not a CATS file name (expected *baro.csv, *imu.csv or *flight_info.csv)")
        directory, prefix, _ = split
    files = {}
    existing = {name.lower(): name for name in os.listdir(directory or ".")}
    for role, suffixes in _ROLES.items():
        for suffix in suffixes:
            name = existing.get(f"{prefix}{suffix}.csv".lower())
            if name is not None:
                files[role] = os.path.join(directory, name)
                break
    for role in ("baro", "imu"):
        if role not in files:
            raise LogError(f"{path}: CATS log without its {prefix}{_ROLES[role][0]}.csv next to it")
    return files


def looks_like_cats(path: str, head: str) -> bool:
    """A CATS split file: its name fits and its header starts with ``ts``."""
    first = head.lstrip("\ufeff").split("\n", 1)[0].replace(" ", "")
    return _split_name(path) is not None and first.startswith("ts,")


def _read(path: str, names, progress, instance_prefix: str, instance: Optional[int], checks=(), messages=None):
    """One CATS file's ``names`` columns for one sensor instance, repeated stamps merged; ``checks`` (role,
    name, low, high, unit, what, low_inclusive) drop absurd cells first, their warnings appended to ``messages``."""
    table = split_header(path, read_text(path, "CATS CSV"))
    positions = [table.index(name) for name in names]
    read = read_columns(table, positions, [table.index("id")] if table.has("id") else [], progress)
    data, lines, dropped = read.numbers, read.lines, read.dropped
    if data.shape[0] < 2:
        raise LogError(f"{path}: need at least 2 data rows, got {data.shape[0]}")
    column = {name: data[:, i] for i, name in enumerate(names)}
    note = ""
    if table.has("id"):
        ids = read.text[0] if data.shape[0] < 2_000_000 else None
        if ids is not None:
            present = sorted(set(ids.tolist()))
            wanted = f"{instance_prefix}{instance}" if instance is not None else present[0]
            if wanted not in present:
                raise LogError(f"{path}: column 'id': no {wanted!r} rows; present: {', '.join(present)}")
            keep = ids == wanted
            column = {name: values[keep] for name, values in column.items()}
            lines = lines[keep]
            note = f"{wanted}" + (f" of {', '.join(present)}" if len(present) > 1 else "")
    check_finite(path, "ts", column["ts"], lines)
    if checks and messages is not None:
        messages += absurd_columns(path, column, lines, checks)
    time, column, repeated = merge_repeated_timestamps(column.pop("ts"), column, path, lines, "ts")
    if time.size < 2:
        raise LogError(f"{path}: need at least 2 distinct time stamps, got {time.size}")
    return time, column, repeated, note, dropped


#: The note saying how ``vertical_acceleration`` was made (the rocket estimator does not use it: it takes the
#: raw accelerometer's long axis, and ``fusion-altitude run`` prints that instead).
ATTITUDE_NOTE = "attitude by gyro integration (ENU)"


def read_cats(path: str, instance: Optional[int] = None, ground_temperature_k: Union[None, float] = None,
              accel_range: float = ACCEL_RANGE, progress: Optional[Callable[[int, int], None]] = None) -> LogData:
    """Read a CATS flight-computer export (split CSVs) onto the IMU's time grid.

    * ``*imu.csv``: ``ts`` (s, 0 = launch), ``Ax, Ay, Az`` (m/s², sensor
      axes, specific force), ``Gx, Gy, Gz`` (°/s) → ``accel``, ``gyro``
      (rad/s), ``imu_frame="sensor"``. The attitude is integrated from the
      gyro from the at-rest attitude (levelled on the mean specific force
      before launch, the pre-launch mean rate removed as bias) with
      :func:`fusion_altitude.sensors.gyro_attitude`, and the specific force
      rotated to vertical acceleration (+up, gravity removed). Samples with
      any axis at or beyond ``accel_range`` are ``clipped``.
    * ``*baro.csv``: ``ts``, ``P`` (Pa), ``T`` (°C, the board's temperature)
      → ``pressure``, ``temperature`` (K), and the height above the pad
      (datum "pad") with :func:`fusion_altitude.sensors.height_above_ground`
      from the median pre-launch pressure (ground temperature: the ISA
      temperature there, or ``ground_temperature_k``).
    * ``*flight_info.csv`` (optional): ``height`` (m above the pad),
      ``velocity`` (m/s) → the reference; a ``state`` column, if present,
      → ``flight_state``.

    Parameters
    ----------
    path : str
        One of the files, or the directory holding the set.
    instance : int, optional
        Sensor instance (``IMU<n>``/``BARO<n>`` in the ``id`` column);
        default the first one present (the primary).
    ground_temperature_k : float, optional
        Air temperature on the pad, K. ``"log"`` is refused with a
        :class:`LogError`: the ``T`` column is the board's temperature
        (about 45 °C on the pad in the Hedy logs), not the air's.
    accel_range : float
        Accelerometer full scale, m/s², for clip detection.
    progress : callable(done, total), optional

    Raises
    ------
    LogError
        Missing sibling file or column, bad cell (file line, column), time
        going backwards, no pre-launch data.
    """
    files = find_cats_files(path)
    imu_read, baro_read, implausible = _read_sensors(files, progress, instance)
    time, imu, imu_repeats, imu_note, dropped_imu = imu_read
    baro_time, baro, baro_repeats, baro_note, dropped_baro = baro_read
    accel_body, gyro_dps, accel, clipped = _imu_vertical(files["imu"], time, imu, accel_range)
    pressure = align(time, baro_time, baro["P"])
    ground_pa = _pad_pressure(files["baro"], baro_time, baro, ground_temperature_k)
    notes = [f"{os.path.basename(files['imu'])} {imu_note}".strip(), f"{os.path.basename(files['baro'])} "
             f"{baro_note} (pad {fmt(ground_pa)} Pa)".strip(), ATTITUDE_NOTE]
    log = LogData(f"{os.path.basename(files['baro'])} + {os.path.basename(files['imu'])} (CATS CSV)", time, accel,
                  height_above_ground(pressure, ground_pa, ground_temperature_k), clipped=clipped, notes=notes,
                  accel=accel_body, gyro=np.radians(gyro_dps), imu_frame="sensor", pressure=pressure,
                  temperature=align(time, baro_time, baro["T"] + 273.15), vehicle="rocket",
                  altitude_reference="pad", ground_altitude=0.0, repeated_timestamps=imu_repeats)
    _warn_read(log, files, implausible, baro_repeats, ((dropped_imu, files["imu"]), (dropped_baro, files["baro"])))
    if "info" in files:
        _add_flight_info(log, files["info"], time, progress)
    return finish(log)


def _read_sensors(files: Dict[str, str], progress, instance: Optional[int]):
    """What :func:`_read` gives of the IMU file and of the baro file, and the warnings of implausible pressures."""
    imu = _read(files["imu"], ["ts", "Ax", "Ay", "Az", "Gx", "Gy", "Gz"], progress, "IMU", instance)
    implausible = []
    baro = _read(files["baro"], ["ts", "P", "T"], progress, "BARO", instance,
                 [("P", "P", *PRESSURE_RANGE, "Pa", "pressure", False)], implausible)
    return imu, baro, implausible


def _warn_read(log: LogData, files: Dict[str, str], implausible, baro_repeats: int, dropped) -> None:
    """The warnings of reading the files: implausible cells dropped, repeated baro stamps merged, last lines cut
    short (``dropped``: (file line or None, file) pairs)."""
    for message in implausible:
        log.warn(message)
    if baro_repeats:
        log.warn(f"{files['baro']}: {baro_repeats} rows repeated the timestamp of the row before; merged")
    for line, file in dropped:
        if line is not None:
            log.warn(f"{file}: line {line}: the last line is cut short (no newline at the end); dropped")


def _imu_vertical(file: str, time: np.ndarray, imu: Dict[str, np.ndarray], accel_range: float):
    """Accelerometer (m/s², n×3 sensor axes), gyro (°/s, n×3), vertical acceleration (m/s², +up, gravity
    removed; attitude integrated from the levelled at-rest attitude) and clip flags (any axis ≥
    ``accel_range``, m/s²) of a CATS IMU file."""
    rest = time < (0.0 - REST_MARGIN) if (time < -REST_MARGIN).sum() >= 10 else time <= time[0] + 1.0
    accel_body = np.column_stack([imu["Ax"], imu["Ay"], imu["Az"]])
    gyro_dps = np.column_stack([imu["Gx"], imu["Gy"], imu["Gz"]])
    for name in ("Ax", "Ay", "Az", "Gx", "Gy", "Gz"):
        bad = np.flatnonzero(~np.isfinite(imu[name]))
        if bad.size:
            raise LogError(f"{file}: column {name!r}: empty at ts {fmt(time[bad[0]])} s")
    at_rest = accel_body[rest].mean(axis=0)
    if not 0.5 * GRAVITY < float(np.linalg.norm(at_rest)) < 1.5 * GRAVITY:
        raise LogError(f"{file}: the mean specific force before launch is "
                       f"{fmt(np.linalg.norm(at_rest))} m/s², not about 1 g: cannot level the attitude")
    dt = np.diff(time, prepend=time[0] - (time[1] - time[0]))
    attitude = gyro_attitude(gyro_dps, dt, at_rest, gyro_dps[rest].mean(axis=0))
    accel = vertical_acceleration(accel_body, attitude, frame="ENU")
    clipped = np.any(np.abs(accel_body) >= accel_range, axis=1)
    return accel_body, gyro_dps, accel, clipped


def _pad_pressure(file: str, baro_time: np.ndarray, baro: Dict[str, np.ndarray], ground_temperature_k) -> float:
    """The pad's pressure, Pa: the median ``P`` before launch (or over the first second). Also refuses a
    ground temperature (K) that is not a positive number ("log" with its own message: ``T`` is the board's)."""
    baro_rest = baro_time < -REST_MARGIN if (baro_time < -REST_MARGIN).any() else baro_time <= baro_time[0] + 1.0
    good = baro_rest & np.isfinite(baro["P"])
    if not good.any():
        raise LogError(f"{file}: column 'P': no pressure before launch to take as the pad's")
    ground_pa = float(np.median(baro["P"][good]))
    if isinstance(ground_temperature_k, str):
        if ground_temperature_k.strip().lower() == "log":
            board = baro["T"][baro_rest & np.isfinite(baro["T"])]
            on_pad = f" (median {fmt(float(np.median(board)))} °C on the pad)" if board.size else ""
            raise LogError(f"{file}: column 'T' is the flight computer's board temperature{on_pad}, "
                           f"not the air's: give --ground-temperature in °C instead of 'log'")
        raise LogError(f"ground temperature must be a positive number of K, got {ground_temperature_k!r}")
    if ground_temperature_k is not None and not (isinstance(ground_temperature_k, (int, float))
                                                 and np.isfinite(ground_temperature_k) and ground_temperature_k > 0):
        raise LogError(f"ground temperature must be a positive number of K, got {ground_temperature_k!r}")
    return ground_pa


def _add_flight_info(log: LogData, file: str, time: np.ndarray, progress) -> None:
    """The reference (``height``, m above the pad; ``velocity``, m/s) and ``state`` of a CATS flight-info file,
    on the grid ``time`` (s)."""
    table = split_header(file, read_text(file, "CATS CSV"))
    names = ["ts"] + [name for name in ("height", "velocity") if table.has(name)]
    read = read_columns(table, [table.index(name) for name in names],
                        [table.index("state")] if "state" in table.header else [], progress)
    lines = read.lines
    info = {name: read.numbers[:, i] for i, name in enumerate(names)}
    check_finite(file, "ts", info["ts"], lines)
    if "state" in table.header:
        info["state"] = read.text[0]
    info_time, info, _ = merge_repeated_timestamps(info.pop("ts"), info, file, lines, "ts")
    if "height" in info and info_time.size >= 2:
        log.reference_altitude = np.interp(time, info_time, info["height"], left=np.nan, right=np.nan)
        if "velocity" in info:
            log.reference_velocity = np.interp(time, info_time, info["velocity"], left=np.nan, right=np.nan)
        log.reference_name = "CATS flight computer (flight info)"
    if "state" in info:
        index = np.clip(np.searchsorted(info_time, time, side="right") - 1, 0, info_time.size - 1)
        log.flight_state = info["state"][index]
