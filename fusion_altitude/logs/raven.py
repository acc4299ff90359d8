"""Featherweight Raven flight-computer CSV exports (Featherweight Interface Program "export").

A Raven export holds several channels side by side, each with its own time
column: ``Time-Axial Accel (Gs), Axial Accel (Gs), bILBA, Time (s),
Altitude (Ft-AGL), bILBA``. A column whose name starts with ``Time`` is the
time base (s) of the columns after it up to the next time column; ``bILBA``
columns are status bits (launch detect, burnout, apogee…) as text such as
``b1110``. The accelerometer is exported at 400 Hz for the boost only (about
4.5 s), the baro altitude at 20 Hz for the whole flight.
"""

from __future__ import annotations

import os
from typing import Callable, List, Optional

import numpy as np

from .._core._common import GRAVITY
from ._checks import ALTITUDE_RANGE, drop_absurd
from ._data import LogData, LogError, fmt, finish
from ._table import Table, numeric_columns, read_table

#: Header names of the two channels the reader uses.
ACCEL_NAME = "Axial Accel (Gs)"
ALTITUDE_NAMES = {"Altitude (Ft-AGL)": "pad", "Altitude (Ft-MSL)": "sea level"}
FEET = 0.3048


def looks_like_raven(head: str) -> bool:
    """True if the first line of ``head`` is a Raven export header (a ``Time…`` column and a Raven channel)."""
    first = head.lstrip("\ufeff").lstrip().split("\n", 1)[0]
    names = [name.strip() for name in first.split(",")]
    return bool(names) and names[0].startswith("Time") and (
        ACCEL_NAME in names or any(name in names for name in ALTITUDE_NAMES))


def _time_bases(header: List[str]) -> List[Optional[int]]:
    """For every column, the position of its time column (the last ``Time…`` column before it), or None."""
    bases, current = [], None
    for position, name in enumerate(header):
        if name.startswith("Time"):
            current = position
            bases.append(None)
        else:
            bases.append(current)
    return bases


def read_raven(path: str, progress: Optional[Callable[[int, int], None]] = None) -> LogData:
    """Read a Featherweight Raven CSV export, merging its two time bases onto one grid.

    * ``Axial Accel (Gs)`` (specific force along the rocket's axis, g, +nose:
      ≈ +1 on the pad) on its time column → ``axial_acceleration`` (× 9.80665
      → m/s²) and ``vertical_acceleration`` = axial − g (the rocket taken as
      vertical) on the steps where it was sampled;
    * ``Altitude (Ft-AGL)`` on its time column → ``baro_altitude`` (ft → m,
      datum "pad"; ``Altitude (Ft-MSL)``: "sea level");
    * the grid is the union of both time columns (400 Hz during boost, 20 Hz
      after); between accelerometer samples the last one is held, and after
      the accelerometer's last sample ``vertical_acceleration`` is 0 m/s²
      (the estimators track the baro alone) — said in one :class:`LogWarning`.

    Absurd altitudes (outside −1 km…100 km) are dropped with a warning naming
    the file line; the status bits are not used.

    Raises
    ------
    LogError
        Not a Raven header, no altitude column, a bad cell (file line and column).
    """
    source = f"{os.path.basename(path)} (Featherweight Raven CSV)"
    table = read_table(path, "Raven CSV")  # the body left as the file's bytes for the C scan, decoded on demand
    if not looks_like_raven(",".join(table.header)):
        raise LogError(f"{path}: not a Featherweight Raven export (no 'Time…' column with {ACCEL_NAME!r} or "
                       f"'Altitude (Ft-AGL)')")
    altitude_name, positions = _channel_positions(path, table)
    order = sorted(set(positions.values()))
    data, lines, dropped = numeric_columns(table, order, progress)
    column = {role: data[:, order.index(position)] for role, position in positions.items()}
    altitude, message = drop_absurd(path, altitude_name, column["altitude"] * FEET, lines, *ALTITUDE_RANGE, "m",
                                    "baro altitude")
    baro_time, baro = _channel(path, table.header[positions["altitude_time"]], column["altitude_time"], altitude,
                               lines)
    if baro_time.size < 2:
        raise LogError(f"{path}: column {altitude_name!r}: fewer than 2 altitude samples")
    notes = [f"{altitude_name} (ft → m) on {table.header[positions['altitude_time']]!r}"]
    if "accel" in column:
        accel_time, accel = _channel(path, table.header[positions["accel_time"]], column["accel_time"],
                                     column["accel"] * GRAVITY, lines)
        notes.append(f"{ACCEL_NAME} (g → m/s², +nose) on {table.header[positions['accel_time']]!r}; "
                     f"vertical acceleration = axial − g (rocket taken as vertical)")
    else:
        accel_time, accel = np.zeros(0), np.zeros(0)
    time, baro_steps, accel_steps = _grid(baro_time, accel_time)
    log = LogData(source, time, _vertical(time, accel_steps, accel), _on_grid(time, baro_steps, baro), notes=notes,
                  vehicle="rocket", altitude_reference=ALTITUDE_NAMES[altitude_name],
                  ground_altitude=0.0 if ALTITUDE_NAMES[altitude_name] == "pad" else None,
                  axial_acceleration=_on_grid(time, accel_steps, accel) if accel.size else None,
                  baro_only=not accel.size)
    if dropped is not None:
        log.warn(f"{path}: line {dropped}: the last line is cut short (no newline at the end); dropped")
    if message is not None:
        log.warn(message)
    _warn_accelerometer_span(log, accel_time)
    return finish(log)


def _channel_positions(path: str, table: Table):
    """The altitude column's name, and the positions of the altitude, the accelerometer (if any) and their
    time columns (``altitude``, ``altitude_time``, ``accel``, ``accel_time``); LogError if one is missing."""
    bases = _time_bases(table.header)
    altitude_name = next((name for name in ALTITUDE_NAMES if name in table.header), None)
    if altitude_name is None:
        raise LogError(f"{path}: column 'Altitude (Ft-AGL)' not found; columns are {', '.join(table.header)}")
    positions = {"altitude": table.index(altitude_name)}
    positions["altitude_time"] = bases[positions["altitude"]]
    if ACCEL_NAME in table.header:
        positions["accel"] = table.index(ACCEL_NAME)
        positions["accel_time"] = bases[positions["accel"]]
    if any(position is None for position in positions.values()):
        raise LogError(f"{path}: a Raven channel without a 'Time…' column before it; columns are "
                       f"{', '.join(table.header)}")
    return altitude_name, positions


def _vertical(time: np.ndarray, accel_steps: np.ndarray, accel: np.ndarray) -> np.ndarray:
    """Vertical acceleration on the grid ``time`` (s), m/s²: the last axial sample (m/s²; sampled on the grid
    steps ``accel_steps``) held, minus g, up to the accelerometer's last sample; 0 after it (and without one)."""
    vertical = np.zeros(time.shape)
    if accel.size:
        sampled = time <= time[accel_steps[-1]]
        count = np.zeros(time.size, dtype=np.int64)
        count[accel_steps] = 1
        held = np.clip(np.cumsum(count) - 1, 0, accel.size - 1)  # the accelerometer samples at or before each step
        vertical[sampled] = accel[held[sampled]] - GRAVITY
    return vertical


def _on_grid(time: np.ndarray, steps: np.ndarray, values: np.ndarray) -> np.ndarray:
    """A channel's finite ``values`` on their grid ``steps``, NaN on the other steps of ``time``."""
    out = np.full(time.shape, np.nan)
    finite = np.isfinite(values)
    out[steps[finite]] = values[finite]
    return out


def _warn_accelerometer_span(log: LogData, accel_time: np.ndarray) -> None:
    """Warn that the accelerometer (sampled at ``accel_time``, s) ends before the log, or is absent."""
    time = log.time
    if accel_time.size and accel_time[-1] < time[-1]:
        log.warn(f"{log.source}: the accelerometer ends at {fmt(accel_time[-1])} s (the Raven exports it for the "
                 f"boost only) and the log at {fmt(time[-1])} s: vertical acceleration is 0 m/s² after "
                 f"{fmt(accel_time[-1])} s, the estimators track the baro alone there")
    elif not accel_time.size:
        log.warn(f"{log.source}: no {ACCEL_NAME!r} column: baro only (vertical acceleration 0 m/s²)")


def _channel(path: str, time_name: str, time: np.ndarray, values: np.ndarray, lines: np.ndarray):
    """One channel's own (time s, values) where both cells are present, time strictly increasing (LogError
    naming the line otherwise)."""
    present = np.isfinite(time) & ~np.isnan(values)
    time, values, lines = time[present], values[present], lines[present]
    back = np.flatnonzero(~(np.diff(time) > 0))
    if back.size:
        i = back[0] + 1
        raise LogError(f"{path}: line {int(lines[i])}, column {time_name!r}: time does not increase "
                       f"({fmt(time[i])} s after {fmt(time[i - 1])} s)")
    return time, values


def _grid(first: np.ndarray, second: np.ndarray):
    """The sorted distinct times of two increasing time arrays (s) — :func:`numpy.union1d`, by a stable sort, which
    merges the two sorted runs in linear time — and the grid step of each sample of each array."""
    both = np.concatenate([first, second])
    order = np.argsort(both, kind="stable")
    ordered = both[order]
    distinct = np.ones(both.size, dtype=bool)
    np.not_equal(ordered[1:], ordered[:-1], out=distinct[1:])
    step = np.empty(both.size, dtype=np.int64)
    step[order] = np.cumsum(distinct) - 1
    return ordered[distinct], step[:first.size], step[first.size:]
