"""``fusion-altitude fit``: fit the observer's gains to a reference (a log's own estimate or a scenario's truth),
optionally holding out the end of the log (:mod:`fusion_altitude.tuning`)."""

from __future__ import annotations

import argparse
import math
import sys
from typing import Optional

from .common import MAX_OMEGA, CliError, EstimateError, check_plot, check_search_flags, format_table
from .logargs import add_log_arguments, load
from .progress import Progress

__all__ = ["add_parser"]


def add_parser(commands) -> None:
    """The ``fit`` subcommand: fit the observer's gains to a reference altitude."""
    from ..sim.scenarios import scenario_names

    fit = commands.add_parser("fit", help="fit the gains to a reference altitude (a log or a scenario)",
                              description="Search omega, zeta, omega_b for the gains whose altitude best matches a "
                                          "reference: a log's reference column or autopilot estimate, or a "
                                          "simulated scenario's truth.")
    fit.add_argument("file", nargs="?", help="CSV (with --reference), PX4 ULog (.ulg) or ArduPilot DataFlash (.bin)")
    add_log_arguments(fit, agl=False)
    fit.add_argument("--scenario", choices=scenario_names(), help="fit on a simulated scenario instead of a log")
    fit.add_argument("--seed", type=int, default=0, help="scenario seed, >= 0 (default: 0)")
    fit.add_argument("--skip", type=float, default=None,
                     help="seconds at the start left out of the metric, >= 0 (default: the scenario's transient, "
                          "5 s for logs)")
    fit.add_argument("--train-until", metavar="T|P%",
                     help="fit on the samples before T s after the start (or P%% of the log) and score fitted vs "
                          "default gains on the rest; the default is kept if the fit does not generalise")
    fit.add_argument("--omega-min", type=float, default=0.05, help="lowest omega searched, rad/s (default 0.05)")
    fit.add_argument("--omega-max", type=float, default=20.0,
                     help=f"highest omega searched, rad/s, <= {MAX_OMEGA:g} (default 20)")
    fit.add_argument("--plot", metavar="OUT.png", help="contour plot of RMS over (omega, omega_b) ([plot] extra)")
    fit.set_defaults(handler=_cmd_fit)


def _cmd_fit(args: argparse.Namespace) -> int:
    import numpy as np

    from .. import tuning

    progress = Progress()
    _check_fit_arguments(args)
    source, time, accel, baro, reference, preset_row, skip = _fit_inputs(args, progress)
    time = np.asarray(time, float)
    split, scored_until = _fit_split(args, time, skip)
    steps = tuning.steps_per_baro(baro)
    result, held_out = _fit(args, time, accel, baro, reference, split, skip, steps, progress)
    if not np.isfinite(result.rms_error):
        raise EstimateError(f"{source}: no candidate gains give a finite RMS against the reference "
                            f"(best: {result.rms_error}): nothing to recommend")
    gaps, baro_rms = _fit_gaps_and_baro_rms(time, baro, reference, skip, scored_until)
    gains = result.settings
    print(f"{source}: {len(time)} samples, metrics after {skip:g} s"
          + (f", trained before {split - time[0]:.2f} s" if split is not None else ""))
    if gaps:
        print(f"{gaps} logging gap(s): the {tuning.GAP_SETTLING:.2f} s after each are left out of every RMS below "
              "(every candidate restarts there)")
    if steps > 1.0:
        print(f"baro on 1 of {steps:.2f} steps: gains compensated for the baro rate, as `run` and `compare` do")
    print(f"best of {len(result.landscape)} stable candidates (checked at the nominal period): "
          f"omega {result.omega:.4g} rad/s, zeta {result.zeta:.3g}, omega_b {result.omega_b:.4g} rad/s")
    print(f"  position_gain {gains.position_gain:.6g} 1/s, velocity_gain {gains.velocity_gain:.6g} 1/s², "
          f"bias_gain {gains.bias_gain:.6g} 1/s³")
    print()
    _print_fit_scores(result, held_out, preset_row, baro_rms, split, steps)
    print()
    print("runners-up:")
    print(format_table(["omega (rad/s)", "zeta", "omega_b (rad/s)", "RMS (m)"], _runners_up(result.landscape)))
    if args.plot:
        from ..plotting import plot_fit_landscape

        with progress.stage("plotting"):
            plot_fit_landscape(result, args.plot, title=source)
        print(f"plot written to {args.plot}")
    return 0


def _check_fit_arguments(args: argparse.Namespace) -> None:
    """CliError for ``fit`` flags out of range or contradicting each other (before any file is read)."""
    if args.scenario is None and args.file is None:
        raise CliError("give a log FILE (with a reference) or --scenario NAME")
    if args.scenario is not None and args.file is not None:
        raise CliError("give a log FILE or --scenario, not both")
    if args.seed < 0:
        raise CliError(f"--seed must be >= 0, got {args.seed}")
    check_search_flags(args)
    check_plot(args.plot, [args.file] if args.file else [])
    _parse_train_until(args.train_until)


def _parse_train_until(text: Optional[str]) -> Optional[tuple]:
    """``--train-until`` checked before any work: ("%", fraction of the log) or ("s", seconds after its start)."""
    if text is None:
        return None
    try:
        if text.endswith("%"):
            fraction = float(text[:-1]) / 100.0
            if not 0 < fraction < 1:  # also false for NaN
                raise CliError(f"--train-until {text}: a percentage must be between 0 and 100 (exclusive)")
            return ("%", fraction)
        seconds = float(text)
    except ValueError:
        raise CliError(f"--train-until must be seconds after the log's start or a percentage like 60%, "
                       f"got {text!r}") from None
    if not (math.isfinite(seconds) and seconds > 0):
        raise CliError(f"--train-until {text}: seconds must be finite and > 0")
    return ("s", seconds)


def _train_until(text: Optional[str], time) -> Optional[float]:
    """``--train-until``: "T" s after the first sample, or "P%" of the log; the absolute time, s."""
    parsed = _parse_train_until(text)
    if parsed is None:
        return None
    start, stop = float(time[0]), float(time[-1])
    kind, value = parsed
    if kind == "%":
        return start + value * (stop - start)
    if not value < stop - start:
        raise CliError(f"--train-until {text}: must be > 0 and < the log's {stop - start:.2f} s")
    return start + value


def _fit_inputs(args: argparse.Namespace, progress: Progress):
    """(source, time s, accel m/s², baro m, reference m, default RMS row or None, skip s) for ``fit``."""
    import numpy as np

    if args.scenario is not None:
        from ..sim.scenarios import run_scenario
        if args.file is not None:
            raise CliError("give a log FILE or --scenario, not both")
        result = run_scenario(args.scenario, args.seed)
        skip = result.transient if args.skip is None else args.skip
        duration = float(result.time[-1] - result.time[0])
        if skip >= duration:
            raise CliError(f"--skip {skip:g} s leaves no sample of scenario {args.scenario}'s {duration:.2f} s")
        from ..metrics import error_statistics

        preset_rms = error_statistics(result.time, result.altitude_error, skip).rms
        return (f"scenario {args.scenario}, seed {args.seed} (reference: simulator truth)", result.time,
                result.vertical_acceleration, result.baro_altitude, result.trajectory.altitude,
                ("scenario preset, as `demo` runs it", preset_rms), skip)
    if args.file is None:
        raise CliError("give a log FILE (with a reference) or --scenario NAME")
    data = load(args, progress)
    if data.reference_altitude is None or not np.isfinite(data.reference_altitude).any():
        raise CliError(f"{data.source} has no reference altitude: give --reference COLUMN (CSV), or a .ulg/.bin "
                       "with the autopilot's own height estimate")
    for warning in getattr(data, "warnings", []):
        print(f"warning: {warning}", file=sys.stderr)
    skip = 5.0 if args.skip is None else args.skip
    return (f"{data.source} (reference: {data.reference_name})", data.time, data.vertical_acceleration,
            data.baro_altitude, data.reference_altitude, None, skip)


def _fit_split(args: argparse.Namespace, time, skip: float):
    """The ``--train-until`` time (s, or None) and the end of the scored part (s); CliError when ``--skip`` (s)
    leaves nothing; a warning on stderr when the scored part is short for the default bias loop."""
    duration = float(time[-1] - time[0])
    if skip >= duration:
        raise CliError(f"--skip {skip:g} s leaves no sample of a {duration:.2f} s log")
    split = _train_until(args.train_until, time)
    scored_until = split if split is not None else float(time[-1])
    scored = scored_until - (time[0] + skip)
    if split is not None and scored <= 0:
        given = "" if args.skip is not None or not args.file else " (the default on a log; give a shorter --skip)"
        raise CliError(f"--train-until {args.train_until} is within the first --skip {skip:g} s{given}: nothing to "
                       "train on")
    slowest = 1.0 / (0.3 * 0.7)  # s: time constant of the default bias loop (ω_b = 0.3 rad/s)
    if scored < 3 * slowest:
        print(f"warning: the fit is scored over only {scored:.1f} s of data, less than 3 time constants of the "
              f"default bias loop ({3 * slowest:.0f} s): the fitted gains may not generalise", file=sys.stderr)
    return split, scored_until


def _fit(args: argparse.Namespace, time, accel, baro, reference, split, skip: float, steps: float, progress):
    """The fit over the whole log (after ``skip`` s) or, with a ``split`` time (s), on the part before it scored
    on the rest: (fit result, held-out result or None). The library's ValueError → CliError naming our flags."""
    from .. import tuning

    options = dict(omega_range=(args.omega_min, args.omega_max), steps_per_baro=steps)
    held_out = None
    with progress.stage("fitting") as bar:
        try:
            if split is None:
                dt_values = _sample_periods(time)
                mask = tuning.training_mask(time, skip)  # as metrics.error_statistics counts "after the transient"
                result = tuning.fit(accel, baro, dt_values, reference, mask=mask, progress=bar, **options)
            else:
                held_out = tuning.fit_held_out(time, accel, baro, reference, split, skip=skip, progress=bar, **options)
                result = held_out.fit
        except ValueError as error:  # the library's keyword → our flags
            raise CliError(str(error).replace("omega_range", "--omega-min/--omega-max")) from None
    return result, held_out


def _fit_gaps_and_baro_rms(time, baro, reference, skip: float, scored_until: float):
    """The number of logging gaps, and the raw baro's RMS error (m) against the reference over the scored part
    (after ``skip`` s, before ``scored_until`` s, without the gaps' transients)."""
    import numpy as np

    from .. import metrics, tuning

    counted = tuning.without_gap_transients(_sample_periods(time), (time > time[0] + skip) & (time < scored_until))
    gaps = int(np.count_nonzero(_sample_periods(time) > tuning.gap_period_for(_sample_periods(time))))
    baro_rms = metrics.error_statistics(time[counted], (baro - reference)[counted], 0.0).rms \
        if np.isfinite((baro - reference)[counted]).any() else math.nan
    return gaps, baro_rms


def _improvement(fitted: float, other: float) -> str:
    """How much lower ``fitted`` is than ``other`` (RMS, m), in %; "" when ``other`` is no score."""
    return f"{100 * (1 - fitted / other):+.0f}%" if other > 0 and math.isfinite(other) else ""


def _print_fit_scores(result, held_out, preset_row, baro_rms: float, split, steps: float) -> None:
    """The RMS table (m) of the fitted, default and preset gains and the raw baro; the held-out table."""
    rows = [["fitted gains", result.rms_error, ""],
            ["VTOL default gains", result.default_rms_error, _improvement(result.rms_error, result.default_rms_error)]]
    if preset_row is not None:
        rows.append([preset_row[0], preset_row[1], _improvement(result.rms_error, preset_row[1])])
    rows.append(["raw baro", baro_rms, ""])
    title = "training part: altitude − reference" if split is not None else "altitude − reference"
    print(format_table([title, "RMS (m)", "fit improves by"], rows))
    if not math.isfinite(result.default_rms_error):
        print(f"(the VTOL default gains diverge with the baro on 1 of {steps:.2f} steps: no score)")
    if held_out is not None:
        print()
        print(format_table(["held-out part (after the split)", "RMS (m)", "fit improves by"],
                           [["fitted gains", held_out.fitted_rms_error, ""],
                            ["VTOL default gains", held_out.default_rms_error,
                             _improvement(held_out.fitted_rms_error, held_out.default_rms_error)]]))
        if held_out.generalises:
            print("the fitted gains generalise: use them")
        else:
            print("the fitted gains do worse than the default on the held-out part: keep the default "
                  f"(position_gain {held_out.settings.position_gain:g}, velocity_gain "
                  f"{held_out.settings.velocity_gain:g}, bias_gain {held_out.settings.bias_gain:g})")


def _runners_up(landscape, count: int = 5) -> list:
    """The ``count`` best candidates after the winner as printed rows (4 significant digits), without rows
    that print the same as the winner or as a better one (the refinement revisits nearly equal candidates)."""
    seen = set()
    rows = []
    for k, row in enumerate(landscape):
        cells = tuple(f"{float(row[name]):.4g}" for name in ("omega", "zeta", "omega_b"))
        if cells in seen:
            continue
        seen.add(cells)
        if k > 0:
            rows.append(list(cells) + [float(row["rms_error"])])
            if len(rows) == count:
                break
    return rows


def _sample_periods(time):
    from ..runner import sample_periods

    return sample_periods(time)
