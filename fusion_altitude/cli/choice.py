"""Which estimator and observer preset ``run`` (and ``report``, by the same rule) uses on a log, and the
stability warnings about a preset at the log's rate (:func:`fusion_altitude.estimators.observer_rate`)."""

from __future__ import annotations

import argparse
import sys

from .common import CliError

__all__ = ["run_estimator", "default_preset", "warn_if_unstable"]


def run_estimator(args: argparse.Namespace, data, health=()) -> str:
    """The estimator ``run`` uses: ``--estimator``, else ``rocket`` for a rocket log (or ``--rocket``), else the
    Kalman filter when the baro stops before the log's end and the log has GPS (it carries on with the GPS), else
    the INS when the log has a raw gyro and accelerometer (and no ``--preset``, which names observer gains), else
    the observer. CliError when the flags contradict each other or the log lacks what the estimator needs."""
    from .. import runner

    rocket = args.rocket or getattr(data, "vehicle", "") == "rocket"
    baro_stops = any(s.name == "baro" and s.stopped for s in health)
    gps = any(s.name == "gps" and s.samples > 0 for s in health)
    if args.estimator:
        estimator = args.estimator
    elif rocket:
        estimator = "rocket"
    elif baro_stops and gps and args.preset is None:
        estimator = "kalman"
    elif args.preset is None and not runner.missing_inputs(data, "ins"):
        estimator = "ins"
    else:
        estimator = "observer"
    if args.preset is not None and estimator != "observer":
        raise CliError(f"--preset names observer gains; it does not apply to --estimator {estimator}")
    if args.rocket and estimator != "rocket":
        raise CliError(f"--rocket runs the rocket estimator; it cannot be combined with --estimator {estimator}")
    if args.events_csv and estimator != "rocket":
        raise CliError(f"--events-csv needs the rocket estimator (a rocket log, --rocket or --estimator rocket), "
                       f"not --estimator {estimator}")
    if args.long_axis and estimator != "rocket":
        raise CliError("--long-axis applies to the rocket estimator only")
    missing = runner.missing_inputs(data, estimator)
    if missing:
        raise CliError(f"--estimator {estimator} needs raw {' and '.join(missing)} in the log; {data.source} has no "
                       f"{' or '.join(missing)} (PX4 sensor_combined, ArduPilot IMU, CSV --gyro-body/--accel-body)")
    return estimator


def default_preset(rate) -> str:
    """The observer preset ``run`` uses without ``--preset`` (``rate.default_preset``, of
    :func:`fusion_altitude.estimators.observer_rate`); a change from vtol is said on stderr."""
    name = rate.default_preset
    if name != "vtol":
        print(f"note: the default preset vtol is unstable at this log's rate (nominal period "
              f"{rate.nominal_period:g} s, baro on 1 of {rate.steps_per_baro:.2f} steps): running preset {name}, the "
              "fastest one stable there", file=sys.stderr)
    elif not rate.is_stable(name):
        warn_if_unstable(name, rate, "the default preset vtol")
    return name


def warn_if_unstable(settings, rate, what: str) -> None:
    """Warn on stderr when ``settings`` (or a preset name), compensated for the log's baro rate, fail Jury's test at
    its nominal period (``rate``: :func:`fusion_altitude.estimators.observer_rate`). The core treats every step its
    gains cannot integrate stably as a gap (it restarts at the baro sample), so the estimate does not diverge but is
    the raw baro on those steps; the warning says so and names the presets that are stable at this rate."""
    if not rate.is_stable(settings):
        advice = (f"presets stable at this rate: {', '.join(rate.stable_presets)}; or fit the gains"
                  if rate.stable_presets else "no preset is stable at this rate: fit the gains")
        print(f"warning: {what} is unstable at this log's rate (nominal period {rate.nominal_period:g} s, baro on 1 of "
              f"{rate.steps_per_baro:.2f} steps: Jury's test at {rate.stability_period:g} s fails): such steps are "
              f"gaps, where the estimate is the raw baro; {advice}",
              file=sys.stderr)
