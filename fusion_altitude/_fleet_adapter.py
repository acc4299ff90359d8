"""The one place where :mod:`fusion_altitude.fleet` calls the rest of the package.

Fleet processing runs, per log, exactly what ``fusion-altitude run`` runs on
one file: read the log, run the estimator, take the columns that ``run -o``
writes. Those interfaces are moving (``fusion_altitude.logs`` is becoming a
package of readers, ``run_log``/``write_csv`` are moving to
``fusion_altitude.runner`` with an ``estimator=`` argument), so every call
into them is here and nowhere else: retarget these functions, and the fleet
follows.
"""

from __future__ import annotations

import dataclasses
import inspect
import math
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

__all__ = ["LOG_ERRORS", "estimator_names", "resolve_settings", "settings_key", "read_log", "run_log",
           "run_columns", "write_csv", "compare", "sweep", "fit", "sample_periods", "fit_mask", "steps_per_baro",
           "stability_period", "fit_score", "fit_search", "without_gap_transients", "default_settings",
           "settings_from_bandwidth", "fit_landscape_dtype"]


def _logs():
    from . import logs
    return logs


def _runner():
    """``fusion_altitude.runner`` (where ``run_log``/``write_csv`` are moving) if it exists, else None."""
    try:
        from . import runner
    except ImportError:
        return None
    return runner


def _from_runner_or_logs(name: str):
    """``runner.<name>`` if the runner module has it, else ``logs.<name>``."""
    runner = _runner()
    if runner is not None and hasattr(runner, name):
        return getattr(runner, name)
    return getattr(_logs(), name)


#: Exceptions that mean "this log cannot be used", as opposed to a problem of
#: the machine (a missing package, a full disk): the first kind is recorded and
#: not retried with the same settings, the second is reported and retried.
LOG_ERRORS: Tuple[type, ...] = (ValueError,)  # logs.LogError is a ValueError


def estimator_names() -> Tuple[str, ...]:
    """Estimators a log can be run with."""
    runner = _runner()
    if runner is not None and hasattr(runner, "ESTIMATORS"):
        return tuple(runner.ESTIMATORS)
    if runner is not None and "estimator" in inspect.signature(runner.run_log).parameters:
        return ("observer", "kalman", "complementary", "alphabeta")  # the runner's announced set
    return ("observer",)


def resolve_settings(estimator: str, settings: Any) -> Any:
    """The settings object for ``estimator``: None (its default), a preset name, or a settings object."""
    if estimator not in estimator_names():
        raise ValueError(f"estimator must be one of {', '.join(estimator_names())}, got {estimator!r}")
    if estimator == "observer":
        from ._core._observer import AltitudeSettings
        if settings is None:
            return AltitudeSettings()
        if isinstance(settings, str):
            return AltitudeSettings.preset(settings)
        if not isinstance(settings, AltitudeSettings):
            raise TypeError(f"settings must be an AltitudeSettings or a preset name, got {type(settings).__name__}")
        return settings
    if isinstance(settings, str):
        raise ValueError(f"settings: presets by name exist for the observer only, got {settings!r} for {estimator}")
    return settings


def _jsonable(value: Any) -> Any:
    if isinstance(value, float):
        return value.hex() if math.isfinite(value) else repr(value)
    if isinstance(value, (np.floating,)):
        return float(value).hex()
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in sorted(value.items())}
    if value is None or isinstance(value, (bool, int, str)):
        return value
    return repr(value)


def settings_key(estimator: str, settings: Any) -> Dict[str, Any]:
    """A JSON-able, exact description of the settings (floats as hex), for the settings hash."""
    if settings is None:
        values: Any = None
    elif hasattr(settings, "as_tuple"):
        values = list(settings.as_tuple())
    elif dataclasses.is_dataclass(settings):
        values = dataclasses.asdict(settings)
    else:
        values = repr(settings)
    return {"estimator": estimator, "type": type(settings).__name__, "values": _jsonable(values)}


def read_log(path: str, csv_options: Optional[Dict[str, Any]] = None):
    """Read one local log file as ``fusion-altitude run`` does (``LogData``); ``csv_options``
    go to the logs that need column names (generic CSV) only.

    A CSV log without the column options its reader needs raises ``ValueError``
    (a property of the log and the options, like any reader error).
    """
    logs = _logs()
    options = dict(csv_options or {})
    if options and hasattr(logs, "sniff_format") and hasattr(logs, "FORMATS"):
        # the readers package rejects column options for formats that know their columns
        if not getattr(logs.FORMATS[logs.sniff_format(path)], "needs_columns", False):
            options = {}
    try:
        from .logs._data import quiet_warnings

        with quiet_warnings():  # the warnings are in LogData.warnings: the summary and the CLI report them
            return logs.load_log(path, **options)
    except TypeError as error:
        raise ValueError(f"{path}: this log needs csv_options ({error})") from None


def run_log(data, estimator: str, settings: Any):
    """Run ``estimator`` on a ``LogData`` with the function ``fusion-altitude run`` calls."""
    function = _from_runner_or_logs("run_log")
    if "estimator" in inspect.signature(function).parameters:
        return function(data, estimator=estimator, settings=settings)
    if estimator != "observer":
        raise ValueError(f"estimator {estimator!r}: this build's run_log runs the observer only")
    return function(data, settings)


def run_columns(run) -> List[Tuple[str, np.ndarray]]:
    """The per-step columns ``run -o`` writes, in its order, each in its native dtype.

    ``runner.csv_columns`` where it exists; else mirrors ``logs.write_csv``: time
    s, baro_altitude m, vertical_acceleration m/s², altitude m, vertical_velocity
    m/s, accel_bias m/s², baro_residual m and, if present, reference_altitude m.
    """
    runner = _runner()
    if runner is not None and hasattr(runner, "csv_columns"):
        return [(name, np.asarray(values)) for name, values in runner.csv_columns(run)]
    columns = [("time", run.time), ("baro_altitude", run.baro_altitude),
               ("vertical_acceleration", run.vertical_acceleration), ("altitude", run.estimate.altitude),
               ("vertical_velocity", run.estimate.vertical_velocity), ("accel_bias", run.estimate.accel_bias),
               ("baro_residual", run.estimate.baro_residual)]
    if run.reference_altitude is not None:
        columns.append(("reference_altitude", run.reference_altitude))
    return [(name, np.asarray(values)) for name, values in columns]


def write_csv(run, path: str) -> None:
    """The CSV ``fusion-altitude run -o`` writes."""
    return _from_runner_or_logs("write_csv")(run, path)


def compare(run) -> Tuple[Optional[Any], Optional[Any]]:
    """(fused − reference, baro − reference) :class:`~fusion_altitude.metrics.ErrorStatistics`, or (None, None)."""
    return run.comparison(), run.baro_comparison()


def sample_periods(time) -> np.ndarray:
    """Per-sample dt (s) as ``fusion-altitude run`` and ``fit`` compute it."""
    return _from_runner_or_logs("sample_periods")(time)


def sweep(accel, baro_altitude, dt, gains, reference, mask):
    """:func:`fusion_altitude.tuning.sweep` on one thread (a fleet worker is one core)."""
    from . import tuning
    return tuning.sweep(accel, baro_altitude, dt, gains, reference=reference, mask=mask, threads=1)


def fit(accel, baro_altitude, dt, reference, mask, **options):
    """:func:`fusion_altitude.tuning.fit` (the single-machine fit the fleet fit must equal)."""
    from . import tuning
    return tuning.fit(accel, baro_altitude, dt, reference, mask=mask, **options)


def without_gap_transients(dt, mask):
    """:func:`fusion_altitude.tuning.without_gap_transients`: the fit metric's mask without each gap's transient."""
    from . import tuning
    return tuning.without_gap_transients(dt, mask)


def fit_mask(time, skip: float) -> np.ndarray:
    """The samples ``fusion-altitude fit --skip`` scores (:func:`fusion_altitude.tuning.training_mask`)."""
    from . import tuning
    return tuning.training_mask(time, skip)


def steps_per_baro(baro_altitude) -> float:
    """Grid steps per baro sample, as ``fusion-altitude fit`` passes it (:func:`fusion_altitude.tuning.steps_per_baro`)."""
    from . import tuning
    return tuning.steps_per_baro(baro_altitude)


def stability_period(dt, steps_per_baro: float) -> float:
    """Period of :func:`fusion_altitude.tuning.fit`'s stability check for one log, s (median dt · steps per baro)."""
    from . import tuning
    return tuning.stability_period(dt, steps_per_baro)


def fit_score(accel, baro_altitude, dt, reference, mask, gains, steps_per_baro: float):
    """:func:`fusion_altitude.tuning.score` (fit's metric, baro-rate compensated) on one thread."""
    from . import tuning
    return tuning.score(accel, baro_altitude, dt, reference, mask, gains, steps_per_baro, threads=1)


def fit_search(evaluate_rms, dt_check: float, omega_range, zetas, bias_ratios, refinements: int):
    """:func:`fusion_altitude.tuning.search`: fit's candidate search with the caller's metric."""
    from . import tuning
    return tuning.search(evaluate_rms, dt_check, omega_range, zetas, bias_ratios, refinements)


def default_settings():
    """The gains :func:`fusion_altitude.tuning.fit` reports as the default (VTOL) for comparison."""
    from ._core._observer import AltitudeSettings
    return AltitudeSettings()


def settings_from_bandwidth(omega: float, zeta: float, omega_b: float):
    """Observer gains from ω (rad/s), ζ and ω_b (rad/s), as :func:`fusion_altitude.tuning.fit` builds its result."""
    from ._core._observer import AltitudeSettings
    return AltitudeSettings.from_bandwidth(omega, zeta, omega_b)


def fit_landscape_dtype():
    """The structured dtype of :attr:`fusion_altitude.tuning.FitResult.landscape`."""
    from . import tuning
    return tuning._LANDSCAPE
