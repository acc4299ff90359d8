"""Generic CSV logs: the caller names the columns."""

from __future__ import annotations

import csv
import os
from typing import Optional

import numpy as np

from .._common import GRAVITY
from ..sensors import pressure_to_altitude
from ._data import LogData, LogError


def read_csv_log(path: str, time_column: str, accel_column: str, baro_column: Optional[str] = None,
                 pressure_column: Optional[str] = None, accel_units: str = "m/s^2",
                 sea_level_pa: float = 101325.0, reference_column: Optional[str] = None) -> LogData:
    """Read a CSV log with a header row.

    Parameters
    ----------
    path : str
        CSV file (comma separated, header on the first line).
    time_column : str
        Time, s; must increase strictly (irregular steps are fine).
    accel_column : str
        Vertical acceleration, earth frame, +up, gravity removed, in
        ``accel_units``; every row needs one.
    baro_column : str, optional
        Baro altitude, m; an empty cell or ``nan`` means no baro that row.
    pressure_column : str, optional
        Static pressure, Pa, converted with the ISA troposphere formula
        (:func:`fusion_altitude.sensors.pressure_to_altitude`) relative to
        ``sea_level_pa``. Give ``baro_column`` or this, not both.
    accel_units : {"m/s^2", "g"}
        Units of the acceleration column.
    sea_level_pa : float
        Reference pressure for ``pressure_column``, Pa.
    reference_column : str, optional
        A better altitude for (part of) the log, m (RTK GPS, motion capture);
        an empty cell or ``nan`` means unknown. Becomes ``reference_altitude``.

    Raises
    ------
    LogError
        Missing file or column, a cell that is not a number (naming column
        and line), time not increasing (naming the line).
    """
    if (baro_column is None) == (pressure_column is None):
        raise LogError("give exactly one of a baro altitude column or a pressure column")
    if accel_units not in ("m/s^2", "g"):
        raise LogError(f"accel units must be 'm/s^2' or 'g', got {accel_units!r}")
    try:
        handle = open(path, newline="")
    except OSError as error:
        raise LogError(f"cannot open {path}: {error.strerror}") from None
    with handle:
        reader = csv.reader(handle)
        try:
            header = [name.strip() for name in next(reader)]
        except StopIteration:
            raise LogError(f"{path} is empty") from None
        wanted = {"time": time_column, "accel": accel_column, "baro": baro_column or pressure_column}
        if reference_column is not None:
            wanted["reference"] = reference_column
        index = {}
        for role, name in wanted.items():
            if name not in header:
                raise LogError(f"{path}: column {name!r} not found; columns are {', '.join(header)}")
            index[role] = header.index(name)
        columns = {role: [] for role in wanted}
        for line_number, row in enumerate(reader, start=2):
            if not row or all(not cell.strip() for cell in row):
                continue
            for role, name in wanted.items():
                cell = row[index[role]].strip() if index[role] < len(row) else ""
                if role in ("baro", "reference") and cell.lower() in ("", "nan", "na", "null"):
                    columns[role].append(np.nan)
                    continue
                try:
                    value = float(cell)
                except ValueError:
                    raise LogError(f"{path}: line {line_number}, column {name!r}: {cell!r} is not a number") from None
                if role in ("time", "accel") and not np.isfinite(value):
                    raise LogError(f"{path}: line {line_number}, column {name!r}: {cell!r} must be finite")
                columns[role].append(value)
    time = np.asarray(columns["time"], dtype=float)
    if time.size < 2:
        raise LogError(f"{path}: need at least 2 data rows, got {time.size}")
    bad = np.flatnonzero(~(np.diff(time) > 0))
    if bad.size:
        raise LogError(f"{path}: line {bad[0] + 3}, column {time_column!r}: time {time[bad[0] + 1]!r} s does not "
                       f"increase (previous row {time[bad[0]]!r} s)")
    accel = np.asarray(columns["accel"], dtype=float) * (GRAVITY if accel_units == "g" else 1.0)
    baro = np.asarray(columns["baro"], dtype=float)
    if pressure_column is not None:
        baro = pressure_to_altitude(baro, sea_level_pa)
    reference = np.asarray(columns["reference"], dtype=float) if reference_column is not None else None
    return LogData(f"{os.path.basename(path)} (CSV)", time, accel, baro, reference_altitude=reference,
                   reference_name=f"column {reference_column!r}" if reference_column is not None else "",
                   notes=[f"time {time_column!r}, accel {accel_column!r} ({accel_units}), "
                          + (f"baro {baro_column!r} (m)" if baro_column else f"pressure {pressure_column!r} (Pa)")])
