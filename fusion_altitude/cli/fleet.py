"""``fusion-altitude fleet run|fit|summary``: the command line of :mod:`fusion_altitude.fleet`.

:func:`add_fleet_parser` adds the ``fleet`` command to the subparsers of
``fusion-altitude``; its handler is :func:`run_fleet_command`. Errors in user
input are raised as the CLI's one-line error (exit status 2).
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from typing import Any, Callable, Dict, List, Optional, Sequence

__all__ = ["add_fleet_parser", "run_fleet_command"]

_SUMMARY_COLUMNS = ("log_id", "status", "samples", "duration_s", "baro_rate_hz", "imu_gaps", "rms_error_m",
                    "final_accel_bias_m_s2")


def _cli_error(message: str) -> Exception:
    from .common import CliError
    return CliError(message)


def _format_table(header, rows) -> str:
    from .common import format_table
    return format_table(header, rows)


def _add_cluster_arguments(parser: argparse.ArgumentParser) -> None:
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--workers", type=int, default=None,
                       help="worker processes of the local Dask cluster (default: one per core)")
    group.add_argument("--scheduler", metavar="ADDR",
                       help="run on an existing Dask cluster, e.g. tcp://HOST:8786 (outputs must be on storage "
                            "every worker sees)")


def _add_csv_arguments(parser: argparse.ArgumentParser, reference: bool = False) -> None:
    parser.add_argument("--time", help="CSV logs: time column, s")
    parser.add_argument("--accel", help="CSV logs: vertical acceleration column (earth frame, +up, gravity removed)")
    parser.add_argument("--accel-units", default="m/s^2", choices=("m/s^2", "g"), help="CSV logs: units of --accel")
    parser.add_argument("--baro", help="CSV logs: baro altitude column, m")
    parser.add_argument("--pressure", help="CSV logs: static pressure column, Pa (instead of --baro)")
    parser.add_argument("--sea-level-pa", type=float, default=None,
                        help="CSV logs: reference pressure for --pressure, Pa (default 101325)")
    if reference:
        parser.add_argument("--reference", help="CSV logs: reference altitude column, m")


def add_fleet_parser(subparsers: Any, more: Sequence[Callable[[Any], Any]] = ()) -> argparse.ArgumentParser:
    """Add ``fleet`` (with ``run``, ``fit``, ``summary``, then each of ``more``, called with the subparsers of
    ``fleet``) to the subparsers of ``fusion-altitude``."""
    fleet = subparsers.add_parser(
        "fleet", help="run, summarise or fit over many logs on Dask (needs the [fleet] extra)",
        description="Fleet processing on dask.distributed: a batch of logs per task, on a local cluster sized to this "
                    "machine or on an existing cluster (--scheduler).")
    commands = fleet.add_subparsers(dest="fleet_command", metavar="SUBCOMMAND")
    fleet.set_defaults(handler=run_fleet_command, fleet_parser=fleet)

    run = commands.add_parser("run", help="run an estimator on every log; Parquet outputs and a summary table",
                              description="Run an estimator on every log (files, directories, globs, fsspec URLs). "
                                          "Writes OUT/logs/<id>.parquet per log and OUT/summary.{parquet,csv}; a "
                                          "second run with the same settings skips logs already done.")
    run.add_argument("paths", nargs="+", metavar="DIR_OR_GLOB", help="logs: files, directories, globs or URLs")
    run.add_argument("-o", "--output", required=True, metavar="OUT/", help="output directory (or fsspec URL)")
    run.add_argument("--estimator", default="observer", help="estimator (default observer)")
    from .._core._observer_glue import PRESET_OMEGA

    run.add_argument("--preset", default=None, choices=tuple(PRESET_OMEGA),
                     help="observer gains, as `run --preset` (default vtol)")
    run.add_argument("--csv", action="store_true", help="also write each log's `run -o` CSV to OUT/csv/")
    run.add_argument("--retry-failed", action="store_true", help="recompute logs that failed before")
    run.add_argument("--worst", type=int, default=10, help="worst logs to print (default 10)")
    _add_csv_arguments(run)
    _add_cluster_arguments(run)

    fit = commands.add_parser("fit", help="one set of observer gains for many logs, scored on held-out logs",
                              description="Fit observer gains to the logs' reference altitudes (autopilot "
                                          "estimate, or a CSV --reference column): per-log sweeps on the workers, "
                                          "pooled RMS on the client, refined.")
    fit.add_argument("paths", nargs="+", metavar="DIR_OR_GLOB", help="training logs")
    fit.add_argument("--holdout", nargs="+", metavar="DIR_OR_GLOB", help="held-out logs to score the fit on")
    fit.add_argument("--holdout-every", type=int, default=None, metavar="N",
                     help="hold out every N-th log of the training set (in path order) instead")
    fit.add_argument("--skip", type=float, default=5.0, help="seconds at each log's start left out (default 5)")
    fit.add_argument("--omega-min", type=float, default=0.05, help="lowest omega searched, rad/s (default 0.05)")
    fit.add_argument("--omega-max", type=float, default=20.0, help="highest omega searched, rad/s (default 20)")
    fit.add_argument("-o", "--output", metavar="FIT.json", help="write the result as JSON")
    _add_csv_arguments(fit, reference=True)
    _add_cluster_arguments(fit)

    summary = commands.add_parser("summary", help="print the summary table of an output directory",
                                  description="Print the summary table of a `fleet run` output directory and "
                                              "its worst logs (failed first, then by RMS error).")
    summary.add_argument("output", metavar="OUT/", help="output directory of `fleet run`")
    summary.add_argument("--worst", type=int, default=10, help="worst logs to print (default 10)")
    summary.add_argument("--all", action="store_true", help="print every log, not only the worst")
    for add_more in more:  # e.g. `fleet report` (cli/report.py), handed in by cli/__init__.py
        add_more(commands)
    return fleet


def _csv_options(args: argparse.Namespace) -> Dict[str, Any]:
    options: Dict[str, Any] = {}
    if args.time is None and args.accel is None and args.baro is None and args.pressure is None:
        return options
    missing = [flag for flag, value in (("--time", args.time), ("--accel", args.accel)) if value is None]
    if args.baro is None and args.pressure is None:
        missing.append("--baro or --pressure")
    if missing:
        raise _cli_error(f"CSV logs need {', '.join(missing)}")
    if args.baro is not None and args.pressure is not None:
        raise _cli_error("give --baro or --pressure, not both")
    options = dict(time_column=args.time, accel_column=args.accel, accel_units=args.accel_units)
    options["baro_column" if args.baro is not None else "pressure_column"] = args.baro or args.pressure
    if args.sea_level_pa is not None:
        options["sea_level_pa"] = args.sea_level_pa
    if getattr(args, "reference", None) is not None:
        options["reference_column"] = args.reference
    return options


#: Python names in the library's messages → the command line's names for them.
_FLAG_NAMES = (("paths_or_globs", "DIR_OR_GLOB"), ("output_dir", "OUT/"), ("omega_range", "--omega-min/--omega-max"),
               ("time_column", "--time"), ("accel_column", "--accel"), ("accel_units", "--accel-units"),
               ("baro_column", "--baro"), ("pressure_column", "--pressure"), ("sea_level_pa", "--sea-level-pa"),
               ("reference_column", "--reference"))
#: Names that are ordinary words too: replaced only where they open the message.
_LEADING_NAMES = (("holdout:", "--holdout:"), ("skip ", "--skip "), ("workers ", "--workers "),
                  ("estimator ", "--estimator "), ("settings:", "--preset:"))


def _flag_message(error: object) -> str:
    """The library's message with the command line's flag names instead of its keyword names."""
    import re

    message = str(error)
    for name, flag in _FLAG_NAMES:
        message = re.sub(rf"\b{name}\b", flag, message)
    for name, flag in _LEADING_NAMES:
        if message.startswith(name):
            message = flag + message[len(name):]
    return message


def _check_inputs(flag: str, paths: List[str]) -> List[str]:
    """Before any cluster starts: every local path exists and every glob or directory holds logs; the expanded
    list of logs. URLs are left to the workers."""
    from .. import fleet

    for item in paths:
        if "://" in item or any(ch in item for ch in "*?["):
            continue
        if not os.path.exists(item):
            raise _cli_error(f"{flag} {item}: no such file or directory")
    try:
        return fleet.expand_paths(paths)
    except (ValueError, TypeError) as error:
        raise _cli_error(_flag_message(error).replace("DIR_OR_GLOB", flag, 1)) from None


def _check_numbers(args: argparse.Namespace) -> None:
    from .common import number as _number

    _number("--sea-level-pa", args.sea_level_pa, 0.0)
    if getattr(args, "worst", 0) < 0:
        raise _cli_error(f"--worst must be >= 0, got {args.worst}")


def _cell(value: Any) -> Any:
    if value is None:
        return ""
    if isinstance(value, float) and not math.isfinite(value):
        return "—"  # no figure (e.g. no reference in the log), never a printed nan
    return value


def _print_rows(rows: List[Dict[str, Any]]) -> None:
    print(_format_table(list(_SUMMARY_COLUMNS), [[_cell(row.get(name)) for name in _SUMMARY_COLUMNS]
                                                for row in rows]))
    for row in rows:
        if row["status"] != "ok":
            print(f"  {row['log_id']}: {_flag_message(row['error'])}")


def _print_summary(table, worst: int, everything: bool = False) -> None:
    from .. import fleet

    rows = table.to_pylist()
    ok = [row for row in rows if row["status"] == "ok"]
    samples = sum(row["samples"] or 0 for row in ok)
    hours = sum(row["duration_s"] or 0.0 for row in ok) / 3600
    print(f"{len(rows)} logs: {len(ok)} ok, {len(rows) - len(ok)} failed; {samples} samples, {hours:.2f} h of flight")
    rms = [row["rms_error_m"] for row in ok if row["rms_error_m"] is not None and math.isfinite(row["rms_error_m"])]
    if rms:
        print(f"RMS altitude − own estimate over {len(rms)} logs with one: median {sorted(rms)[len(rms) // 2]:.4f} m, "
              f"worst {max(rms):.4f} m")
    if everything:
        print()
        _print_rows(rows)
    if worst > 0:
        print()
        print(f"worst {min(worst, len(rows))} (failed first, then by RMS error against the log's own estimate):")
        _print_rows(fleet.worst_logs(table, worst))


def _client_argument(args: argparse.Namespace) -> Optional[str]:
    if args.workers is not None and args.workers < 1:
        raise _cli_error(f"--workers must be >= 1, got {args.workers}")
    return args.scheduler


def _check_output_directory(path: str) -> None:
    """``fleet run -o``: a local output that exists must be a directory (it is created otherwise)."""
    if not path:
        raise _cli_error("-o needs a directory name, got ''")
    if "://" not in path and os.path.exists(path) and not os.path.isdir(path):
        raise _cli_error(f"-o {path} is a file, not a directory")


def _cmd_run(args: argparse.Namespace) -> int:
    from .. import fleet

    fleet.require_fleet_packages()
    _check_numbers(args)
    csv_options = _csv_options(args)
    _client_argument(args)
    _check_output_directory(args.output)
    try:
        fleet.resolve_settings(args.estimator, args.preset)
    except (ValueError, TypeError) as error:
        raise _cli_error(_flag_message(error)) from None
    logs = _check_inputs("DIR_OR_GLOB", args.paths)
    try:
        fleet.check_output_apart(args.paths, logs, args.output)
    except ValueError as error:
        raise _cli_error(str(error).replace(f"output_dir {args.output!r}", f"-o {args.output}", 1)) from None
    try:
        with fleet.open_client(_client_argument(args), args.workers) as client:
            link = fleet.dashboard_link(client)
            count = len(client.scheduler_info().get("workers", {}))
            print(f"Dask cluster: {count} worker{'s' if count != 1 else ''}"
                  + (f", dashboard {link}" if link else ""), file=sys.stderr)
            result = fleet.run_many(args.paths, estimator=args.estimator, settings=args.preset, client=client,
                                    output_dir=args.output, csv_options=csv_options, write_csv=args.csv,
                                    retry_failed=args.retry_failed, progress=sys.stdout.isatty())
    except (ValueError, TypeError) as error:
        raise _cli_error(_flag_message(error)) from None
    for row in result.summary.to_pylist():  # the readers' warnings, one line each (never a Python warning)
        for warning in filter(None, (row.get("warnings") or "").split(" | ")):
            print(f"warning: {row['log_id']}: {warning}", file=sys.stderr)
    costs = result.costs.to_pylist()
    computed = [row for row in costs if row["action"] == "computed"]
    print(f"{len(computed)} computed, {len(result.reused)} reused (same settings {result.settings_hash}), "
          f"{len(result.failed)} failed; outputs in {args.output}")
    if computed:
        total = {name: sum(row[name] for row in computed) for name in ("read_s", "estimate_s", "write_s")}
        megabytes = sum(row["bytes"] for row in computed) / 1e6
        busy = sum(total.values())
        print(f"worker time per computed log: read {total['read_s'] / len(computed) * 1e3:.1f} ms, estimate "
              f"{total['estimate_s'] / len(computed) * 1e3:.1f} ms, write {total['write_s'] / len(computed) * 1e3:.1f}"
              f" ms ({f'{megabytes / busy:.2f}' if busy else '—'} MB/s per worker)")
    print()
    _print_summary(result.summary, args.worst)
    return 0 if not result.failed else 1


def _cmd_fit(args: argparse.Namespace) -> int:
    from .. import fleet

    fleet.require_fleet_packages()
    _check_numbers(args)
    csv_options = _csv_options(args)
    _client_argument(args)
    _check_fit_arguments(args)
    every = _check_inputs("DIR_OR_GLOB", args.paths)
    if args.holdout:
        _check_inputs("--holdout", args.holdout)
    try:
        train, holdout = args.paths, args.holdout
        if args.holdout_every:
            holdout = every[args.holdout_every - 1::args.holdout_every]
            train = [path for path in every if path not in set(holdout)]
        with fleet.open_client(_client_argument(args), args.workers) as client:
            link = fleet.dashboard_link(client)
            if link:
                print(f"Dask dashboard {link}", file=sys.stderr)
            result = fleet.fit_many(train, holdout=holdout, client=client, csv_options=csv_options, skip=args.skip,
                                    omega_range=(args.omega_min, args.omega_max))
    except (ValueError, TypeError) as error:
        raise _cli_error(_flag_message(error)) from None
    _print_fit(result, args.skip)
    if args.output:
        _write_fit(result, args.output)
    return 0


def _check_fit_arguments(args: argparse.Namespace) -> None:
    """CliError for ``fleet fit`` flags out of range or contradicting each other, and for an unwritable ``-o``."""
    from .common import check_output as _check_output, check_search_flags

    if args.holdout and args.holdout_every:
        raise _cli_error("give --holdout or --holdout-every, not both")
    if args.holdout_every is not None and args.holdout_every < 2:
        raise _cli_error(f"--holdout-every must be >= 2, got {args.holdout_every}")
    check_search_flags(args)
    _check_output(args.output, "-o", extensions=(".json",))


def _print_fit(result, skip: float) -> None:
    """The fleet fit's gains and its RMS tables (m): training logs, and held-out logs when there are some."""
    gains = result.settings
    print(f"{len(result.logs)} training logs ({result.metric_samples} samples after {skip:g} s each), "
          f"{len(result.excluded)} left out")
    for path, reason in result.excluded:
        print(f"  left out {path}: {_flag_message(reason)}")
    print(f"best of {len(result.landscape)} stable candidates: omega {result.omega:.4g} rad/s, zeta {result.zeta:.3g}, "
          f"omega_b {result.omega_b:.4g} rad/s")
    print(f"  position_gain {gains.position_gain:.6g} 1/s, velocity_gain {gains.velocity_gain:.6g} 1/s², "
          f"bias_gain {gains.bias_gain:.6g} 1/s³")
    print()
    rows = [["training logs, fitted gains", result.rms_error], ["training logs, VTOL default", result.default_rms_error]]
    if result.holdout:
        rows += [["held-out logs, fitted gains", result.holdout_rms_error],
                 ["held-out logs, VTOL default", result.holdout_default_rms_error]]
    print(_format_table(["pooled altitude − reference", "RMS (m)"], rows))
    if result.holdout:
        print()
        print(_format_table(["held-out log", "samples", "fitted RMS (m)", "default RMS (m)"],
                            [[row["log_id"], row["samples"], _cell(row["rms_error_m"]),
                              _cell(row["default_rms_error_m"])] for row in result.holdout]))
        for row in result.holdout:
            if row["error"]:
                print(f"  {row['log_id']}: {_flag_message(row['error'])}")


def _write_fit(result, path: str) -> None:
    """The fleet fit as JSON at ``path`` (written atomically)."""
    gains = result.settings
    record = {"omega": result.omega, "zeta": result.zeta, "omega_b": result.omega_b,
              "position_gain": gains.position_gain, "velocity_gain": gains.velocity_gain,
              "bias_gain": gains.bias_gain, "rms_error_m": result.rms_error,
              "default_rms_error_m": result.default_rms_error, "metric_samples": result.metric_samples,
              "logs": result.logs, "excluded": [list(item) for item in result.excluded],
              "holdout": result.holdout, "holdout_rms_error_m": result.holdout_rms_error,
              "holdout_default_rms_error_m": result.holdout_default_rms_error}
    import json

    from ..outputs import atomic_output

    with atomic_output(path) as temporary, open(temporary, "w") as handle:
        json.dump(record, handle, indent=1, allow_nan=True)
    print(f"fit written to {path}")


def _cmd_summary(args: argparse.Namespace) -> int:
    from .. import fleet

    if args.worst < 0:
        raise _cli_error(f"--worst must be >= 0, got {args.worst}")
    if "://" not in args.output and not os.path.isdir(args.output):
        raise _cli_error(f"OUT/ {args.output}: no such directory")
    try:
        table = fleet.summary(args.output)
    except ValueError as error:
        raise _cli_error(_flag_message(error)) from None
    _print_summary(table, args.worst, everything=args.all)
    return 0


def run_fleet_command(args: argparse.Namespace) -> int:
    """Handler of ``fusion-altitude fleet ...``; returns the exit status (1 if a log failed in ``run``)."""
    commands = {"run": _cmd_run, "fit": _cmd_fit, "summary": _cmd_summary}
    if getattr(args, "fleet_command", None) not in commands:
        args.fleet_parser.print_help()
        return 2
    return commands[args.fleet_command](args)
