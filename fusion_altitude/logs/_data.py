"""The common shape of every log: :class:`LogData` on one time grid, :class:`LogError`, grid helpers."""

from __future__ import annotations

import contextlib
import math
import sys
import threading
import warnings
from dataclasses import dataclass, field
from typing import List, Optional, Tuple

import numpy as np


class LogError(ValueError):
    """A log cannot be read or used; the one-line message names the file, the line or message, and the column.

    Line breaks in the message (e.g. from a third-party parser's error) are
    folded into spaces, so the message is always one line.
    """

    def __init__(self, message: str = ""):
        super().__init__(" ".join(str(message).split()))


class LogWarning(UserWarning):
    """A log was read but something in it deserves a look (repeated timestamps, gaps, odd units)."""


#: A step longer than this many median steps counts as a logging gap ...
GAP_FACTOR = 10.0
#: ... and never one shorter than this, s.
GAP_MIN_SECONDS = 0.1


@dataclass
class LogData:
    """A log on the observer's time grid.

    Every array field has one entry per grid step (the accelerometer's
    timestamps, possibly irregular). Sensors slower than the grid are placed
    on the first grid step at or after their own timestamp and are NaN on
    the other steps ("NaN = no new sample on this step"). Optional fields are
    ``None`` when the log does not have that quantity.

    Attributes
    ----------
    source : str
        File name and format, e.g. ``"flight.csv (AltOS CSV)"``.
    time : numpy.ndarray
        Sample times, s, strictly increasing (irregular allowed). Logs with
        their own epoch (AltOS, CATS: 0 = launch, negative on the pad; CSVs:
        as written) keep it; ULog and DataFlash start at 0.
    vertical_acceleration : numpy.ndarray
        Observer input, m/s², earth frame, +up, gravity removed.
    baro_altitude : numpy.ndarray
        Baro altitude, m, +up, datum given by ``altitude_reference``; NaN on
        steps without a new baro sample.
    reference_altitude, reference_velocity : numpy.ndarray or None
        The flight computer's / autopilot's own height (m, **same datum as
        ``baro_altitude``**) and vertical velocity (m/s, +up), if the log has
        them. NaN where unknown.
    reference_name : str
        Where the reference came from.
    clipped : numpy.ndarray of bool or None
        True on samples where the accelerometer was at its range limit.
    notes : list of str
        What the reader chose (topics, instances, columns), for the report.
    gps_altitude : numpy.ndarray or None
        GPS altitude above mean sea level, m; NaN between fixes and whenever
        the receiver has no 3D fix (fix status respected).
    gps_accuracy : numpy.ndarray or None
        Vertical 1σ accuracy of ``gps_altitude``, m, as the receiver reports
        it; NaN unknown.
    gps_satellites : numpy.ndarray or None
        Satellites used in the fix (float; NaN unknown), on GPS steps.
    rangefinder : numpy.ndarray or None
        Distance to the ground, m (rangefinder / lidar / sonar, as logged);
        NaN on steps without a valid reading.
    accel : numpy.ndarray or None, shape (N, 3)
        Raw accelerometer, specific force, m/s², body frame ``imu_frame``
        (a level vehicle at rest reads −9.81 on the "down" axis of an FRD
        frame, +9.81 on the "up" axis of an FLU frame).
    gyro : numpy.ndarray or None, shape (N, 3)
        Raw gyroscope, rad/s, body frame ``imu_frame`` (right-handed).
    imu_frame : str
        Axes of ``accel``/``gyro``: ``"FRD"`` (x forward, y right, z down;
        PX4, ArduPilot, CSV with ``frame="NED"``), ``"FLU"`` (x forward,
        y left, z up; CSV ``"NWU"``), ``"RFU"`` (x right, y forward, z up;
        CSV ``"ENU"``), ``"sensor"``
        (the board's own axes, unknown mounting: AltOS, CATS), or ``""``
        when there is no raw IMU.
    pressure : numpy.ndarray or None
        Static pressure, Pa, on baro steps (NaN elsewhere).
    temperature : numpy.ndarray or None
        Temperature the log reports with the baro, K (often the board's
        temperature, not the air's), on baro steps (NaN elsewhere).
    flight_state : numpy.ndarray of str or None
        The flight computer's own flight state on every step (the latest one
        logged at or before it), e.g. AltOS ``state_name`` (``"pad"``,
        ``"boost"``, ``"coast"``, ``"drogue"``, ``"main"``, ``"landed"``) or
        ArduPilot/PX4 ``"armed"``/``"disarmed"`` where known.
    vehicle : str
        Hint of the kind of vehicle: ``"rocket"`` (AltOS, CATS), ``"copter"``,
        ``"plane"``, ``"rover"`` or ``""`` unknown.
    altitude_reference : str
        Datum of ``baro_altitude`` and ``reference_altitude``:
        ``"sea level"`` (pressure altitude, ISA or the flight computer's own
        table), ``"pad"`` (0 at the launch pad / start of the log) or ``""``
        (an arbitrary datum, e.g. an autopilot's own origin).
    ground_altitude : float or None
        Altitude of the ground / launch pad in that datum, m, when the log
        states it (AltOS ``altitude − height``; 0 for ``"pad"``); subtract it
        for height above the pad.
    repeated_timestamps : int
        Rows that shared a timestamp with the row before and were merged
        into it (see :func:`merge_repeated_timestamps`); 0 if none.
    gaps : list of (float, float)
        Logging gaps, as (time of the last sample before the gap s, gap
        length s): grid steps longer than ``GAP_FACTOR`` (10) median steps
        and at least ``GAP_MIN_SECONDS`` (0.1 s).
    axial_acceleration : numpy.ndarray or None
        A rocket flight computer's own along-axis accelerometer (AltOS
        ``acceleration``, Featherweight Raven ``Axial Accel``), specific force,
        m/s², +nose (reads about +9.81 on the pad, nose up), on the steps it
        was sampled (NaN elsewhere). Usually a high-range part that does not
        saturate in boost: the rocket estimator prefers it to a raw IMU axis.
    baro_only : bool
        True when the log has no accelerometer at all (e.g. a Missile Works
        RRC3): ``vertical_acceleration`` is then zeros and every estimator
        runs as a baro-only tracking filter; ``run`` says so.
    truncated : bool
        The file ends inside a message (a ULog or DataFlash log cut short by
        a crash, a brown-out or an interrupted copy); warned.
    warnings : list of str
        One line per thing the reader noticed but accepted (repeated
        timestamps, gaps, pressure values out of range); each is also issued
        as a :class:`LogWarning`.
    """

    source: str
    time: np.ndarray
    vertical_acceleration: np.ndarray
    baro_altitude: np.ndarray
    reference_altitude: Optional[np.ndarray] = None
    reference_velocity: Optional[np.ndarray] = None
    reference_name: str = ""
    clipped: Optional[np.ndarray] = None
    notes: List[str] = field(default_factory=list)
    gps_altitude: Optional[np.ndarray] = None
    gps_accuracy: Optional[np.ndarray] = None
    gps_satellites: Optional[np.ndarray] = None
    rangefinder: Optional[np.ndarray] = None
    accel: Optional[np.ndarray] = None
    gyro: Optional[np.ndarray] = None
    imu_frame: str = ""
    pressure: Optional[np.ndarray] = None
    temperature: Optional[np.ndarray] = None
    flight_state: Optional[np.ndarray] = None
    vehicle: str = ""
    altitude_reference: str = ""
    ground_altitude: Optional[float] = None
    repeated_timestamps: int = 0
    gaps: List[Tuple[float, float]] = field(default_factory=list)
    axial_acceleration: Optional[np.ndarray] = None
    baro_only: bool = False
    truncated: bool = False
    warnings: List[str] = field(default_factory=list)

    @property
    def gap_count(self) -> int:
        """Number of logging gaps (``len(gaps)``)."""
        return len(self.gaps)

    def warn(self, message: str) -> None:
        """Record a reader warning in ``warnings`` and issue it as a :class:`LogWarning` (not inside
        :func:`quiet_warnings`)."""
        self.warnings.append(message)
        if getattr(_QUIET, "on", False):
            return
        frame, level = sys._getframe(1), 2  # point the warning at the first caller outside the readers
        while frame is not None and frame.f_globals.get("__name__", "").startswith("fusion_altitude.logs"):
            frame, level = frame.f_back, level + 1
        warnings.warn(message, LogWarning, stacklevel=level)


_QUIET = threading.local()


@contextlib.contextmanager
def quiet_warnings():
    """Within this block, in this thread only, reader warnings are recorded in ``LogData.warnings`` but not
    issued as Python warnings (the fleet's workers are threads: ``warnings.catch_warnings`` is not thread-safe).
    The caller reports ``LogData.warnings`` itself."""
    before = getattr(_QUIET, "on", False)
    _QUIET.on = True
    try:
        yield
    finally:
        _QUIET.on = before


def fmt(value: float) -> str:
    """A number for a message: plain Python formatting, never a numpy repr."""
    return f"{float(value):.6g}"


def all_true(mask: np.ndarray) -> bool:
    """``bool(mask.all())`` of a boolean array, by counting (``ndarray.all`` is a Python wrapper over a reduction: on
    a small log it takes about four times as long)."""
    return np.count_nonzero(mask) == mask.size


def median(values: np.ndarray) -> float:
    """``float(numpy.median(values))`` of a non-empty 1-D float64 array without NaN, bit for bit (the same order
    statistics, the mean of the middle two as ``numpy.mean`` takes it), in one partition: a fifth of the time on a
    small log. The last element is partitioned too, as numpy's ``median`` does: without it, on a grid of few
    distinct steps (a 1.4-million-step Raven log) the partition takes five times as long."""
    half = values.size // 2
    if values.size % 2:
        return float(np.partition(values, (half, -1))[half])
    part = np.partition(values, (half - 1, half, -1))
    return (float(part[half - 1]) + float(part[half])) / 2.0


def find_gaps(time: np.ndarray, steps: Optional[np.ndarray] = None,
              median_step: Optional[float] = None) -> List[Tuple[float, float]]:
    """Logging gaps of a grid: (start s, length s) of steps > max(10 × median step, 0.1 s).

    ``steps`` (``time[1:] - time[:-1]``, s) and their ``median_step`` (s), when the caller has them (``finish``),
    are not computed again."""
    time = np.asarray(time, dtype=float)
    if time.size < 3:
        return []
    dt = time[1:] - time[:-1] if steps is None else steps  # np.diff's values, without its wrapper
    if median_step is None:
        median_step = median(dt) if not np.isnan(dt).any() else float(np.median(dt))
    limit = max(GAP_FACTOR * median_step, GAP_MIN_SECONDS)
    index = (dt > limit).nonzero()[0]  # np.flatnonzero of a 1-D array, without its wrapper
    return [(float(time[i]), float(dt[i])) for i in index]


def merge_repeated_timestamps(time: np.ndarray, columns: dict, source: str,
                              lines: Optional[np.ndarray] = None, time_name: str = "time", row_word: str = "line"):
    """Merge rows that share a timestamp; refuse time that goes backwards.

    Rule: consecutive rows with the same time become one sample. A numeric
    column takes the **mean of its finite values** in the group (NaN if it
    has none); any other column (e.g. a state name) takes the **last** row's
    value.

    Parameters
    ----------
    time : numpy.ndarray
        Row times, s.
    columns : dict of str → numpy.ndarray
        Per-row columns (first axis = rows).
    source : str
        File name, for messages.
    lines : numpy.ndarray of int, optional
        File line of every row, for messages (default: row index + 2).
    time_name : str
        Time column's name, for messages.
    row_word : str
        What ``lines`` count, for messages ("line", "IMU message").

    Returns
    -------
    time, columns, repeated : numpy.ndarray, dict, int
        The merged grid and columns and the number of rows merged away.

    Raises
    ------
    LogError
        Time decreases (naming the file line and both times) or is not finite.
    """
    time = np.asarray(time, dtype=float)
    dt = time[1:] - time[:-1]  # np.diff's values, without its wrapper
    if _increasing(time, dt):  # finite, every step > 0: nothing to refuse, nothing to merge
        return time, columns, 0
    if lines is None:
        lines = np.arange(time.size) + 2
    _check_time_order(time, dt, source, lines, time_name, row_word)
    same = dt == 0
    repeated = int(np.count_nonzero(same))
    if not repeated:
        return time, columns, 0
    starts = np.flatnonzero(np.concatenate([[True], ~same]))
    return time[starts], {name: _merged(np.asarray(values), starts) for name, values in columns.items()}, repeated


def _increasing(time: np.ndarray, steps: np.ndarray) -> bool:
    """True when ``time`` (s; ``steps`` its steps) has at least 2 samples, all finite and strictly increasing, by
    one reduction: a NaN or an infinity inside the array makes a NaN or a −inf step (the least step is then not
    > 0), so only the two ends need a finite test of their own."""
    return bool(steps.size and np.minimum.reduce(steps) > 0 and math.isfinite(time[0]) and math.isfinite(time[-1]))


def _check_time_order(time: np.ndarray, dt: np.ndarray, source: str, lines: np.ndarray, time_name: str,
                      row_word: str) -> None:
    """LogError naming the first row (``lines``: its file line) whose time (s; ``dt`` its steps) is not finite or
    goes backwards."""
    if not all_true(np.isfinite(time)):
        bad = np.flatnonzero(~np.isfinite(time))
        raise LogError(f"{source}: {row_word} {int(lines[bad[0]])}, column {time_name!r}: "
                       f"time must be a finite number")
    back = np.flatnonzero(dt < 0) if np.count_nonzero(dt < 0) else ()
    if len(back):
        i = back[0]
        raise LogError(f"{source}: {row_word} {int(lines[i + 1])}, column {time_name!r}: time goes backwards "
                       f"({fmt(time[i + 1])} s after {fmt(time[i])} s on {row_word} {int(lines[i])})")


def _merged(values: np.ndarray, starts: np.ndarray) -> np.ndarray:
    """One column's rows merged by groups starting at ``starts``: numbers the mean of their finite values (NaN
    if none), booleans any, anything else the group's last row."""
    if values.dtype.kind == "f":
        finite = np.isfinite(values)
        total = np.add.reduceat(np.where(finite, values, 0.0), starts, axis=0)
        count = np.add.reduceat(finite.astype(float), starts, axis=0)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(count > 0, total / np.maximum(count, 1), np.nan)
    if values.dtype.kind == "b":
        return np.logical_or.reduceat(values, starts, axis=0)
    return values[np.concatenate([starts[1:], [values.shape[0]]]) - 1]


def finish(data: LogData) -> LogData:
    """Common last step of every reader: check the grid, its plausibility (:func:`._checks.check_log`: time in
    seconds, absurd samples dropped, dead channels), find gaps and warn about them and repeats."""
    from ._checks import check_log  # the checks import this module

    steps = _check_grid(data.time, data.source)  # the grid's steps (s), each > 0, and their median: found once
    # A gap or a time column in ms needs a step above 0.1 s: without one, the median (at most the longest step)
    # decides nothing, and its partition is not paid.
    median_step = median(steps) if float(np.maximum.reduce(steps)) > GAP_MIN_SECONDS else None
    check_log(data, median_step, short_steps=median_step is None)
    if data.repeated_timestamps:
        data.warn(f"{data.source}: {data.repeated_timestamps} rows repeated the timestamp of the row before; "
                  f"merged (numeric columns averaged, states: last)")
    data.gaps = find_gaps(data.time, steps, median_step) if median_step is not None else []
    if data.gaps:
        longest = max(length for _, length in data.gaps)
        first = data.gaps[0]
        data.warn(f"{data.source}: {len(data.gaps)} logging gap(s), the longest {fmt(longest)} s "
                  f"(first at {fmt(first[0])} s, {fmt(first[1])} s long)")
    return data


def align(target_time: np.ndarray, source_time: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Each source sample on the first target step at or after it; NaN on other steps (newest wins)."""
    values = np.asarray(values, dtype=float)
    out = np.empty(target_time.shape + values.shape[1:])
    out.fill(np.nan)  # np.full's values, without its wrapper
    index = target_time.searchsorted(source_time, side="left")
    finite = np.isfinite(values)
    if index.size and all_true(finite) and np.maximum.reduce(index) < target_time.size:
        out[index] = values  # every sample kept: no masks to apply
        return out
    finite = finite if values.ndim == 1 else finite.all(axis=1)
    keep = (index < target_time.size) & finite
    out[index[keep]] = values[keep]
    return out


def previous(target_time: np.ndarray, source_time: np.ndarray, values: np.ndarray) -> np.ndarray:
    """The latest source sample at or before each target time (the first one before it starts)."""
    source_time, values = np.asarray(source_time), np.asarray(values)
    if values.shape[:1] == source_time.shape and _same_grid(source_time, target_time):  # e.g. PX4's attitude
        return values.copy()  # each step's own sample: values[arange(size)]
    index = source_time.searchsorted(target_time, side="right")
    index -= 1  # in −1 … size − 1: only −1 needs clipping
    np.maximum(index, 0, out=index)
    return values.take(index, axis=0)


def _same_grid(source_time: np.ndarray, target_time: np.ndarray) -> bool:
    """True when ``source_time`` is ``target_time`` sample for sample and strictly increasing (s): then the
    latest source sample at or before each target time is the one at the same index."""
    if source_time.shape != np.shape(target_time) or source_time.size < 2:
        return False
    if np.count_nonzero(source_time == target_time) != source_time.size:
        return False
    return np.count_nonzero(source_time[1:] > source_time[:-1]) == source_time.size - 1


def reference_on_grid(time, baro_altitude, ref_time, ref_altitude, ref_velocity):
    """A reference's altitude (m) and velocity (m/s) on the grid ``time`` (s), NaN outside it, the altitude moved
    onto the baro's datum by the median difference over the first 2 s where both exist."""
    altitude = np.interp(time, ref_time, ref_altitude, left=np.nan, right=np.nan)
    velocity = np.interp(time, ref_time, ref_velocity, left=np.nan, right=np.nan)
    both = np.isfinite(altitude) & np.isfinite(baro_altitude)
    if not np.count_nonzero(both):
        return altitude, velocity
    early = both & (time <= time[both.argmax()] + 2.0)  # argmax: the first True
    if not np.count_nonzero(early):
        return altitude, velocity
    return altitude + median(baro_altitude[early] - altitude[early]), velocity  # numpy.median's value: no NaN


def _check_grid(time: np.ndarray, source: str) -> np.ndarray:
    """LogError unless the grid ``time`` (s) has at least 2 finite, strictly increasing samples; its steps (s)."""
    time = np.asarray(time, dtype=float)
    if time.size < 2:
        raise LogError(f"{source}: need at least 2 samples, got {time.size}")
    with np.errstate(invalid="ignore"):  # inf − inf: refused below, without a RuntimeWarning
        steps = time[1:] - time[:-1]
    if _increasing(time, steps):
        return steps
    if not all_true(np.isfinite(time)):
        raise LogError(f"{source}: sample {int(np.flatnonzero(~np.isfinite(time))[0])}: time is not finite")
    increasing = steps > 0
    bad = np.flatnonzero(~increasing) if not all_true(increasing) else ()
    if len(bad):
        raise LogError(f"{source}: time must increase strictly; sample {int(bad[0]) + 1} "
                       f"({fmt(time[bad[0] + 1])} s) follows {fmt(time[bad[0]])} s")
    return steps

