"""``fusion-altitude report LOG`` and ``fleet report OUT``: the command line of :mod:`fusion_altitude.report`.

:func:`add_report_parser` adds ``report`` to the subcommands of
``fusion-altitude``; :func:`add_fleet_report_parser` adds ``report`` to the
subcommands of ``fleet``. Each sets its own handler. Errors in user input are
the CLI's one-line error (exit status 2); an estimate that cannot be trusted
is refused as ``run`` refuses it (exit status 3).

The log is read and run exactly as ``fusion-altitude run`` does it (the same
reader flags, the same default estimator and observer preset).
"""

from __future__ import annotations

import argparse
import os
import sys
import warnings
from types import SimpleNamespace
from typing import Any, Dict, List

from .choice import default_preset, run_estimator
from .common import CliError, EstimateError, check_output
from .logargs import add_log_arguments, load
from .progress import Progress

__all__ = ["add_report_parser", "add_fleet_report_parser", "run_report", "run_fleet_report", "log_runs"]


def add_report_parser(subcommands: Any) -> argparse.ArgumentParser:
    """Add ``report LOG [-o report.html] [--estimator NAME ... | --all-estimators]`` to ``subcommands``."""
    from ..runner import ESTIMATORS

    report = subcommands.add_parser(
        "report", help="an interactive HTML report of a log (needs the [report] extra)",
        description="Run estimators on a log as `run` does and write one self-contained HTML page: the log's "
                    "sensor health, the settings, the error table, and linked zoomable plots (altitude, vertical "
                    "velocity, accelerometer bias, baro residual) with gaps, timeouts, rejections, rocket phases "
                    "and events marked. Opens offline.")
    report.add_argument("file", help="the log: PX4 .ulg, ArduPilot .bin, AltOS or CATS CSV, or a generic CSV")
    add_log_arguments(report)
    which = report.add_mutually_exclusive_group()
    which.add_argument("--estimator", action="append", default=None, choices=list(ESTIMATORS),
                       help="estimator to show; repeat for several (default: the one `run` picks)")
    which.add_argument("--all-estimators", action="store_true",
                       help="every estimator that applies to the log (as `compare LOG`)")
    report.add_argument("--preset", default=None, choices=("balloon", "fixed_wing", "vtol", "racing", "rocket"),
                        help="observer gains (default: as `run`)")
    report.add_argument("-o", "--output", metavar="OUT.html", default=None,
                        help="the page (default: the log's name with .html, in the current folder)")
    report.set_defaults(handler=run_report)
    return report


def add_fleet_report_parser(fleet_subcommands: Any) -> argparse.ArgumentParser:
    """Add ``report OUT [-o fleet.html] [--no-log-reports]`` to the subcommands of ``fleet``."""
    report = fleet_subcommands.add_parser(
        "report", help="an interactive HTML page of a fleet run, linking each log's report",
        description="Write the fleet summary of a `fleet run` output directory as one self-contained HTML page: "
                    "a sortable, filterable table (status, error, rates, gaps, RMS) and distributions. Each log's "
                    "own report is written to OUT/reports/<log_id>.html and linked from its row.")
    report.add_argument("output_dir", metavar="OUT/", help="output directory of `fleet run`")
    report.add_argument("-o", "--output", metavar="FLEET.html", default=None,
                        help="the page (default OUT/fleet.html)")
    report.add_argument("--no-log-reports", action="store_true",
                        help="do not write the per-log reports (rows link to those already in OUT/reports/)")
    report.set_defaults(handler=run_fleet_report)
    return report


def _default_output(path: str) -> str:
    return os.path.splitext(os.path.basename(path))[0] + ".html"


def log_runs(data, estimators: List[str], preset=None, agl: bool = False) -> Dict[str, Any]:
    """Run each of ``estimators`` on ``data`` as ``run`` does: {"runs": [LogRun], "settings": {name: text},
    "refused": [(name, reason)]}. An estimate :func:`fusion_altitude.health.check_estimate` refuses is left out."""
    from .. import runner
    from .._core._observer import AltitudeSettings
    from ..health import check_estimate

    runs, settings, refused = [], {}, []
    for name in estimators:
        observer_settings = None
        if name == "observer":
            observer_settings = AltitudeSettings.preset(preset)
            settings[name] = f"preset {preset}: {observer_settings}"
        try:
            run = runner.run_log(data, observer_settings, estimator=name, agl=agl)
        except ValueError as error:
            refused.append((name, str(error)))
            continue
        problem = check_estimate(run, run.estimate.altitude, run.estimate.vertical_velocity)
        if problem is not None:
            refused.append((name, str(problem)))
            continue
        runs.append(run)
    return {"runs": runs, "settings": settings, "refused": refused}


def run_report(args: argparse.Namespace) -> int:
    """Handler of ``fusion-altitude report``."""
    from .. import runner
    from ..health import sensor_health
    from ..report import log_report, report_title, save

    output = args.output or _default_output(args.file)
    check_output(output, "-o", [args.file], extensions=(".html", ".htm"))
    try:
        import bokeh  # noqa: F401
    except ImportError:
        raise CliError("report needs bokeh: pip install 'fusion-altitude[report]'") from None
    progress = Progress()
    data = load(args, progress)
    health = sensor_health(data)
    if args.all_estimators:
        estimators = runner.applicable_estimators(data)
    elif args.estimator:
        estimators = list(dict.fromkeys(args.estimator))
        for name in estimators:
            missing = runner.missing_inputs(data, name)
            if missing:
                raise CliError(f"--estimator {name} needs raw {' and '.join(missing)} in the log; {data.source} "
                                   f"has no {' or '.join(missing)}")
    else:  # the estimator `run` picks, by `run`'s own rule
        choice = SimpleNamespace(estimator=None, rocket=False, preset=args.preset, events_csv=None, long_axis=None)
        estimators = [run_estimator(choice, data, health)]
    if args.preset is not None and "observer" not in estimators:
        raise CliError("--preset names observer gains; add --estimator observer")
    preset = args.preset
    if "observer" in estimators and preset is None:
        preset = default_preset(runner.observer_rate(data))
    with progress.stage("estimating"):
        result = log_runs(data, estimators, preset, agl=args.agl)
    for name, reason in result["refused"]:
        print(f"warning: estimator {name} left out of the report: {reason}", file=sys.stderr)
    if not result["runs"]:
        raise EstimateError(f"{data.source}: no estimate can be trusted ("
                                + "; ".join(f"{n}: {r}" for n, r in result["refused"]) + "): no report written")
    with progress.stage("writing"):
        layout = log_report(result["runs"], settings=result["settings"])
        size = save(layout, output, title=report_title(result["runs"][0]))
    print(f"report written to {output} ({size / 1e6:.2f} MB; estimators: "
          f"{', '.join(r.estimator for r in result['runs'])})")
    return 0


def _fleet_log_report(row: Dict[str, Any], path: str) -> str:
    """Write one fleet log's report to ``path`` (its log read and run again, as ``fleet run`` did); '' when
    written, else the one-line reason."""
    from .. import fleet, runner
    from ..health import check_estimate
    from ..report import log_report, report_title, save

    try:
        with warnings.catch_warnings():  # the reader's warnings are in data.warnings, shown in the report
            warnings.simplefilter("ignore")
            data = fleet.read_log(row["path"])
        settings = fleet.resolve_settings(row["estimator"], None)
        run = runner.run_log(data, estimator=row["estimator"], settings=settings)
        problem = check_estimate(run, run.estimate.altitude, run.estimate.vertical_velocity)
        if problem is not None:
            return str(problem)
        described = f"{settings} (fleet run's default)" if settings is not None else "defaults (fleet run's)"
        save(log_report(run, settings={row["estimator"]: described}), path, title=report_title(run))
    except (ValueError, OSError) as error:
        return " ".join(str(error).split())
    return ""


def run_fleet_report(args: argparse.Namespace) -> int:
    """Handler of ``fusion-altitude fleet report``."""
    from ..report import fleet_report, save

    if not os.path.isdir(args.output_dir):
        raise CliError(f"OUT/ {args.output_dir}: no such directory")
    output = args.output or os.path.join(args.output_dir, "fleet.html")
    check_output(output, "-o", extensions=(".html", ".htm"))
    try:
        import bokeh  # noqa: F401
    except ImportError:
        raise CliError("fleet report needs bokeh: pip install 'fusion-altitude[report]'") from None
    from .. import fleet

    try:
        table = fleet.summary(args.output_dir)
    except ValueError as error:
        raise CliError(str(error)) from None
    rows = table.to_pylist()
    reports = os.path.join(args.output_dir, "reports")
    links = {}
    for row in rows:
        if row["status"] != "ok":
            continue
        path = os.path.join(reports, f"{row['log_id']}.html")
        if not args.no_log_reports:
            os.makedirs(reports, exist_ok=True)
            reason = _fleet_log_report(row, path)
            if reason:
                print(f"warning: {row['log_id']}: no report: {reason}", file=sys.stderr)
                continue
        if os.path.exists(path):
            links[row["log_id"]] = os.path.relpath(path, os.path.dirname(os.path.abspath(output))).replace(os.sep, "/")
    size = save(fleet_report(rows, links=links, title=f"Fleet {args.output_dir}"), output,
                title=f"{args.output_dir} — fusion-altitude fleet report")
    print(f"fleet report written to {output} ({size / 1e6:.2f} MB; {len(links)} of {len(rows)} logs linked to "
          f"their reports in {reports})")
    return 0
