"""Plausibility checks shared by every reader, run before any estimator sees a log ("never silently wrong").

Three kinds of check, each reported in one line (a :class:`LogWarning` or a
:class:`LogError`), none silent:

* **Absurd cells** (:func:`drop_absurd`): a baro altitude outside
  :data:`ALTITUDE_RANGE` (−1 km … +100 km), a pressure outside
  :data:`PRESSURE_RANGE` (> 0 … 120 kPa), ``inf`` or the AltOS "missing"
  sentinel are dropped — NaN, i.e. "no sample on that step" — with a warning
  naming the first file line (CSV line numbers: the header is line 1) and
  how many more. The CSV readers check every row before merging repeated
  time stamps, so the line is exact; :func:`check_log` (called by
  :func:`~fusion_altitude.logs._data.finish`, so by every reader) repeats the
  check on the grid for the binary formats and names the sample and time.
* **Dead channels** (:func:`is_dead`): a channel whose samples are all
  equal (all zero included) over at least :data:`DEAD_MIN_SAMPLES` samples
  is a sensor that is not working (a raw 3-axis accelerometer: unless it
  reads a steady 1 g, :func:`is_dead_imu`). It is never chosen: the reader falls back
  to the alternative (AltOS: the along-axis accelerometer instead of the IMU;
  otherwise baro-only) and says so.
* **Time units** (:func:`check_time_units`): a time column in milliseconds or
  microseconds is refused with a one-line :class:`LogError` that names the fix.
  Rule: the median step is more than :data:`MAX_MEDIAN_STEP` (2 s, slower
  than 0.5 Hz: no altitude log is that slow, while a slow 1 Hz log passes),
  or it is at least 1 s and the log spans more than :data:`MAX_SPAN` (one
  day: a 1 kHz log in ms looks like 1 Hz but spans 1000 × too long).
"""

from __future__ import annotations

import math
from typing import List, Optional, Sequence, Tuple

import numpy as np

from .._core._common import GRAVITY
from ._data import LogError, fmt, median

#: Plausible baro / reference altitude, m (below the Dead Sea shore … well above any balloon).
ALTITUDE_RANGE = (-1_000.0, 100_000.0)
#: Plausible static pressure, Pa: above 0 and at most 120 kPa (the highest sea-level pressure is ≈ 108.6 kPa).
PRESSURE_RANGE = (0.0, 120_000.0)
#: Fewest finite samples for a constant channel to count as dead (a short log may be constant honestly).
DEAD_MIN_SAMPLES = 20
#: A median time step above this (s) is not seconds.
MAX_MEDIAN_STEP = 2.0
#: A log with a median step ≥ 1 s that spans more than this (s) is not in seconds.
MAX_SPAN = 86_400.0
#: The AltOS "no value" sentinel (``AltosLib.MISSING``, 0x7fffffff) that its CSV writes for absent sensors.
ALTOS_MISSING = 2_147_483_647.0


def drop_absurd(source: str, name: str, values: np.ndarray, lines: Optional[np.ndarray], low: float, high: float,
                unit: str, what: str, low_inclusive: bool = True,
                row_word: str = "line") -> Tuple[np.ndarray, Optional[str]]:
    """Cells of ``values`` outside [low, high] or infinite become NaN ("no sample"); one warning line, or None.

    Parameters
    ----------
    source : str
        File name, for the message.
    name : str
        Column name, for the message.
    values : numpy.ndarray
        One value per row (NaN = empty cell, left alone), in ``unit``.
    lines : numpy.ndarray of int or None
        File line of every row (CSV: the header is line 1); None names the
        sample index instead.
    low, high : float
        Plausible range, in ``unit``; ``low`` itself is plausible unless
        ``low_inclusive`` is False (a pressure of 0 Pa is not).
    unit : str
        Unit of the values, for the message (m, Pa).
    what : str
        The quantity, for the message ("baro altitude", "pressure").
    row_word : str
        What ``lines`` count ("line", "sample").

    Returns
    -------
    values : numpy.ndarray
        A copy with the absurd cells NaN (the input itself if none).
    message : str or None
        ``"<source>: line 57, column 'baro': 1e+30 m is not a plausible baro
        altitude (plausible: -1000…100000 m); dropped (no sample there), and
        2 more lines (the last line 90)"``.
    """
    values = np.asarray(values, dtype=float)
    if not values.size or _all_plausible(values, low, high, low_inclusive):
        return values, None
    present = ~np.isnan(values)
    with np.errstate(invalid="ignore"):
        inside = (values >= low if low_inclusive else values > low) & (values <= high)
    bad = np.flatnonzero(present & ~inside)
    if not bad.size:
        return values, None
    first_value = float(values[bad[0]])
    values = values.copy()
    values[bad] = np.nan

    def where(i: int) -> str:
        return f"{row_word} {int(lines[i])}" if lines is not None else f"sample {int(i)}"

    shown = "the AltOS 'missing' value" if first_value == ALTOS_MISSING else f"{fmt(first_value)} {unit}"
    bounds = f"{fmt(low)}…{fmt(high)} {unit}" if low_inclusive else f"above {fmt(low)}, up to {fmt(high)} {unit}"
    message = (f"{source}: {where(bad[0])}, column {name!r}: {shown} is not a plausible {what} "
               f"(plausible: {bounds}); dropped (no sample there)")
    if bad.size > 1:
        message += f", and {bad.size - 1} more {row_word}s (the last {where(bad[-1])})"
    return values, message


def _all_plausible(values: np.ndarray, low: float, high: float, low_inclusive: bool) -> bool:
    """True when every non-NaN value lies in the range of :func:`drop_absurd` (and one at least): its least and
    greatest ignoring NaN (``fmin``/``fmax``), two reductions instead of a mask per test. A strided column (a
    view into a table) is copied first: ``fmin``/``fmax`` over a stride take five times as long as the copy."""
    if not values.flags.c_contiguous:
        values = values.copy()
    least, greatest = float(np.fmin.reduce(values)), float(np.fmax.reduce(values))
    return (least >= low if low_inclusive else least > low) and greatest <= high


def is_dead(values: np.ndarray) -> bool:
    """True if a channel is dead: at least :data:`DEAD_MIN_SAMPLES` finite samples, all equal (all zero too).

    ``values`` may be 1-D or (N, k): for several axes the channel is dead
    when every axis is constant.
    """
    values = np.asarray(values, dtype=float)
    if values.size and values.ndim <= 2 and _ends_differ(values):
        return False
    if values.ndim == 1:  # one channel: the same test without the axis reductions
        if values.size and _two_finite_values(values):
            return False
        live = values[np.isfinite(values)]
        return live.size >= DEAD_MIN_SAMPLES and bool(live.max() == live.min())
    rows = np.all(np.isfinite(values), axis=1)
    if rows.sum() < DEAD_MIN_SAMPLES:
        return False
    live = values[rows]
    return bool(np.all(live.max(axis=0) == live.min(axis=0)))


def _ends_differ(values: np.ndarray) -> bool:
    """True when the first and the last sample (rows of every axis) of ``values`` (not empty) are finite and
    differ: two different finite samples (rows), so not a dead channel, seen in two elements."""
    first, last = values[0].tolist(), values[-1].tolist()
    if values.ndim == 1:
        return first != last and math.isfinite(first) and math.isfinite(last)
    return first != last and all(map(math.isfinite, first + last))


def _two_finite_values(values: np.ndarray) -> bool:
    """True when the least and the greatest of ``values`` (1-D, not empty; NaN ignored) are finite and differ: two
    different finite samples, so not a dead channel (two reductions, without the mask of the full test)."""
    least, greatest = float(np.fmin.reduce(values)), float(np.fmax.reduce(values))
    return least != greatest and math.isfinite(least) and math.isfinite(greatest)


def is_dead_imu(accel: np.ndarray) -> bool:
    """True if a raw 3-axis accelerometer (specific force, m/s²) is dead: every axis constant
    (:func:`is_dead`) and not reading 1 g (all zero, or a norm off 9.81 m/s² by more than 25 %). A constant
    1 g is a vehicle at rest (a simulated one: a real sensor is never exactly constant) and passes."""
    accel = np.asarray(accel, dtype=float)
    if not is_dead(accel):
        return False
    live = accel[np.all(np.isfinite(accel), axis=1)]
    norm = float(np.linalg.norm(live[0]))
    return not 0.75 * GRAVITY < norm < 1.25 * GRAVITY


def dead_message(source: str, name: str, values: np.ndarray, unit: str, instead: str) -> str:
    """One line for a dead channel: its constant value(s) and what is used instead."""
    values = np.asarray(values, dtype=float)
    live = values[np.all(np.isfinite(values.reshape(values.shape[0], -1)), axis=1)]
    constant = live[0] if live.size else np.nan
    shown = ", ".join(fmt(v) for v in np.atleast_1d(constant))
    kind = "all zero" if np.all(np.atleast_1d(constant) == 0) else f"constant ({shown} {unit})"
    return f"{source}: {name} is {kind} on every sample: a dead sensor, not used; {instead}"


def check_time_units(source: str, time: np.ndarray, fix: str, median_step: Optional[float] = None) -> None:
    """Refuse a time column that is not in seconds (LogError naming ``fix``), by the rule of the module docstring.

    Parameters
    ----------
    source : str
        File name, for the message.
    time : numpy.ndarray
        Sample times as read, meant to be s, increasing.
    fix : str
        What the user can do, e.g. ``"set time_units to 'ms' or 'us'"`` (the CLI shows the flag: ``--time-units``).
    median_step : float, optional
        The median step of ``time`` (s) when the caller has it, for a grid of at least 2 finite, strictly
        increasing times (``finish``'s): not found again.
    """
    time = np.asarray(time, dtype=float)
    if median_step is not None:
        step, span = median_step, float(time[-1] - time[0])
    else:
        if time.size >= 2:
            with np.errstate(invalid="ignore"):  # inf − inf: NaN, which fails the test below
                largest = float(np.maximum.reduce(time[1:] - time[:-1]))
            if largest < 1.0:  # a NaN, or an infinity inside, makes the largest step NaN or inf: not here
                return  # every step under 1 s (the finite times' too): so the median, without a partition
        finite = np.isfinite(time)
        finite = time if np.count_nonzero(finite) == time.size else time[finite]
        if finite.size < 2:
            return
        steps = finite[1:] - finite[:-1]
        positive = steps > 0
        steps = steps if positive.all() else steps[positive]
        if not steps.size:
            return
        step = median(steps)  # steps of finite times: no NaN
        span = float(finite[-1] - finite[0])
    if step > MAX_MEDIAN_STEP or (step >= 1.0 and span > MAX_SPAN):
        guess = "microseconds" if step >= 1_000.0 or span > 1e3 * MAX_SPAN else "milliseconds"
        raise LogError(f"{source}: the time column does not look like seconds (median step {fmt(step)}, span "
                       f"{fmt(span)}): probably {guess}; {fix}")


def check_log(data, median_step: Optional[float] = None, short_steps: bool = False) -> None:
    """The checks every reader's grid goes through (called by ``finish``, which gives the grid's ``median_step``,
    s, or ``short_steps``: every step is at most 0.1 s); warnings via ``data.warn``.

    * time in seconds (:func:`check_time_units`, LogError; passed without a look when ``short_steps``: the
      median step is then below 1 s);
    * absurd baro / reference altitude and pressure samples → NaN, one
      warning per quantity naming the first sample and its time;
    * a dead raw accelerometer (:func:`is_dead_imu`) → ``accel`` and ``gyro``
      dropped (no INS on it), one warning (a vertical-acceleration *column*
      is checked by the readers that read one: generic CSV, AltOS);
    * a baro whose samples are all equal → one warning (no reader has another
      altitude source at this point; a reader that has one falls back first).
    """
    source = data.source
    if not short_steps:
        check_time_units(source, data.time, _time_fix(data), median_step)
    for attribute, low, high, unit, what, inclusive in (
            ("baro_altitude", *ALTITUDE_RANGE, "m", "baro altitude", True),
            ("reference_altitude", *ALTITUDE_RANGE, "m", "reference altitude", True),
            ("pressure", *PRESSURE_RANGE, "Pa", "pressure", False)):
        values = getattr(data, attribute)
        if values is None:
            continue
        cleaned, message = drop_absurd(source, attribute, values, None, low, high, unit, what, inclusive)
        if message is not None:
            first = int(np.flatnonzero(np.isnan(cleaned) & ~np.isnan(np.asarray(values, float)))[0])
            setattr(data, attribute, cleaned)
            data.warn(message.replace(f"sample {first},", f"sample {first} ({fmt(data.time[first])} s),", 1))
    if data.accel is not None and is_dead_imu(data.accel):
        data.warn(dead_message(source, "the raw accelerometer (every axis)", data.accel, "m/s²",
                               "no INS on this log"))
        data.accel = None
        data.gyro = None
        data.imu_frame = ""
    if is_dead(data.baro_altitude):
        data.warn(dead_message(source, "the baro altitude", data.baro_altitude, "m",
                               "this log has no other altitude source: every estimate follows it (check the log)")
                  .replace("a dead sensor, not used", "a dead sensor?"))


def _time_fix(data) -> str:
    if data.source.endswith("(CSV)"):
        return "set time_units to 'ms' or 'us'"
    return "this format's time is in seconds: the file is not what it claims to be"


def column_dead(source: str, name: str, values: np.ndarray, unit: str, instead: str) -> Optional[str]:
    """:func:`dead_message` for one named column if it is dead (:func:`is_dead`), else None."""
    return dead_message(source, f"column {name!r}", values, unit, instead) if is_dead(values) else None


def absurd_columns(source: str, columns: dict, lines: np.ndarray,
                   checks: Sequence[Tuple[str, str, float, float, str, str, bool]]) -> List[str]:
    """Apply :func:`drop_absurd` in place to ``columns[role]`` for each (role, name, low, high, unit, what,
    low_inclusive) present; returns the warning lines."""
    messages = []
    for role, name, low, high, unit, what, inclusive in checks:
        if role in columns:
            columns[role], message = drop_absurd(source, name, columns[role], lines, low, high, unit, what,
                                                 inclusive)
            if message is not None:
                messages.append(message)
    return messages
