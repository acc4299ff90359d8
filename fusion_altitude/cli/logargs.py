"""The log options of ``run``, ``fit``, ``compare`` and ``report``: their arguments, reading the log with them
(:func:`load`: the CSV flags → the readers' keywords, the readers' errors → one line naming our flags) and the
log's one-line summary."""

from __future__ import annotations

import argparse
import inspect
import os
import sys
import warnings
from typing import Optional

from .common import CliError, number
from .progress import Progress

__all__ = ["add_log_arguments", "load", "print_log_summary"]


#: CSV flags → (read_csv_log keyword, default): passed only when the user changed them.
_CSV_FLAGS = (
    ("--time", "time", "time_column", None),
    ("--time-units", "time_units", "time_units", "s"),
    ("--accel", "accel", "accel_column", None),
    ("--baro", "baro", "baro_column", None),
    ("--pressure", "pressure", "pressure_column", None),
    ("--reference", "reference", "reference_column", None),
    ("--accel-units", "accel_units", "accel_units", "m/s^2"),
    ("--altitude-units", "altitude_units", "altitude_units", "m"),
    ("--sea-level-pa", "sea_level_pa", "sea_level_pa", 101325.0),
    ("--remove-gravity", "remove_gravity", "remove_gravity", False),
    ("--gps", "gps", "gps_column", None),
    ("--rangefinder", "rangefinder", "rangefinder_column", None),
    ("--accel-body", "accel_body", "accel_body_columns", None),
    ("--gyro-body", "gyro_body", "gyro_body_columns", None),
    ("--gyro-units", "gyro_units", "gyro_units", "rad/s"),
    ("--attitude-columns", "attitude_columns", "attitude_columns", None),
    ("--attitude-convention", "attitude_convention", "attitude_convention", "quaternion"),
    ("--frame", "frame", "frame", "NED"),
    ("--temperature", "temperature", "temperature_column", None),
    ("--temperature-units", "temperature_units", "temperature_units", "C"),
    ("--ground-temperature", "ground_temperature", "ground_temperature_k", None),
)


def add_log_arguments(parser: argparse.ArgumentParser, agl: bool = True) -> None:
    group = parser.add_argument_group("log options (column flags: generic CSV only)")
    group.add_argument("--time", help="CSV: time column, s")
    group.add_argument("--time-units", default="s", choices=("s", "ms", "us"), help="CSV: units of --time")
    group.add_argument("--accel", help="CSV: vertical acceleration column (earth frame, +up)")
    group.add_argument("--accel-units", default="m/s^2", choices=("m/s^2", "g"), help="CSV: units of --accel")
    group.add_argument("--remove-gravity", action="store_true",
                       help="CSV: --accel still holds gravity (≈ +1 g at rest): subtract it")
    group.add_argument("--baro", help="CSV: baro altitude column (empty = no sample that row)")
    group.add_argument("--altitude-units", default="m", choices=("m", "ft"),
                       help="CSV: units of --baro, --reference and --gps")
    group.add_argument("--pressure", help="CSV: static pressure column, Pa (instead of --baro)")
    group.add_argument("--sea-level-pa", type=float, default=101325.0,
                       help="CSV: reference pressure for --pressure, Pa, > 0 (default 101325)")
    group.add_argument("--reference", help="CSV: the log's own altitude estimate or a better altitude, "
                                           "column (empty = unknown that row)")
    group.add_argument("--accel-body", metavar="X,Y,Z",
                       help="CSV: body-frame accelerometer columns (specific force), instead of --accel; needs "
                            "--attitude-columns")
    group.add_argument("--gyro-body", metavar="X,Y,Z",
                       help="CSV: body-frame gyroscope columns, the axes of --accel-body: with them the log has a "
                            "raw IMU and run picks the INS")
    group.add_argument("--gyro-units", default="rad/s", choices=("rad/s", "deg/s"), help="CSV: units of --gyro-body")
    group.add_argument("--attitude-columns", metavar="COLS",
                       help="CSV: attitude columns: W,X,Y,Z (quaternion, body → earth) or ROLL,PITCH,YAW (ZYX Euler)")
    group.add_argument("--attitude-convention", default="quaternion",
                       choices=("quaternion", "euler_deg", "euler_rad"), help="CSV: what --attitude-columns hold")
    group.add_argument("--frame", default="NED", choices=("NED", "ENU", "NWU"),
                       help="CSV: earth frame of --attitude-columns and body frame of --accel-body (default NED)")
    group.add_argument("--gps", help="CSV: GPS altitude column (used by --estimator kalman/alphabeta)")
    group.add_argument("--rangefinder", help="CSV: distance-to-ground column, m (used by kalman/alphabeta)")
    group.add_argument("--temperature", help="CSV: air temperature column for the hypsometric conversion")
    group.add_argument("--temperature-units", default="C", choices=("C", "K"), help="CSV: units of --temperature")
    group.add_argument("--ground-temperature", default=None, metavar="DEG_C|log",
                       help="ground temperature for the pressure → height conversion, °C, or 'log' (the log's own "
                            "temperature)")
    group.add_argument("--instance", type=int, default=None, metavar="N",
                       help=".bin/.ulg: sensor instance to read (default: the primary)")
    group.add_argument("--decoder", default="fast", choices=("fast", "pymavlink", "pyulog"),
                       help="log decoder: fast (default; .bin and .ulg decoded in C) or the reference library of one "
                            "format, pymavlink (.bin) or pyulog (.ulg), kept for one release")
    if agl:
        group.add_argument("--agl", action="store_true",
                           help="heights above the start (or the pad): estimate, baro and reference alike")


def _log_format(path: str) -> str:
    """"csv" for a generic CSV (needs column flags), else the reader's format name."""
    from .. import logs

    sniff = getattr(logs, "sniff_format", None)
    if sniff is not None:
        try:
            return str(sniff(path))
        except (OSError, ValueError):
            pass  # load_log reports the problem with its own message
    suffix = os.path.splitext(path)[1].lower()
    return {".ulg": "ulog", ".bin": "dataflash"}.get(suffix, "csv")


def load(args: argparse.Namespace, progress: Progress):
    """Read ``args.file`` with the CSV flags the user gave; LogError → CliError."""
    if not os.path.exists(args.file):
        raise CliError(f"{args.file}: no such file")
    number("--sea-level-pa", args.sea_level_pa, 0.0)
    ground_temperature_k = _ground_temperature_k(args.ground_temperature)
    column_lists = _column_lists(args)
    if args.instance is not None and args.instance < 0:
        raise CliError(f"--instance must be >= 0, got {args.instance}")
    fmt = _log_format(args.file)
    given = {}
    for flag, attribute, keyword, default in _CSV_FLAGS:
        value = getattr(args, attribute, default)
        if value != default:
            if keyword == "ground_temperature_k":
                value = ground_temperature_k
            value = column_lists.get(attribute, value)
            given[flag] = (keyword, value)
    options = _csv_options(given) if fmt == "csv" else _other_format_options(given, args.file, fmt)
    data = _read_log(args, options, progress)
    if data.time.size < 2:
        raise CliError(f"{data.source}: {data.time.size} sample(s); a log needs at least 2")
    if not (data.baro_altitude == data.baro_altitude).any():  # no finite baro sample at all
        raise CliError(f"{data.source}: no baro sample (the baro column is empty)")
    return data


def _ground_temperature_k(text: Optional[str]):
    """``--ground-temperature`` (°C or "log") as the readers take it: K, "log" or None."""
    if text is None:
        return None
    if text.strip().lower() == "log":
        return "log"
    try:
        celsius = float(text)
    except ValueError:
        raise CliError(f"--ground-temperature must be a temperature in °C or 'log', got {text!r}") from None
    number("--ground-temperature", celsius, -273.15, maximum=100.0)
    return celsius + 273.15


def _column_lists(args: argparse.Namespace) -> dict:
    """``--accel-body``, ``--gyro-body`` and ``--attitude-columns`` split into column names (attribute → tuple);
    CliError on a wrong count or an empty name."""
    column_lists = {}
    for flag, attribute, count in (("--accel-body", "accel_body", (3,)), ("--gyro-body", "gyro_body", (3,)),
                                   ("--attitude-columns", "attitude_columns", (3, 4))):
        text = getattr(args, attribute, None)
        if text is not None:
            names = [name.strip() for name in text.split(",")]
            if len(names) not in count or not all(names):
                raise CliError(f"{flag} takes {' or '.join(str(c) for c in count)} comma-separated column names, "
                               f"got {text!r}")
            column_lists[attribute] = tuple(names)
    return column_lists


def _csv_options(given: dict) -> dict:
    """The keywords of :func:`fusion_altitude.logs.read_csv_log` from the flags ``given`` (flag → (keyword,
    value)); CliError when a needed flag is missing, two exclude each other, or the reader lacks one."""
    from .. import logs

    parameters = inspect.signature(logs.read_csv_log).parameters
    missing = [flag for flag, keyword in (("--time", "time_column"), ("--accel", "accel_column"))
               if flag not in given and keyword in parameters
               and parameters[keyword].default is inspect.Parameter.empty]
    if "--accel" not in given and "--accel-body" not in given:
        missing.append("--accel (or --accel-body with --attitude-columns)")
    if "--baro" not in given and "--pressure" not in given:
        missing.append("--baro or --pressure")
    if missing:
        raise CliError(f"a CSV log needs {', '.join(missing)}")
    if "--baro" in given and "--pressure" in given:
        raise CliError("give --baro or --pressure, not both")
    options = {}
    for flag, (keyword, value) in given.items():
        if keyword not in parameters:
            raise CliError(f"{flag} is not supported by this version's CSV reader")
        options[keyword] = value
    return options


def _other_format_options(given: dict, path: str, fmt: str) -> dict:
    """The reader keywords for a recognised (not generic CSV) log: only ``--ground-temperature``; CliError for
    any CSV column flag."""
    csv_only = [flag for flag in given if flag != "--ground-temperature"]
    if csv_only:
        raise CliError(f"{', '.join(csv_only)}: CSV column flags do not apply to {path} ({fmt})")
    options = {}
    if "--ground-temperature" in given:  # the reader says whether its format takes it
        keyword, value = given["--ground-temperature"]
        options[keyword] = value
    return options


def _read_log(args: argparse.Namespace, options: dict, progress: Progress):
    """:func:`fusion_altitude.logs.load_log` with ``options`` (and ``--instance``) under a progress bar; its
    LogError → CliError naming our flags instead of the reader's keywords."""
    from .. import logs

    load_parameters = inspect.signature(logs.load_log).parameters
    if args.instance is not None:
        if "instance" not in load_parameters:
            raise CliError("--instance is not supported by this version's readers")
        options["instance"] = args.instance
    if getattr(args, "decoder", "fast") != "fast":
        options["decoder"] = args.decoder
    with progress.stage("reading") as bar:
        if "progress" in load_parameters:
            options["progress"] = bar
        try:
            with warnings.catch_warnings():
                # the reader's LogWarnings are also in data.warnings, printed with the summary
                warnings.simplefilter("ignore", getattr(logs, "LogWarning", UserWarning))
                return logs.load_log(args.file, **options)
        except ImportError as error:
            raise CliError(f"{args.file}: {error}") from None
        except logs.LogError as error:  # name our flags, not the reader's keywords
            raise CliError(_with_flags(str(error))) from None


def _with_flags(message: str) -> str:
    """A reader's message with its keywords spelled as our flags, as the user would type them:
    ``remove_gravity=True (--remove-gravity)`` → ``--remove-gravity``, ``accel_units='g'`` → ``--accel-units g``."""
    import re

    for flag, _, keyword, _ in _CSV_FLAGS:
        message = re.sub(rf"\b{keyword}=True\b", flag, message)
        message = re.sub(rf"\b{keyword}='([^']*)'", rf"{flag} \1", message)
        message = re.sub(rf"\b{keyword}\b", flag, message)
        message = message.replace(f"{flag} ({flag})", flag)
        message = re.sub(rf"({re.escape(flag)} \S+) \({re.escape(flag)} \S+\)", r"\1", message)
    return message


def print_log_summary(data, what: str, notes=None) -> None:
    """The log's one-line summary, then its notes (``notes`` replaces ``data.notes``) and warnings."""
    import numpy as np

    n_baro = int(np.count_nonzero(np.isfinite(data.baro_altitude)))
    duration = float(data.time[-1] - data.time[0])
    print(f"{data.source}: {data.time.size} samples over {duration:.2f} s "
          f"({data.time.size / max(duration, 1e-9):.1f} Hz), {n_baro} baro samples; {what}")
    for note in data.notes if notes is None else notes:
        print(f"  {note}")
    sys.stdout.flush()  # the warnings on stderr come after the summary line in a terminal
    for warning in getattr(data, "warnings", []):  # on stderr, as `fit` prints them
        print(f"warning: {warning}", file=sys.stderr)
    if data.clipped is not None and data.clipped.any():
        print(f"  accelerometer clipped on {int(data.clipped.sum())} samples (observer: baro-trusting gains, "
              "bias frozen there)")
