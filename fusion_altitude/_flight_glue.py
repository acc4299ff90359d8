"""Glue of the rocket flight layer shared by its binding (``_flight.pyx``) and its
reference (``reference/flight.py``): statuses, settings fields, phases, the
``FlightEvents`` result, error messages naming the argument and batch
argument conversion. No algorithm lives here (see ``csrc/fusion_altitude_flight.h``).
"""

from __future__ import annotations

import csv
import enum
import math
import os
from typing import Dict, Iterator, NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np

from ._common import as_float, as_float32_vector
from ._observer_glue import prepare_inputs


class RocketStatus(enum.IntEnum):
    """Status codes, equal to the C enum ``FusionAltitudeRocketStatus``."""

    OK = 0
    INVALID_ACCEL = 1
    INVALID_BARO_ALTITUDE = 2
    INVALID_DT = 3
    INVALID_OBSERVER_SETTINGS = 4
    INVALID_STATIONARY_ACCEL = 5
    INVALID_CALIBRATION_WINDOW = 6
    INVALID_LAUNCH_ACCEL = 7
    INVALID_LAUNCH_TIME = 8
    INVALID_BURNOUT_ACCEL = 9
    INVALID_BURNOUT_TIME = 10
    INVALID_APOGEE_MARGIN = 11
    INVALID_LOCKOUT_SPEED = 12
    INVALID_SPIKE_THRESHOLD = 13
    INVALID_SPIKE_TIME = 14
    INVALID_OFFSET_RATE = 15
    INVALID_MAIN_ALTITUDE = 16
    INVALID_LANDED_SPEED = 17
    INVALID_LANDED_TIME = 18
    INVALID_GAP_PERIOD = 19


class Phase(enum.IntEnum):
    """Flight phases, equal to the C enum ``FusionAltitudeRocketPhase``."""

    PAD = 0
    BOOST = 1
    COAST = 2
    DROGUE = 3
    MAIN = 4
    LANDED = 5


class BaroFate(enum.IntEnum):
    """What happened to a step's baro sample (C enum ``FusionAltitudeRocketBaro``)."""

    NONE = 0
    PAD = 1
    FUSED = 2
    LOCKED_OUT = 3
    SPIKE = 4


#: Event names in the order of the C enum ``FusionAltitudeRocketEventId``.
EVENT_NAMES = ("launch", "burnout", "max_speed", "apogee", "main", "landed")

#: Events written by :meth:`FlightEvents.to_csv` (one row each, when they occurred).
CSV_EVENTS = ("launch", "burnout", "apogee", "main", "landed")

#: Speed above which the baro is always locked out, m/s (FUSION_ALTITUDE_ROCKET_MACH_LOCKOUT).
MACH_LOCKOUT = 236.0

#: Settings fields after the observer gains, in C declaration (and check) order:
#: (name, default, rule) where rule is "positive", "non_negative", "finite" or "gap".
SETTINGS_FIELDS: Tuple[Tuple[str, float, str, str], ...] = (
    ("stationary_accel", 5.0, "positive", "m/s²"),
    ("calibration_window", 0.5, "positive", "s"),
    ("launch_accel", 20.0, "positive", "m/s²"),
    ("launch_time", 0.05, "non_negative", "s"),
    ("burnout_accel", 0.0, "finite", "m/s²"),
    ("burnout_time", 0.1, "non_negative", "s"),
    ("apogee_margin", 1.0, "non_negative", "m/s"),
    ("lockout_speed", 100.0, "positive", "m/s"),
    ("spike_threshold", 20.0, "positive", "m"),
    ("spike_time", 0.2, "non_negative", "s"),
    ("offset_rate", 0.9, "rate", "fraction of |v|"),
    ("main_altitude", 250.0, "non_negative", "m"),
    ("landed_speed", 3.0, "positive", "m/s"),
    ("landed_time", 2.0, "non_negative", "s"),
    ("gap_period", 0.5, "gap", "s"),
)

FIELD_NAMES = tuple(field[0] for field in SETTINGS_FIELDS)
DEFAULTS = {field[0]: field[1] for field in SETTINGS_FIELDS}

#: Rocket observer gains (FusionAltitudeRocketObserverSettings): ω 1.0 rad/s, ζ 0.7, ω_b 0 (bias frozen in flight).
ROCKET_GAINS = (1.4, 1.0, 0.0)

_RULE_TEXT = {"positive": "must be finite and > 0", "non_negative": "must be finite and >= 0",
              "finite": "must be finite", "rate": "must be > 0 and <= 1", "gap": "must be > 0 (+inf: never a gap)"}


def raise_settings_error(status: int, values: Dict[str, float]) -> None:
    """Raise the ValueError for rejected settings, naming the field."""
    status = RocketStatus(status)
    if status == RocketStatus.INVALID_OBSERVER_SETTINGS:
        raise ValueError(f"observer gains are invalid or unstable, got {values.get('observer')!r}")
    name, _, rule, unit = SETTINGS_FIELDS[status - RocketStatus.INVALID_STATIONARY_ACCEL]
    raise ValueError(f"{name} {_RULE_TEXT[rule]} ({unit}), got {values[name]!r}")


_UPDATE_RULES = {
    RocketStatus.INVALID_ACCEL: ("accel", "must be finite (m/s²)"),
    RocketStatus.INVALID_BARO_ALTITUDE: ("baro_altitude", "must be finite, or NaN for no baro sample (m)"),
    RocketStatus.INVALID_DT: ("dt", "must be finite and > 0 (s)"),
}


def raise_update_error(status: int, accel: float, baro_altitude: float, dt: float, index: Optional[int] = None,
                       dt_is_array: bool = False) -> None:
    """Raise the ValueError for a rejected update, naming the argument (and the first bad index)."""
    name, rule = _UPDATE_RULES[RocketStatus(status)]
    value = {"accel": accel, "baro_altitude": baro_altitude, "dt": dt}[name]
    where = name if index is None or (name == "dt" and not dt_is_array) else f"{name}[{index}]"
    raise ValueError(f"{where} {rule}, got {value!r}")


def check_settings_values(values: Dict[str, float]) -> RocketStatus:
    """FusionAltitudeRocketSettingsCheck on the float fields (the observer gains are checked by the caller)."""
    for index, (name, _, rule, _) in enumerate(SETTINGS_FIELDS):
        value = np.float32(values[name])
        finite = bool(np.isfinite(value))
        if rule == "positive":
            bad = not (finite and value > 0)
        elif rule == "non_negative":
            bad = not (finite and value >= 0)
        elif rule == "rate":
            bad = not (finite and value > 0 and value <= 1)
        elif rule == "finite":
            bad = not finite
        else:
            bad = bool(np.isnan(value)) or not value > 0
        if bad:
            return RocketStatus(RocketStatus.INVALID_STATIONARY_ACCEL + index)
    return RocketStatus.OK


def convert_settings(kwargs: Dict[str, object]) -> Dict[str, float]:
    """Keyword settings with defaults filled, as Python floats; TypeError for unknown names or non-reals."""
    unknown = sorted(set(kwargs) - set(FIELD_NAMES))
    if unknown:
        raise TypeError(f"unknown rocket setting {unknown[0]!r}; known: {', '.join(FIELD_NAMES)}")
    values = {}
    for name in FIELD_NAMES:
        value = kwargs.get(name, DEFAULTS[name])
        with np.errstate(over="ignore"):
            values[name] = float(np.float32(as_float(value, name)))
    return values


class FlightEvent(NamedTuple):
    """One flight event.

    Attributes
    ----------
    name : str
        ``launch``, ``burnout``, ``max_speed``, ``apogee``, ``main`` or ``landed``.
    occurred : bool
        Whether it was declared.
    sample : int
        Index of the step that declared it (launch, burnout, landed: the first
        step of the run that confirmed it).
    time : float
        s: since the estimator was initialised, or the log's own time of that
        sample when built by :func:`fusion_altitude.rocket.run_rocket`.
    height : float
        Height above the pad at that step, m.
    velocity : float
        Vertical velocity at that step, m/s, +up.
    """

    name: str
    occurred: bool
    sample: int
    time: float
    height: float
    velocity: float


class FlightEvents:
    """The events of one flight, in the order launch, burnout, max_speed, apogee, main, landed.

    Index by name (``events["apogee"]``) or iterate; events that did not occur
    are present with ``occurred`` False.
    """

    __slots__ = ("_events",)

    def __init__(self, events: Sequence[FlightEvent]) -> None:
        if tuple(event.name for event in events) != EVENT_NAMES:
            raise ValueError(f"events must be named {EVENT_NAMES}")
        self._events = tuple(events)

    def __getitem__(self, name: str) -> FlightEvent:
        if name not in EVENT_NAMES:
            raise KeyError(f"event must be one of {', '.join(EVENT_NAMES)}; got {name!r}")
        return self._events[EVENT_NAMES.index(name)]

    def __iter__(self) -> Iterator[FlightEvent]:
        return iter(self._events)

    def __len__(self) -> int:
        return len(self._events)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, FlightEvents):
            return NotImplemented
        return self._events == other._events

    def __repr__(self) -> str:
        parts = [f"{e.name}@{e.time:.3f}s/{e.height:.1f}m" for e in self._events if e.occurred]
        return f"FlightEvents({', '.join(parts)})"

    def occurred(self) -> Tuple[FlightEvent, ...]:
        """The events that were declared, in flight order."""
        return tuple(event for event in self._events if event.occurred)

    def with_times(self, time: object) -> "FlightEvents":
        """The same events with ``time`` set from a log's time array (s) at each event's sample."""
        times = np.asarray(time, dtype=np.float64)
        return FlightEvents([event._replace(time=float(times[event.sample])) if event.occurred else event
                             for event in self._events])

    def to_csv(self, path: Union[str, os.PathLike]) -> None:
        """Write ``event,time,height`` (s, m above the pad), one row per declared event of
        launch, burnout, apogee, main, landed, in that order. Written whole or not at all."""
        path = os.fspath(path)
        temporary = f"{path}.partial"
        with open(temporary, "w", newline="") as handle:
            writer = csv.writer(handle, lineterminator="\n")
            writer.writerow(("event", "time", "height"))
            for name in CSV_EVENTS:
                event = self[name]
                if event.occurred:
                    writer.writerow((name, repr(float(event.time)), repr(float(event.height))))
        os.replace(temporary, path)


def events_from_tuples(rows: Sequence[Tuple[bool, int, float, float, float]]) -> FlightEvents:
    """FlightEvents from (occurred, sample, time, height, velocity) rows in C order."""
    return FlightEvents([FlightEvent(name, bool(o), int(s), float(t), float(h), float(v))
                         for name, (o, s, t, h, v) in zip(EVENT_NAMES, rows)])


class RocketBatch(NamedTuple):
    """Per-sample outputs of ``update_batch``.

    Attributes
    ----------
    height : numpy.ndarray
        float32, height above the pad after each step, m.
    vertical_velocity : numpy.ndarray
        float32, m/s, +up.
    accel_bias : numpy.ndarray
        float32, accelerometer bias in use, m/s².
    phase : numpy.ndarray
        uint8, :class:`Phase` after each step.
    baro : numpy.ndarray
        uint8, :class:`BaroFate` of each step's baro sample.
    """

    height: np.ndarray
    vertical_velocity: np.ndarray
    accel_bias: np.ndarray
    phase: np.ndarray
    baro: np.ndarray


def prepare_batch(accel: object, baro_altitude: object, dt: object, out: Optional[Sequence[np.ndarray]]
                  ) -> Tuple[np.ndarray, np.ndarray, np.ndarray, bool, RocketBatch]:
    """Inputs as contiguous float32 (dt of length n or 1) and the output arrays (new, or ``out`` checked)."""
    accel32, baro32, dt32, dt_is_array = prepare_inputs(accel, baro_altitude, dt)
    n = accel32.shape[0]
    dtypes = (np.float32, np.float32, np.float32, np.uint8, np.uint8)
    if out is None:
        return accel32, baro32, dt32, dt_is_array, RocketBatch(*(np.empty(n, dtype=d) for d in dtypes))
    if len(out) != 5:
        raise ValueError(f"out must hold 5 arrays {RocketBatch._fields}, got {len(out)}")
    for field, array, dtype in zip(RocketBatch._fields, out, dtypes):
        if not isinstance(array, np.ndarray) or array.dtype != dtype or array.shape != (n,) \
                or not array.flags.c_contiguous or not array.flags.writeable:
            raise ValueError(f"out.{field} must be a writeable contiguous {np.dtype(dtype).name} array of shape ({n},)")
    return accel32, baro32, dt32, dt_is_array, RocketBatch(*out)


def is_real_nan(value: float) -> bool:
    return isinstance(value, float) and math.isnan(value)


__all__ = ["RocketStatus", "Phase", "BaroFate", "FlightEvent", "FlightEvents", "RocketBatch", "EVENT_NAMES",
           "CSV_EVENTS", "SETTINGS_FIELDS", "MACH_LOCKOUT", "as_float32_vector"]


class RocketSettings:
    """Settings of the rocket flight layer (``FusionAltitudeRocketSettings``), float32.

    Parameters
    ----------
    observer : AltitudeSettings or (float, float, float), optional
        Observer gains (Kh 1/s, Kv 1/s², Kb 1/s³) in flight; the rocket gains
        (1.4, 1.0, 0: ω 1 rad/s, ζ 0.7, no in-flight bias learning) if omitted.
        The bias gain is forced to 0 from apogee on.
    stationary_accel : float, default 5.0
        m/s²: a pad sample within this of its window's first sample is stationary.
    calibration_window : float, default 0.5
        s: pad calibration window; only all-stationary windows are learned.
    launch_accel : float, default 20.0
        m/s²: accel − bias above this ...
    launch_time : float, default 0.05
        s: ... for this long declares launch.
    burnout_accel : float, default 0.0
        m/s²: accel − bias below this ...
    burnout_time : float, default 0.1
        s: ... for this long declares burnout.
    apogee_margin : float, default 1.0
        m/s: apogee when the velocity estimate falls below −apogee_margin.
    lockout_speed : float, default 100.0
        m/s: the baro is not fused while |v| exceeds this (and always above 236 m/s, Mach 0.8).
    spike_threshold : float, default 20.0
        m: a baro sample this far from the baro's own prediction is a spike.
    spike_time : float, default 0.2
        s: longest run of spike rejections; then the new level is accepted.
    offset_rate : float, default 0.9
        The output height absorbs the baro offset found at re-admission at up
        to ``offset_rate·|v|`` m/s (0 < offset_rate ≤ 1).
    main_altitude : float, default 250.0
        m above the pad: main deployment on the way down.
    landed_speed : float, default 3.0
        m/s: |v| below this ...
    landed_time : float, default 2.0
        s: ... for this long declares landing.
    gap_period : float, default 0.5
        s: an update with a longer dt is a gap (counted; extrapolated in flight).

    Raises
    ------
    ValueError
        A value breaks its rule (named in the message); TypeError for an
        unknown name or a non-real value.
    """

    __slots__ = ("gains", "values")

    def __init__(self, observer: object = None, **kwargs: object) -> None:
        if observer is None:
            gains = ROCKET_GAINS
        elif hasattr(observer, "as_tuple"):
            gains = tuple(observer.as_tuple())[:3]  # type: ignore[attr-defined]
        else:
            gains = tuple(as_float(g, "observer") for g in observer)  # type: ignore[union-attr]
            if len(gains) != 3:
                raise ValueError(f"observer must hold 3 gains, got {len(gains)}")
        from .reference.observer import _check_gains  # the C check, in float32
        gains32 = tuple(np.float32(g) for g in gains)
        values = convert_settings(kwargs)
        if _check_gains(*gains32) != 0:
            raise_settings_error(RocketStatus.INVALID_OBSERVER_SETTINGS, {"observer": tuple(gains)})
        status = check_settings_values(values)
        if status != RocketStatus.OK:
            raise_settings_error(status, values)
        self.gains = tuple(float(g) for g in gains32)
        self.values = values

    def __getattr__(self, name: str) -> float:
        values = object.__getattribute__(self, "values")
        if name in values:
            return values[name]
        raise AttributeError(name)

    def as_dict(self) -> Dict[str, object]:
        """Every field: ``observer`` (the 3 gains) and the floats, as Python values."""
        return {"observer": self.gains, **self.values}

    def replace(self, **changes: object) -> "RocketSettings":
        """A copy with some fields changed (validated)."""
        fields = self.as_dict()
        fields.update(changes)
        return RocketSettings(**fields)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, RocketSettings):
            return NotImplemented
        return self.as_dict() == other.as_dict()

    def __repr__(self) -> str:
        return "RocketSettings(" + ", ".join(f"{k}={v!r}" for k, v in self.as_dict().items()) + ")"

    def __reduce__(self):
        return (_rebuild_settings, (self.as_dict(),))


def _rebuild_settings(fields: Dict[str, object]) -> RocketSettings:
    return RocketSettings(**fields)
