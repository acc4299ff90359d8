"""``fusion-altitude demo``: simulate a scenario (:mod:`fusion_altitude.sim.scenarios`), print an error table,
optionally plot it or export the simulated log as a CSV that ``run`` reads."""

from __future__ import annotations

import argparse

from .common import CliError, check_attitude, check_output, check_plot, format_table, same_file_name

__all__ = ["add_parser"]


def add_parser(commands) -> None:
    """The ``demo`` subcommand: simulate a scenario and print the error table."""
    from ..sim.scenarios import scenario_names

    demo = commands.add_parser("demo", help="simulate a flight and print the error table",
                               description="Simulate a scenario, run the observer, print raw-baro vs fused errors.")
    demo.add_argument("--scenario", default="realistic", choices=scenario_names(),
                      help="scenario to simulate (default: realistic)")
    demo.add_argument("--seed", type=int, default=0, help="random seed, >= 0 (default: 0)")
    demo.add_argument("--attitude", default="auto", choices=("auto", "ahrs", "truth"),
                      help="attitude source: the imufusion AHRS, the truth, or auto (AHRS if installed)")
    demo.add_argument("--plot", metavar="OUT.png", help="write a plot (needs the [plot] extra)")
    demo.add_argument("--export", metavar="OUT.csv",
                      help="write the simulated log as a CSV that `run` reads (time, vertical_acceleration, "
                           "baro_altitude, true_altitude)")
    demo.set_defaults(handler=_cmd_demo)


def _cmd_demo(args: argparse.Namespace) -> int:
    from .._core._common import GRAVITY
    from ..sim.scenarios import PUBLISHED, PUBLISHED_SOURCE, describe, export_csv, run_scenario

    if args.seed < 0:
        raise CliError(f"--seed must be >= 0, got {args.seed}")
    check_attitude(args.attitude)
    check_plot(args.plot)
    check_output(args.export, "--export", extensions=(".csv",))
    if args.export and args.plot and same_file_name(args.export, args.plot):
        raise CliError("--export and --plot name the same file")
    result = run_scenario(args.scenario, seed=args.seed, attitude=args.attitude)
    fused = result.statistics()
    baro = result.baro_statistics()
    print(f"scenario {result.name}, seed {result.seed}: {describe(result.name)}")
    print(f"attitude: {'imufusion AHRS' if result.attitude == 'ahrs' else 'truth (imufusion not installed)' if args.attitude == 'auto' else 'truth'}; "
          f"errors after the first {result.transient:g} s")
    print()
    rows = [
        ["mean error (m)", baro.mean, fused.mean],
        ["RMS error (m)", baro.rms, fused.rms],
        ["max |error| (m)", baro.max, fused.max],
        ["95th pct |error| (m)", baro.p95, fused.p95],
    ]
    published = PUBLISHED.get(result.name, {})
    header = ["", "raw baro", "fused"]
    if published:
        header.append("published")
        for row, key in zip(rows, ("mean", "rms", "max", None)):
            row.append(published.get(key, "") if key else "")
    print(format_table(header, rows))
    print()
    print(f"final accel bias estimate: {result.final_bias:+.4f} m/s² ({result.final_bias / GRAVITY:+.4f} g); "
          f"true vertical bias {result.true_bias:+.4f} m/s² ({result.true_bias / GRAVITY:+.4f} g)")
    if published:
        print()
        print(f"published: {PUBLISHED_SOURCE}")
        print("the raw baro's mean error is its zero-mean noise averaged out; the fused mean carries the small lag "
              "of the bias loop behind the accelerometer bias, so it can exceed the raw baro's while its RMS is "
              "several times smaller")
    if args.export:
        export_csv(result, args.export)
        print(f"simulated log written to {args.export}; run it with:")
        print(f"  fusion-altitude run {args.export} --time time --accel vertical_acceleration --baro baro_altitude "
              "--reference true_altitude")
    if args.plot:
        from ..plotting import plot_scenario

        plot_scenario(result, args.plot)
        print(f"plot written to {args.plot}")
    return 0
