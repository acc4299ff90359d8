"""The common shape of every log: :class:`LogData` on one time grid, :class:`LogError`, grid helpers."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import List, Optional

import numpy as np


class LogError(ValueError):
    """A log cannot be read or used; the message names the file, column or row."""


@dataclass
class LogData:
    """A log on the observer's time grid.

    Attributes
    ----------
    source : str
        File name and format.
    time : numpy.ndarray
        Sample times, s, strictly increasing (irregular allowed).
    vertical_acceleration : numpy.ndarray
        Observer input, m/s², earth frame, +up, gravity removed.
    baro_altitude : numpy.ndarray
        Baro altitude, m; NaN on steps without a new baro sample.
    reference_altitude, reference_velocity : numpy.ndarray or None
        The autopilot's own height (m, baro datum) and vertical velocity
        (m/s, +up) on the same grid, if the log has them.
    reference_name : str
        Where the reference came from.
    clipped : numpy.ndarray or None
        True on samples where the accelerometer was at its range limit.
    notes : list of str
        What the reader chose (topics, instances), for the report.
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


def _align(target_time: np.ndarray, source_time: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Each source sample on the first target step at or after it; NaN on other steps (newest wins)."""
    out = np.full(target_time.shape, np.nan)
    index = np.searchsorted(target_time, source_time, side="left")
    keep = (index < target_time.size) & np.isfinite(values)
    out[index[keep]] = values[keep]
    return out


def _previous(target_time: np.ndarray, source_time: np.ndarray, values: np.ndarray) -> np.ndarray:
    """The latest source sample at or before each target time (the first one before it starts)."""
    index = np.clip(np.searchsorted(source_time, target_time, side="right") - 1, 0, source_time.size - 1)
    return values[index]


def _reference_on_grid(time, baro_altitude, ref_time, ref_altitude, ref_velocity):
    altitude = np.interp(time, ref_time, ref_altitude, left=np.nan, right=np.nan)
    velocity = np.interp(time, ref_time, ref_velocity, left=np.nan, right=np.nan)
    both = np.isfinite(altitude) & np.isfinite(baro_altitude)
    early = both & (time <= time[both][0] + 2.0) if both.any() else both
    if early.any():
        altitude = altitude + float(np.median(baro_altitude[early] - altitude[early]))
    return altitude, velocity


def _check_grid(time: np.ndarray, source: str) -> None:
    bad = np.flatnonzero(~(np.diff(time) > 0))
    if bad.size:
        raise LogError(f"{source}: time must increase strictly; sample {bad[0] + 1} "
                       f"({time[bad[0] + 1]!r} s) follows {time[bad[0]]!r} s")
