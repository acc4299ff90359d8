"""Command line ``fusion-altitude``: a thin layer over the library.

Subcommands
-----------
demo
    Simulate a scenario (:mod:`fusion_altitude.scenarios`), print an error
    table and optionally plot it.
tune
    Gains, poles, settling times, stability checks and noise bandwidth for a
    bandwidth choice (:mod:`fusion_altitude.tuning`-style report built from
    :mod:`fusion_altitude.metrics`).
run
    Run the observer on a recorded log: CSV, PX4 ULog or ArduPilot DataFlash
    (:mod:`fusion_altitude.logs`).

Errors in user input are printed as one line on stderr with exit status 2,
never as a traceback.
"""

from __future__ import annotations

import argparse
import sys
from typing import List, Optional, Sequence

from ._version import __version__

__all__ = ["main", "build_parser", "format_table"]


class CliError(Exception):
    """An input problem to report to the user in one line (exit status 2)."""


def format_table(header: Sequence[str], rows: Sequence[Sequence[object]]) -> str:
    """Plain-text table: the first column left-aligned, the others right-aligned.

    Floats are printed with 4 significant decimals; other values with ``str``.
    """
    def cell(value: object) -> str:
        if isinstance(value, float):
            return f"{value:.4f}"
        return str(value)

    text = [[cell(v) for v in row] for row in [list(header)] + [list(r) for r in rows]]
    widths = [max(len(row[i]) for row in text) for i in range(len(header))]
    lines = []
    for k, row in enumerate(text):
        parts = [row[0].ljust(widths[0])] + [row[i].rjust(widths[i]) for i in range(1, len(row))]
        lines.append("  ".join(parts).rstrip())
        if k == 0:
            lines.append("  ".join("-" * w for w in widths))
    return "\n".join(lines)


# ----------------------------------------------------------------------------
# demo


def _cmd_demo(args: argparse.Namespace) -> int:
    from ._common import GRAVITY
    from .scenarios import PUBLISHED, describe, run_scenario

    result = run_scenario(args.scenario, seed=args.seed, attitude=args.attitude)
    fused = result.statistics()
    baro = result.baro_statistics()
    print(f"scenario {result.name}, seed {result.seed}: {describe(result.name)}")
    print(f"attitude: {'imufusion AHRS' if result.attitude == 'ahrs' else 'truth (imufusion not installed)'}; "
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
    if args.plot:
        from .plotting import plot_scenario

        plot_scenario(result, args.plot)
        print(f"plot written to {args.plot}")
    return 0


# ----------------------------------------------------------------------------
# parser


def build_parser() -> argparse.ArgumentParser:
    """The argparse parser of ``fusion-altitude``."""
    from .scenarios import scenario_names

    parser = argparse.ArgumentParser(
        prog="fusion-altitude",
        description="Altitude and vertical-velocity estimation: barometer + accelerometer fusion.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")

    demo = commands.add_parser("demo", help="simulate a flight and print the error table",
                               description="Simulate a scenario, run the observer, print raw-baro vs fused errors.")
    demo.add_argument("--scenario", default="realistic", choices=scenario_names(),
                      help="scenario to simulate (default: realistic)")
    demo.add_argument("--seed", type=int, default=0, help="random seed (default: 0)")
    demo.add_argument("--attitude", default="auto", choices=("auto", "ahrs", "truth"),
                      help="attitude source: the imufusion AHRS, the truth, or auto (AHRS if installed)")
    demo.add_argument("--plot", metavar="OUT.png", help="write a plot (needs the [plot] extra)")
    demo.set_defaults(handler=_cmd_demo)
    return parser


def main(argv: Optional[List[str]] = None) -> int:
    """Entry point of ``fusion-altitude`` and ``python -m fusion_altitude``; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if getattr(args, "handler", None) is None:
        parser.print_help()
        return 2
    try:
        return int(args.handler(args) or 0)
    except CliError as error:
        print(f"fusion-altitude {args.command}: error: {error}", file=sys.stderr)
        return 2
    except ImportError as error:
        print(f"fusion-altitude {args.command}: error: {error}", file=sys.stderr)
        return 2
