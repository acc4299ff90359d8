"""Command line ``fusion-altitude``: a thin layer over the library.

Subcommands
-----------
demo
    Simulate a scenario (:mod:`fusion_altitude.scenarios`), print an error
    table, optionally plot it or export the simulated log as a CSV that
    ``run`` reads.
tune
    Gains, poles, settling times, stability checks and noise bandwidth for a
    bandwidth choice (:func:`fusion_altitude.tuning.report`).
run
    Run any estimator of :data:`fusion_altitude.runner.ESTIMATORS` on a
    recorded log (:mod:`fusion_altitude.logs`), compare it with the log's own
    estimate, write the estimates (full precision) and a plot.
fit
    Fit the observer's gains to a reference (a log's own estimate or a
    scenario's truth), optionally holding out the end of the log
    (:mod:`fusion_altitude.tuning`).
compare
    Every estimator on the simulator's scenarios, or on one recorded log
    against its own estimate: one table (:mod:`fusion_altitude.comparison`).

Errors in user input are printed as one line on stderr with exit status 2,
never as a traceback or a Python warning; output paths are checked before any
work and written atomically with the mode ``open()`` would give them; SIGTERM
(status 143) and Ctrl-C (130) remove a partly written output; ``… | head``
ends quietly.

Modules
-------
One module per subcommand (``demo``, ``tune``, ``run``, ``fit``,
``compare``, ``fleet``, ``report``), each with its parser and handler; they
import the shared modules and never each other nor this package:
``common`` (limits, errors, checks, the table), ``progress`` (stage times and
bars on stderr), ``logargs`` (the log options and reading a log with them)
and ``choice`` (the estimator and preset ``run`` and ``report`` use). This
package keeps :func:`build_parser` and :func:`main`.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
from typing import Iterator, List, Optional

from .._version import __version__
from . import compare, demo, fit, progress, run, tune
from .common import CliError, EstimateError, format_table  # noqa: F401 (EstimateError: re-exported)
from .fleet import add_fleet_parser
from .report import add_fleet_report_parser, add_report_parser

__all__ = ["main", "build_parser", "format_table", "CliError"]

#: A stage that takes at least this long prints its time on stderr, s (read by :func:`main` before each command).
STAGE_REPORT_SECONDS = progress.STAGE_REPORT_SECONDS


def build_parser() -> argparse.ArgumentParser:
    """The argparse parser of ``fusion-altitude``."""
    parser = argparse.ArgumentParser(
        prog="fusion-altitude",
        description="Altitude and vertical-velocity estimation: barometer + accelerometer fusion.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    for subcommand in (demo, tune, run, fit, compare):
        subcommand.add_parser(commands)
    add_fleet_parser(commands, more=(add_fleet_report_parser,))
    add_report_parser(commands)
    return parser


def _quiet_broken_pipe() -> int:
    """stdout's reader went away (``… | head``): stop quietly, as Unix tools do (status 141 = SIGPIPE)."""
    with contextlib.suppress(OSError, ValueError):
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    return 141


class _Terminated(BaseException):
    """SIGTERM arrived: unwind (removing temporary output files) and exit with status 143."""


def _raise_terminated(signum, frame) -> None:
    raise _Terminated()


@contextlib.contextmanager
def _sigterm_unwinds() -> Iterator[None]:
    """While the command runs, SIGTERM raises :class:`_Terminated` so that ``finally`` blocks and
    :func:`fusion_altitude.runner.atomic_output` clean up (the default action would kill the process on the
    spot and leave a ``.part`` file behind). Outside the main thread signals cannot be caught: no change."""
    import signal

    try:
        previous = signal.signal(signal.SIGTERM, _raise_terminated)
    except ValueError:  # not the main thread
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def main(argv: Optional[List[str]] = None) -> int:
    """Entry point of ``fusion-altitude`` and ``python -m fusion_altitude``; returns the exit status.

    Input problems (bad flags, unreadable or inconsistent files, unwritable
    outputs, missing optional extras) print one line on stderr and return 2.
    Ctrl-C returns 130 and SIGTERM 143 (128 + the signal number), after
    removing any partly written output.
    """
    try:
        with _sigterm_unwinds():
            return _main(argv)
    except _Terminated:
        with contextlib.suppress(OSError, ValueError):
            print("terminated", file=sys.stderr)
        return 143


def _main(argv: Optional[List[str]]) -> int:
    progress.STAGE_REPORT_SECONDS = STAGE_REPORT_SECONDS  # the package's knob (tests and benchmarks set it)
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if getattr(args, "handler", None) is None:
            parser.print_help()
            return 2
        status = 2
        try:
            status = int(args.handler(args) or 0)
            sys.stdout.flush()
            return status
        except CliError as error:
            message, status = str(error), error.status
        except ImportError as error:
            message = str(error)
        except ValueError as error:  # LogError and the library's argument checks
            message = str(error)
        except OSError as error:
            if isinstance(error, BrokenPipeError):
                raise
            message = f"{error.filename}: {error.strerror}" if error.filename else str(error)
        print(f"fusion-altitude {args.command}: error: {message}", file=sys.stderr)
        return status
    except BrokenPipeError:
        return _quiet_broken_pipe()
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
