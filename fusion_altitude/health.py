"""What a log's sensors and an estimator's run can stand behind: the health report of ``run`` and the fleet.

Every answer ``run`` prints comes with the state of the sensors it came
from. :func:`sensor_health` describes each stream of a
:class:`~fusion_altitude.logs.LogData` (rate, first and last sample, longest
outage, dead or saturated, whether it stopped before the log's end);
:func:`row_flags` marks, per grid step, what the ``-o`` CSV's ``flags``
column says; :func:`check_estimate` refuses an estimate that is not finite
or has run away from every height source of the log.

Times are the log's seconds; rates in Hz; outages in s.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import List, Optional, Sequence, Tuple

import numpy as np

__all__ = ["StreamHealth", "sensor_health", "baro_timeout_for", "not_baro_aided", "row_flags", "FLAG_BITS",
           "EstimateProblem", "check_estimate", "RUNAWAY_MARGIN", "format_health", "stream_notes", "stopped_streams"]

#: Longest silence of a stream that is still "the same stream", in nominal periods of that stream ...
OUTAGE_PERIODS = 10.0
#: ... and never shorter than this, s.
OUTAGE_MIN_SECONDS = 1.0
#: An estimate more than this far (m) outside every height source of the log (baro, GPS, rangefinder, the log's
#: own estimate) has run away: ``run`` refuses to print it.
RUNAWAY_MARGIN = 1000.0

#: Bits of the ``flags`` column of ``run -o`` (documented in docs/cli.md).
FLAG_BITS = {
    "not_baro_aided": 1,   # no baro sample for longer than the baro timeout: the height is not baro-aided
    "logging_gap": 2,      # the step before this row is a logging gap (dt > the gap period): the estimator restarted
    "accel_clipped": 4,    # the accelerometer was at its range limit on this row
    "baro_stopped": 8,     # after the baro's last sample (the stream ended before the log)
}


@dataclass(frozen=True)
class StreamHealth:
    """One sensor stream of a log.

    Attributes
    ----------
    name : str
        ``"accelerometer"`` (the log's grid), ``"baro"``, ``"gps"``,
        ``"rangefinder"``, ``"axial accelerometer"``.
    samples : int
        Samples of the stream (finite values on the grid).
    rate : float
        Hz: 1 / the median step between its samples; NaN with fewer than 2.
    first, last : float
        s: time of the first and the last sample; NaN without samples.
    longest_outage : float
        s: the longest time without a sample of this stream from its first
        sample to the log's end (so a stream that stops early has its
        silence to the end counted); 0 without samples.
    outage_start : float
        s: when that longest outage began.
    stopped : bool
        The stream's last sample is more than its timeout
        (:func:`baro_timeout_for` of its rate) before the log's end.
    started_late : bool
        The stream's first sample is more than its timeout after the log's
        start.
    dead : bool
        Every sample has the same value (a constant or all-zero channel).
    saturated : int
        Samples at the range limit (the accelerometer's ``clipped``).
    """

    name: str
    samples: int
    rate: float
    first: float
    last: float
    longest_outage: float
    outage_start: float
    stopped: bool
    started_late: bool
    dead: bool
    saturated: int = 0

    @property
    def timeout(self) -> float:
        """s: silence after which this stream counts as stopped (:func:`baro_timeout_for` of its rate)."""
        return baro_timeout_for(self.rate)


def baro_timeout_for(rate: float) -> float:
    """Silence (s) after which a stream of ``rate`` Hz counts as stopped: max(1 s, 10 / rate).

    Ten nominal periods (the same factor as a logging gap,
    :data:`fusion_altitude.logs.GAP_FACTOR`) at any rate, and never under
    1 s, so a 2 Hz telemetry baro is not stopped by one lost packet.
    """
    if not np.isfinite(rate) or rate <= 0:
        return OUTAGE_MIN_SECONDS
    return max(OUTAGE_MIN_SECONDS, OUTAGE_PERIODS / float(rate))


def _rate(steps: np.ndarray) -> float:
    """Hz: 1 / the median of ``steps`` (s), NaN without a positive median (one median, one partition)."""
    median = float(np.median(steps)) if steps.size else np.nan
    return 1.0 / median if median > 0 else np.nan


def _stream(name: str, time: np.ndarray, values: Optional[np.ndarray], saturated: int = 0) -> Optional[StreamHealth]:
    if values is None:
        return None
    values = np.asarray(values, float)
    if values.ndim == 2:
        present = np.all(np.isfinite(values), axis=1)
    else:
        present = np.isfinite(values)
    index = np.flatnonzero(present)
    end, start = float(time[-1]), float(time[0])
    if index.size == 0:
        return StreamHealth(name, 0, np.nan, np.nan, np.nan, 0.0, np.nan, True, True, True, saturated)
    stamps = time[index]
    steps = np.diff(stamps)
    rate = _rate(steps)
    silences = np.append(steps, end - stamps[-1])
    longest = int(np.argmax(silences))
    timeout = baro_timeout_for(rate)
    kept = values[index]
    dead = bool(index.size > 1 and np.all(kept == kept[0]))
    return StreamHealth(name, int(index.size), rate, float(stamps[0]), float(stamps[-1]), float(silences[longest]),
                        float(stamps[longest]), bool(end - stamps[-1] > timeout),
                        bool(stamps[0] - start > timeout), dead, saturated)


def sensor_health(data) -> List[StreamHealth]:
    """The streams of a :class:`~fusion_altitude.logs.LogData`: the grid's accelerometer (unless the log has
    none, ``baro_only``), the baro, and the GPS, rangefinder and axial accelerometer where the log has them."""
    time = np.asarray(data.time, float)
    streams: List[Optional[StreamHealth]] = []
    if not getattr(data, "baro_only", False):
        raw = getattr(data, "accel", None)
        clipped = getattr(data, "clipped", None)
        streams.append(_stream("accelerometer", time, raw if raw is not None else data.vertical_acceleration,
                               int(np.count_nonzero(clipped)) if clipped is not None else 0))
    streams.append(_stream("baro", time, data.baro_altitude))
    streams.append(_stream("gps", time, getattr(data, "gps_altitude", None)))
    streams.append(_stream("rangefinder", time, getattr(data, "rangefinder", None)))
    streams.append(_stream("axial accelerometer", time, getattr(data, "axial_acceleration", None)))
    return [s for s in streams if s is not None]


def stopped_streams(health: Sequence[StreamHealth]) -> List[StreamHealth]:
    """The streams of ``health`` that stop before the log's end (``stopped`` with at least one sample)."""
    return [s for s in health if s.stopped and s.samples > 0]


def not_baro_aided(time, baro_altitude, timeout: Optional[float] = None) -> np.ndarray:
    """Per grid step: True where the latest baro sample is more than ``timeout`` s old (or there was none yet).

    ``timeout`` defaults to :func:`baro_timeout_for` of the baro's own rate.
    """
    time = np.asarray(time, float)
    baro = np.asarray(baro_altitude, float)
    present = np.isfinite(baro)
    if timeout is None:
        timeout = baro_timeout_for(_rate(np.diff(time[present])))
    index = np.where(present, np.arange(time.size), -1)
    latest = np.maximum.accumulate(index)
    age = np.where(latest >= 0, time - time[np.maximum(latest, 0)], np.inf)
    return age > timeout


def row_flags(data, gap_period: Optional[float] = None, baro_timeout: Optional[float] = None) -> np.ndarray:
    """The ``flags`` column of ``run -o`` (uint8 bit mask of :data:`FLAG_BITS`), one entry per grid step.

    Parameters
    ----------
    data : LogData
        The log (or a :class:`~fusion_altitude.runner.LogRun`).
    gap_period : float, optional
        s: the estimator's gap period; a step longer than it flags
        ``logging_gap`` on the row after it. None: no gap bit.
    baro_timeout : float, optional
        s: see :func:`not_baro_aided`.
    """
    time = np.asarray(data.time, float)
    flags = np.zeros(time.size, np.uint8)
    baro = np.asarray(data.baro_altitude, float)
    flags[not_baro_aided(time, baro, baro_timeout)] |= FLAG_BITS["not_baro_aided"]
    if gap_period is not None and time.size > 1:
        gap = np.zeros(time.size, bool)
        gap[1:] = np.diff(time) > gap_period
        flags[gap] |= FLAG_BITS["logging_gap"]
    clipped = getattr(data, "clipped", None)
    if clipped is not None:
        flags[np.asarray(clipped, bool)] |= FLAG_BITS["accel_clipped"]
    present = np.flatnonzero(np.isfinite(baro))
    if present.size:
        flags[present[-1] + 1:] |= FLAG_BITS["baro_stopped"]
    return flags


@dataclass(frozen=True)
class EstimateProblem:
    """Why an estimate cannot be printed: ``what`` (one line) from ``time`` s on, over ``count`` samples."""

    what: str
    time: float
    count: int

    def __str__(self) -> str:
        return f"{self.what} from {self.time:.3f} s on ({self.count} samples)"


def height_range(data) -> Tuple[float, float]:
    """m: the lowest and highest value of every height source of the log on the baro's datum (baro, the log's
    own estimate, the GPS altitude shifted by its median offset to the baro, rangefinder); (NaN, NaN) if none."""
    low, high = np.inf, -np.inf
    baro = np.asarray(data.baro_altitude, float)
    for values in (baro, getattr(data, "reference_altitude", None)):
        if values is not None and np.isfinite(values).any():
            low, high = min(low, float(np.nanmin(values))), max(high, float(np.nanmax(values)))
    gps = getattr(data, "gps_altitude", None)
    if gps is not None:
        gps = np.asarray(gps, float)
        both = np.isfinite(gps) & np.isfinite(baro)
        if both.any() and np.isfinite(gps).any():
            shifted = gps - float(np.median(gps[both] - baro[both]))
            low, high = min(low, float(np.nanmin(shifted))), max(high, float(np.nanmax(shifted)))
    if not np.isfinite(low):
        return np.nan, np.nan
    return low, high


def check_estimate(data, altitude, vertical_velocity=None) -> Optional[EstimateProblem]:
    """None when the estimate can be printed; else what is wrong with it.

    Refused: a non-finite altitude or vertical velocity on any step, or an
    altitude more than :data:`RUNAWAY_MARGIN` (1 km) outside every height
    source of the log (:func:`height_range`).
    """
    time = np.asarray(data.time, float)
    altitude = np.asarray(altitude, float)
    bad = ~np.isfinite(altitude)
    if vertical_velocity is not None:
        bad |= ~np.isfinite(np.asarray(vertical_velocity, float))
    if bad.any():
        first = int(np.argmax(bad))
        return EstimateProblem("non-finite altitude or vertical velocity", float(time[first]), int(bad.sum()))
    low, high = height_range(data)
    if np.isfinite(low):
        away = (altitude < low - RUNAWAY_MARGIN) | (altitude > high + RUNAWAY_MARGIN)
        if away.any():
            first = int(np.argmax(away))
            return EstimateProblem(f"altitude {altitude[first]:.6g} m more than {RUNAWAY_MARGIN:g} m outside every "
                                   f"height source of the log ({low:.6g} … {high:.6g} m)", float(time[first]),
                                   int(away.sum()))
    return None


def _cell(value: float, digits: str = ".2f") -> str:
    return "—" if not np.isfinite(value) else format(value, digits)


def stream_notes(s: StreamHealth, log_start: float, log_end: float, stop_word: str = "stops") -> List[str]:
    """What is wrong with one sensor stream, as short notes: no sample, dead, saturated, stops (s before the
    log's end, introduced by ``stop_word``), starts late (s after the log's start ``log_start``)."""
    if s.samples == 0:
        return ["no sample"]
    notes = []
    if s.dead:
        notes.append("dead: constant value")
    if s.saturated:
        notes.append(f"saturated on {s.saturated} samples")
    if s.stopped:
        notes.append(f"{stop_word} {log_end - s.last:.1f} s before the log's end")
    if s.started_late:
        notes.append(f"starts {s.first - log_start:.1f} s after the log")
    return notes


def format_health(health: Sequence[StreamHealth], log_start: float, log_end: float) -> List[str]:
    """Lines of the sensor table ``run`` prints: per stream rate, first and last sample, longest outage, notes."""
    lines = [f"{'sensor':20s} {'samples':>8s} {'rate (Hz)':>9s} {'first (s)':>10s} {'last (s)':>10s} "
             f"{'longest outage (s)':>18s}  notes"]
    for s in health:
        notes = stream_notes(s, log_start, log_end, stop_word="STOPS")
        if s.samples and s.longest_outage > s.timeout and not (s.stopped and s.outage_start == s.last):
            notes.append(f"outage from {s.outage_start:.2f} s")
        lines.append(f"{s.name:20s} {s.samples:8d} {_cell(s.rate, '.1f'):>9s} {_cell(s.first):>10s} "
                     f"{_cell(s.last):>10s} {_cell(s.longest_outage):>18s}  {'; '.join(notes)}".rstrip())
    return lines
