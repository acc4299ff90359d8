"""Missile Works RRC3 altimeter CSV exports (mDACS "export flight data"): baro only, no accelerometer.

Header ``time,altitude,pressure,velocity,temperature,events,voltages``:
time (s, 20 Hz), altitude (m above the pad), pressure (hPa), velocity (m/s,
+up, the altimeter's own baro-derived value), temperature (°C, the board's),
events (text: ``-`` for none, ``Drogue``, ``Main``…), voltages (V).
"""

from __future__ import annotations

import csv
import os
from typing import Callable, Dict, List, Optional, Tuple

import numpy as np

from . import _csv_fast
from ._checks import ALTITUDE_RANGE, PRESSURE_RANGE
from ._data import LogData, LogError, all_true, fmt, finish, merge_repeated_timestamps
from ._table import MISSING, Table, data_lines, lines_of_rows, read_table

#: The header's columns (lower case).
COLUMNS = ("time", "altitude", "pressure", "velocity", "temperature", "events", "voltages")
#: A logged velocity faster than this (m/s, about Mach 3) is not a rocket's: the row is garbage.
MAX_SPEED = 1_000.0
#: hPa → Pa.
HPA = 100.0


def looks_like_rrc3(head: str) -> bool:
    """True if the first line of ``head`` is an RRC3 export header."""
    return _names_rrc3(head.lstrip("\ufeff").lstrip().split("\n", 1)[0].split(","))


def _names_rrc3(cells: List[str]) -> bool:
    """True if the header cells (any case, spaces around) start with :data:`COLUMNS`' first four and name
    ``events``."""
    names = [name.strip().lower() for name in cells]
    return names[:4] == list(COLUMNS[:4]) and "events" in names


def _number(cell: str) -> float:
    cell = cell.strip()
    if cell.lower() in MISSING:
        return np.nan
    return float(cell)


def read_rrc3(path: str, progress: Optional[Callable[[int, int], None]] = None) -> LogData:
    """Read a Missile Works RRC3 CSV export.

    * ``time`` → ``time`` (s); ``altitude`` (m AGL) → ``baro_altitude``
      (datum "pad"); ``pressure`` (hPa → Pa) → ``pressure``; ``velocity``
      (m/s) → ``reference_velocity`` (the altimeter's own, baro-derived);
      ``temperature`` (°C → K) → ``temperature``.
    * No accelerometer: ``baro_only`` is True and ``vertical_acceleration``
      zeros (the estimators run as baro-only tracking filters).
    * ``events`` → ``flight_state`` (the latest event at or before each step,
      lower case: ``"pad"`` before the first, then e.g. ``"drogue"``,
      ``"main"``) and a note listing them with their times.

    Real-export quirks handled: rows whose temperature cell is missing (the
    events and voltages then sit one column left: a text cell where the
    temperature should be is taken as the event); garbage rows (an altitude
    outside −1 km…100 km, a pressure ≤ 0 or > 120 kPa, or a logged velocity
    beyond :data:`MAX_SPEED`) are dropped with one warning naming the file
    lines — their event is kept. A one-sample baro spike is kept (it is baro
    noise for the estimators).

    Raises
    ------
    LogError
        Not an RRC3 header, a bad number (file line and column), time going
        backwards.
    """
    table = read_table(path, "RRC3 CSV")  # the body left as the file's bytes for the C scan, decoded on demand
    if not _names_rrc3(table.header) and not looks_like_rrc3(",".join(table.header)):
        raise LogError(f"{path}: not an RRC3 export (its header does not start with "
                       f"{','.join(COLUMNS[:4])} and name 'events')")
    position = {name.lower(): i for i, name in enumerate(table.header)}
    data, lines, events, shifted = _rows_fast(table, position, progress) or _rows_python(table, position, progress)
    if data.shape[0] < 2:
        raise LogError(f"{path}: need at least 2 data rows, got {data.shape[0]}")
    if not all_true(np.isfinite(data[:, 0])):
        bad_time = np.flatnonzero(~np.isfinite(data[:, 0]))
        raise LogError(f"{path}: line {int(lines[bad_time[0]])}, column 'time': needs a number on every row")
    column = {name: data[:, i] for i, name in enumerate(("altitude", "pressure", "velocity", "temperature"), 1)}
    messages = _drop_garbage(path, data, column, lines)
    names, event_rows = events  # the event names, and each row's among them: merged as integers (the last row's)
    time, merged, repeated = merge_repeated_timestamps(data[:, 0], {**column, "events": event_rows}, path, lines,
                                                       "time")
    log = _log(f"{os.path.basename(path)} (RRC3 CSV)", time, merged, names, repeated, shifted)
    for message in messages:
        log.warn(message)
    return finish(log)


def _log(source: str, time: np.ndarray, merged: Dict[str, np.ndarray], names: np.ndarray, repeated: int,
         shifted: int) -> LogData:
    """The LogData of an RRC3 export's columns (``merged``: altitude m, pressure hPa, velocity m/s, temperature
    °C, events: each step's index into the event ``names``) on its time stamps (s), with the notes."""
    state, notes_events = _states(time, names, merged["events"])
    notes = ["time, altitude (m AGL), pressure (hPa), velocity (reference), temperature; no accelerometer: "
             "baro only"]
    if notes_events:
        notes.append("RRC3 events: " + ", ".join(notes_events))
    if shifted:
        notes.append(f"{shifted} row{'s' if shifted > 1 else ''} without a temperature cell (the events one "
                     f"column left): read as such")
    return LogData(source, time, np.zeros(time.shape), merged["altitude"], reference_velocity=merged["velocity"],
                   reference_name="RRC3 altimeter (baro-derived velocity)", notes=notes,
                   pressure=merged["pressure"] * HPA, temperature=merged["temperature"] + 273.15,
                   flight_state=state, vehicle="rocket", altitude_reference="pad", ground_altitude=0.0,
                   repeated_timestamps=repeated, baro_only=True)


def _rows_fast(table: Table, position: Dict[str, int], progress):
    """(time, altitude, pressure, velocity, temperature) rows, their file lines, events and the count of rows
    without a temperature cell, parsed by pyarrow (:func:`._csv_fast.read_numbers_and_text`: the four numeric
    columns as numbers, temperature and events as text, each distinct text cell read once as
    :func:`_rows_python` reads it); None where pyarrow refuses the text (a row of another length, a quote, a
    cell it does not read as a number), and :func:`_rows_python` reads it."""
    text = [position[name] for name in ("temperature", "events") if name in position]
    fast = _numbers_and_text(table, [position[name] for name in COLUMNS[:4]], text, progress)
    if fast is None:
        return None
    numbers, cells, lines = fast
    if len(cells) < 2:  # no temperature or no events column: an empty cell on every row for it
        nothing = (np.array([""], dtype=object), np.zeros(lines.size, dtype=np.int64))
        cells = [cells[0] if "temperature" in position else nothing, cells[-1] if "events" in position else nothing]
    (temperature_cells, temperature_rows), (event_cells, event_rows) = cells
    read = [_temperature_or_event(cell) for cell in temperature_cells]
    rows = np.empty((lines.size, 5))
    rows[:, :4] = numbers
    rows[:, 4] = np.array([value for value, _ in read], dtype=float)[temperature_rows]
    # each row's event: its temperature cell where that holds an event, else its events cell (names of both kinds
    # of distinct cell in one table, so the rows take theirs in one gather)
    names = _event_names([*temperature_cells.tolist(), *event_cells.tolist()])
    shifted = np.array([event for _, event in read], dtype=bool)[temperature_rows]
    events = np.where(shifted, temperature_rows, event_rows + temperature_cells.size)
    return rows, lines, (names, events), int(np.count_nonzero(shifted))


def _numbers_and_text(table: Table, numeric: List[int], text: List[int], progress):
    """The ``numeric`` columns (float64, rows × columns), the ``text`` columns as (distinct stripped cells, each
    row's index) and each row's file line; None where the fast parsers refuse the body. The C scan reads the
    file's bytes in place (:func:`._csv_fast.scan_bytes`, its line count giving the rows' lines) when the table
    has them; else the decoded body goes to :func:`._csv_fast.read_numbers_and_text`."""
    if table.raw is not None:
        scanned = _csv_fast.scan_bytes(table.raw, table.body_start, numeric, text, MISSING, progress)
        if scanned is not None:
            numbers, cells, line_count = scanned
            rows = numbers.shape[0]
            lines = np.arange(rows, dtype=np.int64) + table.first_line if rows == line_count else lines_of_rows(
                table, rows)
            return None if lines is None else (numbers, cells, lines)
    fast = _csv_fast.read_numbers_and_text(table.body, numeric, text, MISSING, progress, encoded=True)
    lines = None if fast is None else lines_of_rows(table, fast[0].shape[0])
    return None if lines is None else (fast[0], fast[1], lines)


def _event_names(cells: List[str]) -> np.ndarray:
    """Each event cell, or "" for none (a cell of :data:`MISSING`, any case); object array of str."""
    named = np.empty(len(cells), dtype=object)
    named[:] = ["" if cell.lower() in MISSING else cell for cell in cells]
    return named


def _temperature_or_event(cell: str) -> Tuple[float, bool]:
    """A stripped temperature cell as (°C, False), NaN if empty; (NaN, True) if it is text: an event (``-`` for
    none) in a row without its temperature cell."""
    try:
        return (float(cell) if cell else np.nan), False
    except ValueError:
        return np.nan, True


def _rows_python(table: Table, position: Dict[str, int], progress):
    """What :func:`_rows_fast` returns, line by line with :mod:`csv`; LogError naming the first bad cell."""
    rows, lines, events, shifted = [], [], [], 0
    total = table.body.count("\n") + 1
    for i, number, line in data_lines(table):
        try:
            cells = next(csv.reader([line]))
        except csv.Error as error:
            raise LogError(f"{table.path}: line {number}: not CSV ({error})") from None
        values = [_cell(table.path, number, name, cells, position[name]) for name in COLUMNS[:4]]
        event = ""
        temperature = np.nan
        if "temperature" in position and position["temperature"] < len(cells):
            temperature, is_event = _temperature_or_event(cells[position["temperature"]].strip())
            if is_event:  # text (an event, "-" for none): the temperature cell is missing, events moved left
                event, shifted = cells[position["temperature"]].strip(), shifted + 1
        if not event and "events" in position and position["events"] < len(cells):
            event = cells[position["events"]].strip()
        rows.append(values + [temperature])
        lines.append(number)
        events.append("" if event.lower() in MISSING else event)
        if progress is not None and i % 10_000 == 0:
            progress(i, total)
    data = np.array(rows, dtype=float).reshape(len(rows), 5)
    names = np.empty(len(events), dtype=object)
    names[:] = events
    return data, np.array(lines, dtype=np.int64), (names, np.arange(len(events))), shifted


def _drop_garbage(path: str, data: np.ndarray, column: Dict[str, np.ndarray], lines: np.ndarray) -> List[str]:
    """Set the altitude, pressure, velocity and temperature of garbage rows (:func:`_garbage_rows`) to NaN, in the
    rows ``data`` (time and those four; ``column``: views of them by name); the warning naming their lines, if
    any."""
    garbage = _garbage_rows(column)
    count = int(np.count_nonzero(garbage))
    if not count:
        return []
    where = ", ".join(str(n) for n in lines[garbage][:5].tolist()) + (" …" if count > 5 else "")
    first = int(garbage.nonzero()[0][0])
    message = (f"{path}: line{'s' if count > 1 else ''} {where}: garbage row"
               f"{'s' if count > 1 else ''} (altitude {fmt(column['altitude'][first])} m, "
               f"pressure {fmt(column['pressure'][first])} hPa, velocity {fmt(column['velocity'][first])} "
               f"m/s: not a plausible flight); dropped, their events kept")
    data[garbage, 1:] = np.nan  # the four columns of ``column``, in one assignment
    return [message]


def _cell(path: str, number: int, name: str, cells: List[str], position: int) -> float:
    if position >= len(cells):
        return np.nan
    try:
        return _number(cells[position])
    except ValueError:
        shown = cells[position].strip()[:40]
        raise LogError(f"{path}: line {number}, column {name!r}: {shown!r} is not a number") from None


def _garbage_rows(column: dict) -> np.ndarray:
    """Rows whose altitude (m), pressure (hPa) or logged velocity (m/s) is not a flight's: an altitude outside
    :data:`ALTITUDE_RANGE`, a pressure (in Pa) outside :data:`PRESSURE_RANGE` (its low end excluded) — the cells
    :func:`._checks.drop_absurd` drops, infinities included — or a speed above :data:`MAX_SPEED`. NaN cells are none of
    these (a comparison with NaN is False)."""
    altitude, pressure = column["altitude"], column["pressure"] * HPA
    with np.errstate(invalid="ignore"):
        garbage = (altitude < ALTITUDE_RANGE[0]) | (altitude > ALTITUDE_RANGE[1])
        garbage |= (pressure <= PRESSURE_RANGE[0]) | (pressure > PRESSURE_RANGE[1])
        garbage |= np.abs(column["velocity"]) > MAX_SPEED
    return garbage


def _states(time: np.ndarray, names: np.ndarray, events: np.ndarray):
    """Flight state on every step (the latest event, lower case; "pad" before the first) and the notes; ``events``:
    each step's index into the event ``names`` (str: "" for none)."""
    named = np.asarray(names != "", dtype=bool)[events]
    marks = named.nonzero()[0]
    notes = [f"{names[events[i]]} at {fmt(time[i])} s" for i in marks]
    states = np.empty(marks.size + 1, dtype=object)
    states[:] = ["pad"] + [str(names[events[i]]).lower() for i in marks]
    return states[np.cumsum(named)], notes  # each step: the count of events at or before it
