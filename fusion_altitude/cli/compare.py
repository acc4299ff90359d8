"""``fusion-altitude compare``: every estimator on the simulator's scenarios, or on one recorded log against its
own estimate: one table (:mod:`fusion_altitude.comparison`)."""

from __future__ import annotations

import argparse
import sys

from .common import CliError, EstimateError, check_attitude, check_plot, format_table, number
from .logargs import add_log_arguments, load, print_log_summary
from .progress import Progress

__all__ = ["add_parser"]


def add_parser(commands) -> None:
    """The ``compare`` subcommand: every estimator on the simulator's scenarios or on one log."""
    from ..comparison import SCENARIOS
    from ..sim.scenarios import scenario_names

    comparison = commands.add_parser(
        "compare", help="every estimator on the simulator's scenarios, or on one log: one table",
        description="Without FILE: observer (preset and fitted gains), Kalman filter, two-stage complementary "
                    "filter, quality-weighted alpha-beta fusion, inertial filter (INS, from the simulated raw IMU), "
                    "the rocket estimator (rocket scenario) and raw baro on the same simulated data: altitude "
                    "RMS and max error, velocity RMS, recovery time after a sensor fault, C batch ns/sample. "
                    "With a log FILE: every estimator of `run --estimator` against the log's own estimate.")
    comparison.add_argument("file", nargs="?", help="a recorded log with its own estimate (as for `run`)")
    add_log_arguments(comparison)
    comparison.add_argument("--skip", type=float, default=None,
                            help="log: seconds at the start left out of the metrics (default 0)")
    comparison.add_argument("--scenario", action="append", choices=scenario_names(), metavar="NAME",
                            help=f"scenario (repeatable; default: {', '.join(SCENARIOS)})")
    comparison.add_argument("--seed", type=int, default=0, help="simulation seed (default: 0)")
    comparison.add_argument("--fit-seed", type=int, default=1,
                            help="seed the fitted observer's gains are fitted on (default: 1, held out)")
    comparison.add_argument("--attitude", default="truth", choices=("truth", "ahrs"),
                            help="attitude source (default truth: the same numbers with or without imufusion)")
    comparison.add_argument("--repeat", type=int, default=5,
                            help="timing repeats, best taken (default 5; 0: no timing)")
    comparison.add_argument("--markdown", action="store_true", help="print a Markdown table")
    comparison.add_argument("--plot", metavar="OUT.png", help="overlay the estimators ([plot] extra)")
    comparison.add_argument("--plot-scenario", choices=scenario_names(), metavar="NAME",
                            help="scenario of the plot (default: the first one compared)")
    comparison.set_defaults(handler=_cmd_compare)


def _cmd_compare(args: argparse.Namespace) -> int:
    from .. import comparison

    if args.repeat < 0:
        raise CliError(f"--repeat must be >= 0 (0: no timing), got {args.repeat}")
    if args.seed < 0 or args.fit_seed < 0:
        raise CliError(f"--seed and --fit-seed must be >= 0, got {args.seed} and {args.fit_seed}")
    check_attitude(args.attitude)
    check_plot(args.plot, [args.file] if args.file else [])
    if args.file is not None:
        return _compare_log(args)
    scenarios = args.scenario or list(comparison.SCENARIOS)
    with Progress().stage("comparing") as bar:
        rows = comparison.compare(scenarios, seed=args.seed, fit_seed=args.fit_seed, attitude=args.attitude,
                                  repeat=args.repeat, progress=bar)
    print(f"seed {args.seed} (observer (fit): gains fitted on seed {args.fit_seed}), attitude {args.attitude}; "
          "errors after each scenario's transient; recovery: s after the fault ends until |error| <= 0.5 m")
    print()
    _print_rows(args, rows)
    if args.plot:
        comparison.plot_comparison(args.plot_scenario or scenarios[0], args.plot, seed=args.seed,
                                   fit_seed=args.fit_seed, attitude=args.attitude)
        print(f"plot written to {args.plot}")
    return _refused_rows(rows)


def _print_rows(args: argparse.Namespace, rows) -> None:
    from .. import comparison

    if args.markdown:
        print(comparison.format_markdown(rows))
    else:
        print(format_table(comparison.header(rows), comparison.table_cells(rows)))


def _refused_rows(rows) -> int:
    """One line on stderr per row whose estimate was refused (its cells are blank); exit status 3 if any, else 0."""
    refused = [row for row in rows if getattr(row, "problem", None)]
    for row in refused:
        print(f"error: {row.scenario}: estimator {row.estimator}: {row.problem}: its row is left blank",
              file=sys.stderr)
    return EstimateError.status if refused else 0


def _compare_log(args: argparse.Namespace) -> int:
    from .. import comparison

    if args.scenario or args.plot_scenario:
        raise CliError("--scenario and --plot-scenario apply to simulated comparisons, not to a log FILE")
    number("--skip", args.skip, 0.0, strict=False)
    progress = Progress()
    data = load(args, progress)
    with progress.stage("comparing") as bar:
        try:
            rows = comparison.compare_log(data, repeat=args.repeat, skip=args.skip or 0.0, agl=args.agl,
                                          progress=bar)
        except ValueError as error:
            raise CliError(str(error)) from None
    print_log_summary(data, "every estimator against the log's own estimate")
    print(f"reference: {data.reference_name}; errors after {args.skip or 0.0:g} s"
          + ("; heights above the start" if args.agl else "") + "; velocity against the log's own vertical velocity")
    print()
    _print_rows(args, rows)
    if args.plot:
        with progress.stage("plotting"):
            comparison.plot_log_comparison(data, rows, args.plot, agl=args.agl)
        print(f"plot written to {args.plot}")
    return _refused_rows(rows)
