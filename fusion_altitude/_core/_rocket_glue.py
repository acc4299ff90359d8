"""Glue of the rocket estimator shared by its binding (``_rocket.pyx``) and its
reference (``reference/rocket.py``): the settings rules (the enums, defaults and
status messages are generated from the header into ``_c_tables``), the
``FlightEvents`` result, error messages naming the argument and batch
argument conversion. No algorithm lives here (see ``csrc/fusion_altitude_rocket.h``).
"""

from __future__ import annotations

import csv
import math
import os
from typing import Dict, Iterator, NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np

from . import _c_tables
from ._c_tables import BaroFate, Phase, RocketEventId, RocketStatus
from ._common import (BARO_SAMPLE_OR_NAN, DT_POSITIVE, as_float, as_float32_vector, check_no_overlap, input_rules,
                      raise_input_error)
from ._observer_glue import prepare_inputs


#: Event names in the order of the C enum ``FusionAltitudeRocketEventId``.
EVENT_NAMES = tuple(event.name.lower() for event in RocketEventId)

#: Events written by :meth:`FlightEvents.to_csv` (one row each, when they occurred).
CSV_EVENTS = ("launch", "burnout", "apogee", "main", "landed")

#: Speed above which the baro is always locked out, m/s (FUSION_ALTITUDE_ROCKET_MACH_LOCKOUT).
MACH_LOCKOUT = _c_tables.FUSION_ALTITUDE_ROCKET_MACH_LOCKOUT

def _rule(terms: tuple) -> str:
    """The name of a field's rule terms (``_c_tables.ROCKET_RULES``, from the header)."""
    if "finite" not in terms:
        return "gap"
    if ("<=", 1) in terms:
        return "rate"
    return "positive" if (">", 0) in terms else "non_negative" if (">=", 0) in terms else "finite"


#: The check of each settings field after ``observer`` (FusionAltitudeRocketSettingsCheck): "positive",
#: "non_negative", "finite", "rate" (in (0, 1]) or "gap" (> 0, +inf allowed): the ``[rule: ...]`` of each field's
#: comment in the header (:data:`fusion_altitude._c_tables.ROCKET_RULES`).
SETTINGS_RULES = {name: _rule(terms) for name, (_, terms) in _c_tables.ROCKET_RULES.items() if name != "observer"}

#: Settings fields after the observer settings, in C declaration (and check) order: (name, default, rule, unit),
#: the defaults and units read from the header (:mod:`fusion_altitude._c_tables`).
SETTINGS_FIELDS: Tuple[Tuple[str, float, str, str], ...] = tuple(
    (name, default, SETTINGS_RULES[name], comment.split(":")[0].replace("^2", "²").replace("1", "dimensionless"))
    for name, _, kind, default, comment in _c_tables.ROCKET_SETTINGS if kind != "s")

FIELD_NAMES = tuple(field[0] for field in SETTINGS_FIELDS)
DEFAULTS = {field[0]: field[1] for field in SETTINGS_FIELDS}

#: The rocket observer settings of FusionAltitudeRocketSettingsDefault(): (Kh 1/s, Kv 1/s², Kb 1/s³, gap period s),
#: ω 1.0 rad/s, ζ 0.7, ω_b 0 (bias frozen in flight).
ROCKET_OBSERVER = dict((name, default) for name, _, kind, default, _ in _c_tables.ROCKET_SETTINGS)["observer"]

#: The rocket observer gains (Kh, Kv, Kb).
ROCKET_GAINS = ROCKET_OBSERVER[:3]

_RULE_TEXT = {"positive": "must be finite and > 0", "non_negative": "must be finite and >= 0",
              "finite": "must be finite", "rate": "must be > 0 and <= 1", "gap": "must be > 0 (+inf: never a gap)"}


def raise_settings_error(status: int, values: Dict[str, float]) -> None:
    """Raise the ValueError for rejected settings, naming the field."""
    status = RocketStatus(status)
    if status == RocketStatus.INVALID_OBSERVER_SETTINGS:
        raise ValueError(f"observer gains are invalid or unstable, got {values.get('observer')!r}")
    name, _, rule, unit = SETTINGS_FIELDS[status - RocketStatus.INVALID_STATIONARY_ACCEL]
    raise ValueError(f"{name} {_RULE_TEXT[rule]} ({unit}), got {values[name]!r}")


_UPDATE_RULES = input_rules(RocketStatus, accel="must be finite, or NaN for no accelerometer sample (m/s²)",
                            baro_altitude=BARO_SAMPLE_OR_NAN, dt=DT_POSITIVE)


def raise_update_error(status: int, accel: float, baro_altitude: float, dt: float, index: Optional[int] = None,
                       dt_is_array: bool = False) -> None:
    """Raise the ValueError for a rejected update, naming the argument (and the first bad index)."""
    raise_input_error(_UPDATE_RULES, RocketStatus(status), {"accel": accel, "baro_altitude": baro_altitude, "dt": dt},
                      index, {"dt": dt_is_array})


#: The C settings functions the settings class calls instead of the twins here, once the binding (``_rocket.pyx``)
#: registers them at import: ``"check"`` → ``c_settings_check`` (the twin: :func:`check_settings_values` without
#: it). Without the compiled extension it stays empty (``tests/test_settings_checks.py`` holds the twin equal to C).
C_SETTINGS_FUNCTIONS: dict = {}


def check_settings_values(values: Dict[str, float]) -> RocketStatus:
    """FusionAltitudeRocketSettingsCheck on the float fields (the observer gains are checked by the caller): C's
    (with the header's rocket observer) where the binding registered it, else the twin below."""
    c_function = C_SETTINGS_FUNCTIONS.get("check")
    if c_function is not None:
        return RocketStatus(c_function({**values, "observer": ROCKET_OBSERVER}))
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
    check_no_overlap(dict(zip(RocketBatch._fields, out)))
    return accel32, baro32, dt32, dt_is_array, RocketBatch(*out)


def is_real_nan(value: float) -> bool:
    return isinstance(value, float) and math.isnan(value)


__all__ = ["RocketStatus", "Phase", "BaroFate", "FlightEvent", "FlightEvents", "RocketBatch", "EVENT_NAMES",
           "CSV_EVENTS", "SETTINGS_FIELDS", "MACH_LOCKOUT", "as_float32_vector", "observer_settings"]


def observer_settings(observer: object) -> Tuple[float, ...]:
    """The ``observer`` setting as (Kh, Kv, Kb, gap period, baro timeout), float32-rounded Python floats: None (the
    rocket observer), observer settings (``as_tuple`` and ``gap_period``), or 3 gains (the rocket gap period) or 4 or
    5 values. The baro timeout is the rocket observer's (+inf: the rocket estimator dead-reckons through its baro lockout
    on purpose) unless 5 values are given. TypeError for non-reals, ValueError for a wrong count; the stability check
    is the caller's."""
    if observer is None:
        values = ROCKET_OBSERVER
    elif hasattr(observer, "as_tuple"):
        values = (*tuple(observer.as_tuple())[:3], getattr(observer, "gap_period", ROCKET_OBSERVER[3]),  # type: ignore
                  ROCKET_OBSERVER[4])
    else:
        values = tuple(as_float(g, "observer") for g in observer)  # type: ignore[union-attr]
        if len(values) == 3:
            values = (*values, ROCKET_OBSERVER[3])
        if len(values) == 4:
            values = (*values, ROCKET_OBSERVER[4])
        if len(values) != 5:
            raise ValueError(f"observer must hold 3 gains (and optionally a gap period and a baro timeout), got "
                             f"{len(values)} values")
    with np.errstate(over="ignore"):
        return tuple(float(np.float32(as_float(v, "observer"))) for v in values)  # type: ignore[return-value]


class RocketContract:
    """The public methods whose docstring the RocketEstimator binding and reference share, written once here:
    ``_common.share_docstrings`` gives them to both classes."""

    def update(self, accel: float, baro_altitude: float, dt: float, *, accel_is_vertical: bool = False) -> None:
        """Process one step.

        Parameters
        ----------
        accel : float
            m/s², gravity removed, +up: the long-axis accelerometer minus g
            (used as vertical until apogee, ignored after it) or, with
            ``accel_is_vertical``, a trusted earth-frame vertical acceleration
            from an INS (used in every phase). NaN: no accelerometer sample
            (in flight the layer is baro-led from then on).
        baro_altitude : float
            Pressure altitude, m; NaN when no baro sample arrived this step.
        dt : float
            s since the previous step.
        accel_is_vertical : bool, default False
            See ``accel``.

        Raises
        ------
        ValueError
            accel or baro_altitude infinite, dt not finite or <= 0;
            the state is unchanged.
        """
