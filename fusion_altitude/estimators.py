"""The estimator registry: one row per estimator, read by ``run``, ``compare``, the fleet and the tests.

Each :class:`EstimatorEntry` says once what the applications need to know about an estimator: its CLI name
(``--estimator``), its label in ``compare``'s tables, the :mod:`fusion_altitude` class it runs, the log fields it
cannot run without, the vehicle it is made for, whether it fuses GPS, whether the observer's presets apply, and its
adapter (:mod:`fusion_altitude.adapters`, imported on first use). :func:`observer_rate` computes, once per log, the
rate figures of the observer's preset rule and its stability advice (steps per baro sample, the default preset, the
presets stable at the log's rate).

The built-in rows are written once, each on its adapter (:func:`fusion_altitude.adapters.registry_row`: a new
estimator is one decorated adapter there); :data:`ESTIMATORS` holds one :class:`EstimatorEntry` of each adapter
of :data:`fusion_altitude.adapters.ADAPTERS`, in their order. An estimator from outside the package joins by one
:func:`register_estimator` call::

    from fusion_altitude import estimators

    estimators.register_estimator(estimators.EstimatorEntry("mine", "my filter (baro + accel)", run_mine))
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import Callable, Dict, List, Tuple, Union

import numpy as np

from ._core._observer import AltitudeSettings
from .adapters import ADAPTERS, DEFAULT_PRESET_ORDER, default_preset
from .logs import LogData
from .tuning import nominal_period, stable_at, steps_per_baro

__all__ = ["EstimatorEntry", "ESTIMATORS", "register_estimator", "estimator_names", "missing_inputs",
           "applicable_estimators", "DEFAULT_PRESET_ORDER", "ADVICE_PRESETS", "ObserverRate", "observer_rate",
           "default_preset"]


@dataclass(frozen=True)
class EstimatorEntry:
    """One estimator that can run on a :class:`LogData`.

    Attributes
    ----------
    name : str
        Registry key and ``--estimator`` choice.
    description : str
        One line: what it is and which sensors of the log it uses.
    run : callable(data, dt, options) -> NamedTuple
        ``data`` a :class:`LogData`, ``dt`` the per-sample periods (s, from
        :func:`sample_periods`), ``options`` a dict (``settings``,
        ``progress``); returns per-sample outputs with ``altitude`` (m) and
        ``vertical_velocity`` (m/s) fields. It may put ``options["events"]``
        (a :class:`~fusion_altitude.rocket.FlightEvents`), which lands in
        ``LogRun.events``.
    needs : tuple of str, default ()
        :class:`LogData` fields the estimator cannot run without (e.g.
        ``("gyro", "accel")`` for the INS); ``compare LOG`` leaves it out on
        logs that lack one (:func:`applicable_estimators`), ``run`` refuses
        it by name.
    vehicle : str, default ""
        Non-empty: ``compare LOG`` runs it only on logs of that
        ``LogData.vehicle`` (the rocket estimator waits on the pad forever on a
        multirotor log), and ``compare`` on the scenario of that name; ``run``
        still runs it on any log when asked.
    label : str, default ""
        Its row in ``compare``'s tables ("Kalman", "INS"); the name if empty.
    estimator_class : str, default ""
        The class of :mod:`fusion_altitude` that it runs (``"KalmanEstimator"``).
    uses_gps : bool, default False
        It fuses the log's GPS altitude (``run`` says so when the log has one).
    takes_preset : bool, default False
        Its settings are the observer's gains: ``run --preset`` and the default preset rule
        (:func:`observer_rate`) apply to it, to no other.
    has_gap_period : bool, default False
        It has a gap period (s), run at ``max(its default, 10 × the log's nominal period)``
        (:func:`fusion_altitude.tuning.gap_period_for`) and counted in ``LogRun.gap_count``.

    ``run`` may also be ``"module:function"`` (a function of the package, imported on first use), so that this
    table imports no estimator: :meth:`function` returns the callable.
    """

    name: str
    description: str
    run: Union[Callable[[LogData, np.ndarray, dict], object], str]
    needs: Tuple[str, ...] = ()
    vehicle: str = ""
    label: str = ""
    estimator_class: str = ""
    uses_gps: bool = False
    takes_preset: bool = False
    has_gap_period: bool = False

    def function(self) -> Callable[[LogData, np.ndarray, dict], object]:
        """The adapter ``run(data, dt, options)``: :attr:`run`, imported if it is given as ``"module:function"``."""
        if not isinstance(self.run, str):
            return self.run
        module, name = self.run.split(":")
        return getattr(importlib.import_module(f"fusion_altitude.{module}"), name)

    @property
    def table_label(self) -> str:
        """The row label in ``compare``'s tables: :attr:`label`, else :attr:`name`."""
        return self.label or self.name


#: Registered estimators by name, in table order.
ESTIMATORS: Dict[str, EstimatorEntry] = {}


def register_estimator(entry: EstimatorEntry) -> None:
    """Add (or replace) an estimator of :data:`ESTIMATORS`; it appears in ``run --estimator`` and ``compare LOG``."""
    if not isinstance(entry, EstimatorEntry):
        raise TypeError(f"entry must be an EstimatorEntry, got {type(entry).__name__}")
    ESTIMATORS[entry.name] = entry


def estimator_names() -> List[str]:
    """The registered estimator names, in table order."""
    return list(ESTIMATORS)


def missing_inputs(data: LogData, estimator: str) -> List[str]:
    """The :class:`LogData` fields that ``estimator`` needs (``EstimatorEntry.needs``) and ``data`` lacks."""
    return [name for name in ESTIMATORS[estimator].needs if getattr(data, name, None) is None]


def applicable_estimators(data: LogData) -> List[str]:
    """The registered estimators ``compare LOG`` runs on ``data``, in table order: every input they need is in the
    log and, for an entry made for one kind of vehicle (``EstimatorEntry.vehicle``), the log is of that kind."""
    return [name for name, entry in ESTIMATORS.items()
            if not missing_inputs(data, name) and entry.vehicle in ("", getattr(data, "vehicle", ""))]


for _adapter in ADAPTERS:  # the built-in rows, each written on its adapter (adapters.registry_row)
    register_estimator(EstimatorEntry(run=_adapter, **_adapter.registry_row))
del _adapter


# ----------------------------------------------------------------------------
# the observer's preset rule and stability advice, computed once per log

#: The presets the stability advice may name, slowest first.
ADVICE_PRESETS = ("balloon", "fixed_wing", "vtol", "racing", "rocket")


@dataclass(frozen=True)
class ObserverRate:
    """The rate figures of one log that the observer's preset rule and stability advice use.

    Attributes
    ----------
    nominal_period : float
        The log's nominal sample period, s (median dt).
    steps_per_baro : float
        Grid steps per baro sample (:func:`fusion_altitude.tuning.steps_per_baro`); the gains run multiplied by it.
    stability_period : float
        ``nominal_period * steps_per_baro``, s: the period at which the gains must pass Jury's test.
    default_preset : str
        The preset ``run`` uses without ``--preset`` (:func:`default_preset`).
    stable_presets : tuple of str
        The presets of :data:`ADVICE_PRESETS` stable at ``stability_period``.
    """

    nominal_period: float
    steps_per_baro: float
    stability_period: float
    default_preset: str
    stable_presets: Tuple[str, ...]

    def is_stable(self, settings: AltitudeSettings) -> bool:
        """Whether ``settings`` pass the core's stability rule at :attr:`stability_period`."""
        if isinstance(settings, str):
            return settings in self.stable_presets
        return stable_at(settings, self.stability_period)


def observer_rate(data: LogData) -> ObserverRate:
    """The :class:`ObserverRate` of ``data``: each figure computed once."""
    nominal = nominal_period(data.time)
    steps = steps_per_baro(data.baro_altitude)
    period = nominal * steps
    stable = tuple(name for name in ADVICE_PRESETS if stable_at(AltitudeSettings.preset(name), period))
    return ObserverRate(nominal, steps, period, default_preset(data), stable)

