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
"""

from __future__ import annotations

import argparse
import contextlib
import inspect
import math
import os
import sys
import time as _time
import warnings
from typing import Callable, Iterator, List, Optional

from .._version import __version__
from .common import (MAX_OMEGA, MAX_TUNE_RATE, MAX_ZETA, MIN_TUNE_RATE, PROGRESS_MINIMUM, RUN_OUTPUT_EXTENSIONS,
                     CliError, EstimateError, format_table)
from .common import number as _number
from .common import check_output as _check_output
from .common import check_plot as _check_plot

__all__ = ["main", "build_parser", "format_table", "CliError"]

#: A stage that takes at least this long prints its time on stderr, s.
STAGE_REPORT_SECONDS = 0.5


class _Progress:
    """Stage times and progress bars on stderr.

    Each stage (reading, estimating, writing, plotting, fitting) prints its
    duration when it takes ≥ :data:`STAGE_REPORT_SECONDS`; on a terminal,
    stages over logs of ≥ :data:`PROGRESS_MINIMUM` samples (and every fit)
    also draw a bar while they run.
    """

    def __init__(self, stream=None, width: int = 30, minimum: int = PROGRESS_MINIMUM):
        self.stream = stream if stream is not None else sys.stderr
        self.width = width
        self.minimum = minimum

    def bar(self, name: str) -> Callable[[int, int], None]:
        interactive = bool(getattr(self.stream, "isatty", lambda: False)())

        def draw(done: int, total: int) -> None:
            if not interactive or (total < self.minimum and name not in ("fitting", "comparing")):
                return
            filled = int(self.width * done / max(total, 1))
            self.stream.write(f"\r{name:<10} [{'#' * filled}{'.' * (self.width - filled)}] "
                              f"{100 * done / max(total, 1):5.1f}%")
            if done >= total:
                self.stream.write("\r" + " " * (self.width + 22) + "\r")
            self.stream.flush()
        return draw

    @contextlib.contextmanager
    def stage(self, name: str) -> Iterator[Callable[[int, int], None]]:
        start = _time.perf_counter()
        yield self.bar(name)
        elapsed = _time.perf_counter() - start
        if elapsed >= STAGE_REPORT_SECONDS:
            self.stream.write(f"{name}: {elapsed:.2f} s\n")
            self.stream.flush()


# ----------------------------------------------------------------------------
# demo


def _cmd_demo(args: argparse.Namespace) -> int:
    from .._core._common import GRAVITY
    from ..sim.scenarios import PUBLISHED, PUBLISHED_SOURCE, describe, export_csv, run_scenario

    if args.seed < 0:
        raise CliError(f"--seed must be >= 0, got {args.seed}")
    _check_attitude(args.attitude)
    _check_plot(args.plot)
    _check_output(args.export, "--export", extensions=(".csv",))
    if args.export and args.plot and _same_file_name(args.export, args.plot):
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


def _same_file_name(a: str, b: str) -> bool:
    return os.path.abspath(a) == os.path.abspath(b)


def _check_attitude(attitude: str) -> None:
    if attitude == "ahrs":
        try:
            import imufusion  # noqa: F401
        except ImportError:
            raise CliError("--attitude ahrs needs imufusion: pip install 'fusion-altitude[ahrs]'") from None


# ----------------------------------------------------------------------------
# tune


def _cmd_tune(args: argparse.Namespace) -> int:
    from .._core._observer import AltitudeSettings
    from ..tuning import report

    _number("--omega", args.omega, 0.0, maximum=MAX_OMEGA)
    _number("--zeta", args.zeta, 0.0, maximum=MAX_ZETA)
    _number("--omega-b", args.omega_b, 0.0, strict=False, maximum=MAX_OMEGA)
    _number("--rate", args.rate, 0.0, maximum=MAX_TUNE_RATE)
    _number("--rate", args.rate, MIN_TUNE_RATE, strict=False)
    dt = 1.0 / args.rate
    omega_b = args.omega / 5.0 if args.omega_b is None else args.omega_b
    try:
        settings = AltitudeSettings.from_bandwidth(args.omega, args.zeta, omega_b)
        result = report(settings, dt, omega=args.omega, omega_b=omega_b)
    except ValueError as error:
        raise CliError(f"--omega {args.omega:g}, --zeta {args.zeta:g}, --omega-b {omega_b:g}: {error}") from None
    kh, kv, kb = settings.as_tuple()
    print(f"omega {args.omega:g} rad/s, zeta {args.zeta:g}, omega_b {omega_b:g} rad/s, rate {args.rate:g} Hz "
          f"(dt {dt:g} s)")
    print()
    print(format_table(["gain", "value", "unit"], [["position_gain Kh", kh, "1/s"], ["velocity_gain Kv", kv, "1/s²"],
                                                   ["bias_gain Kb", kb, "1/s³"]]))
    print()
    rows = [[f"{s.real:+.4f}{s.imag:+.4f}j", f"{tau:.3f}", f"{z.real:+.6f}{z.imag:+.6f}j", f"{abs(z):.6f}"]
            for s, tau, z in result.poles]
    print(format_table(["continuous pole s (rad/s)", "time constant (s)", "its discrete pole z", "|z|"], rows))
    print()
    print(f"2% settling, altitude after a baro step: {result.step_settling:.2f} s")
    print(f"2% settling, bias estimate after an accel-bias step: {result.bias_settling:.2f} s")
    print()
    print(format_table(["check", "result", "value"], [[name, "ok" if ok else "FAIL", value]
                                                      for name, ok, value in result.checks]))
    print()
    if result.stable:
        print(f"baro noise gain: {result.noise_gain:.4f} (altitude noise sd per m of white baro noise per sample)")
        print(f"equivalent noise bandwidth of baro → altitude: {result.noise_bandwidth:.4f} Hz")
    else:  # the discrete filter diverges: its noise gain and bandwidth are infinite, not a number to print
        print("baro noise gain: unstable (the discrete filter diverges at this rate: no finite noise gain)")
        print("equivalent noise bandwidth of baro → altitude: unstable")
    return 0 if result.stable else 1


# ----------------------------------------------------------------------------
# reading logs

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


def _load(args: argparse.Namespace, progress: _Progress):
    """Read ``args.file`` with the CSV flags the user gave; LogError → CliError."""
    if not os.path.exists(args.file):
        raise CliError(f"{args.file}: no such file")
    _number("--sea-level-pa", args.sea_level_pa, 0.0)
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
    _number("--ground-temperature", celsius, -273.15, maximum=100.0)
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


def _read_log(args: argparse.Namespace, options: dict, progress: _Progress):
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


def _print_log_summary(data, what: str, notes=None) -> None:
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


# ----------------------------------------------------------------------------
# run


#: ``--long-axis`` values: the accelerometer column along the rocket's nose and its sign.
LONG_AXES = {f"{sign}{axis}": (column, 1.0 if sign == "+" else -1.0)
             for column, axis in enumerate("XYZ") for sign in "+-"}


#: Estimators that carry on with the GPS altitude when the baro stops.


def _run_estimator(args: argparse.Namespace, data, health=()) -> str:
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
        raise CliError(f"--rocket runs the rocket flight layer; it cannot be combined with --estimator {estimator}")
    if args.events_csv and estimator != "rocket":
        raise CliError(f"--events-csv needs the rocket flight layer (a rocket log, --rocket or --estimator rocket), "
                       f"not --estimator {estimator}")
    if args.long_axis and estimator != "rocket":
        raise CliError("--long-axis applies to the rocket flight layer only")
    missing = runner.missing_inputs(data, estimator)
    if missing:
        raise CliError(f"--estimator {estimator} needs raw {' and '.join(missing)} in the log; {data.source} has no "
                       f"{' or '.join(missing)} (PX4 sensor_combined, ArduPilot IMU, CSV --gyro-body/--accel-body)")
    return estimator


def _print_health(data, health, run, estimator: str) -> None:
    """The health report: per sensor (rate, first and last sample, longest outage, dead, saturated, stopped) and
    per estimator (gaps, rejections, resets, time not baro-aided); warnings on stderr for a stream that stops and
    for what the estimator cannot do about it."""
    import numpy as np

    from ..estimators import ESTIMATORS
    from ..health import format_health, not_baro_aided, stopped_streams

    time = np.asarray(data.time, float)
    print()
    for line in format_health(health, float(time[0]), float(time[-1])):
        print(f"  {line}")
    if getattr(data, "repeated_timestamps", 0):
        print(f"  rows merged (repeated time stamps): {data.repeated_timestamps}")
    if getattr(data, "baro_only", False):
        print("  no accelerometer in the log: every estimator runs as a baro-only tracking filter")
    unaided = not_baro_aided(time, data.baro_altitude)
    steps = np.diff(time, prepend=time[0])
    seconds = float(np.sum(steps[unaided]))
    parts = [f"estimator {estimator}:"]
    if getattr(run, "gap_count", None) is not None:
        parts.append(f"{run.gap_count} gaps")
    if getattr(run, "baro_rejections", None) is not None:
        parts.append(f"{run.baro_rejections} baro rejections, {run.baro_resets} resets")
    parts.append(f"{seconds:.2f} s without a baro sample for longer than the baro timeout "
                 f"({int(unaided.sum())} rows flagged not baro-aided in -o)")
    print("  " + ", ".join(parts[1:]).join([parts[0] + " ", ""]))
    sys.stdout.flush()
    has_gps = any(s.name == "gps" and s.samples > 0 for s in health)
    for stream in stopped_streams(health):
        print(f"warning: the {stream.name} stops at {stream.last:.2f} s, {float(time[-1]) - stream.last:.2f} s before "
              "the log's end", file=sys.stderr)
        if stream.name == "baro":
            if ESTIMATORS[estimator].uses_gps and has_gps:
                print(f"warning: estimator {estimator} carries on with the GPS altitude after the baro stops",
                      file=sys.stderr)
            else:
                print(f"warning: estimator {estimator} has no other height source: from {stream.last:.2f} s its "
                      "altitude is not baro-aided (flags bit 1 in -o)"
                      + ("; --estimator kalman uses the log's GPS" if has_gps else ""), file=sys.stderr)
    if getattr(data, "vehicle", "") == "rocket" and estimator != "rocket":
        print(f"warning: estimator {estimator} has no baro lockout for transonic flight or ejection charges; on a "
              "rocket log the rocket flight layer (the default) has one", file=sys.stderr)


def _print_events(run, data) -> None:
    """The rocket layer's events next to the flight computer's own (when the log has them)."""
    from ..rocket import flight_computer_events

    theirs, how = flight_computer_events(data, pad_altitude=None)
    print()
    print("flight events (time: the log's s; height: m above the pad)" + (
        f"; flight computer's: {how}" if theirs is not None else f"; no flight computer's events: {how}"))
    header = ["event", "time (s)", "height (m)"]
    if theirs is not None:
        header += ["FC time (s)", "FC height (m)"]
    rows = []
    for event in run.events:
        row = [event.name] + ([event.time, event.height] if event.occurred else [math.nan, math.nan])
        if theirs is not None:
            other = theirs[event.name]
            row += [other.time, other.height] if other.occurred else [math.nan, math.nan]
        rows.append(row)
    print(format_table(header, rows))


def _cmd_run(args: argparse.Namespace) -> int:
    progress = _Progress()
    _check_run_outputs(args)
    if args.output == "-":  # the CSV goes to standard output, the report to stderr
        stdout = sys.stdout
        with contextlib.redirect_stdout(sys.stderr):
            return _run(args, progress, stdout)
    return _run(args, progress, sys.stdout)


def _run(args: argparse.Namespace, progress: "_Progress", stdout) -> int:
    """``run`` after the output checks; ``stdout`` is where ``-o -`` writes the CSV."""
    import numpy as np

    from .. import runner
    from .._core._observer import AltitudeSettings
    from ..health import check_estimate, sensor_health

    data = _load(args, progress)
    health = sensor_health(data)
    estimator = _run_estimator(args, data, health)
    options = {"long_axis": LONG_AXES[args.long_axis]} if args.long_axis else {}
    if runner.ESTIMATORS[estimator].takes_preset:
        rate = runner.observer_rate(data)  # the preset rule, steps per baro and the stability test, once
        options["steps_per_baro"] = rate.steps_per_baro
        if args.preset is None:
            args.preset = _default_preset(rate)
        else:
            _warn_if_unstable(AltitudeSettings.preset(args.preset), rate, f"--preset {args.preset}")
    with progress.stage("estimating") as bar:
        try:
            run = runner.run_log(data, AltitudeSettings.preset(args.preset) if args.preset else None, progress=bar,
                                 estimator=estimator, agl=args.agl, **options)
        except ValueError as error:  # e.g. an INS input out of range, named by the binding
            raise CliError(f"{data.source}: {error}") from None
    what, notes = _run_description(args, data, run, estimator)
    _print_log_summary(data, what, notes)
    _print_health(data, health, run, estimator)
    problem = check_estimate(run, run.estimate.altitude, run.estimate.vertical_velocity)
    if problem is not None:
        raise EstimateError(f"{data.source}: estimator {estimator}: {problem}: no result printed or written "
                            "(the estimate cannot be trusted; try another --estimator or --preset)")
    print()
    _print_run_results(run, estimator)
    if run.reference_altitude is not None and np.isfinite(run.reference_altitude).any():
        _print_run_comparison(run, args.agl)
    if run.events is not None:
        _print_events(run, data)
    _write_run_outputs(args, run, progress, stdout)
    return 0


def _check_run_outputs(args: argparse.Namespace) -> None:
    """CliError when an output of ``run`` (-o, --events-csv, --plot) is the input or two outputs name one file."""
    _check_output(args.output, "-o", [args.file], stdout=True, extensions=RUN_OUTPUT_EXTENSIONS)
    _check_output(args.events_csv, "--events-csv", [args.file], extensions=(".csv",))
    _check_plot(args.plot, [args.file])
    outputs = [(flag, path) for flag, path in (("-o", args.output), ("--plot", args.plot),
                                               ("--events-csv", args.events_csv)) if path]
    for i, (flag_a, a) in enumerate(outputs):
        for flag_b, b in outputs[i + 1:]:
            if _same_file_name(a, b):
                raise CliError(f"{flag_a} and {flag_b} name the same file")


def _run_description(args: argparse.Namespace, data, run, estimator: str):
    """What ``run`` ran (estimator, preset, rocket long axis, datum) and the notes to print (None: the log's)."""
    from .. import runner

    what = f"estimator {estimator}" + (f", preset {args.preset}" if estimator == "observer" else "")
    if estimator == "rocket" and not args.estimator:
        what += " (rocket log)" if not args.rocket else " (--rocket)"
    if estimator == "ins" and not args.estimator:
        what += " (raw gyro and accelerometer in the log)"
    notes = None
    if estimator == "ins":
        # the reader's notes name what the observer would use (an attitude source); the INS makes its own attitude
        frame = f", body {data.imu_frame}" if data.imu_frame else ""
        notes = list(data.notes) + [f"INS inputs: the raw gyro and accelerometer{frame} and the baro; "
                                    "any attitude source above is not used (the INS estimates its own)"]
    if estimator == "rocket" and data.accel is not None:
        from ..logs.cats import ATTITUDE_NOTE

        column, sign = LONG_AXES[args.long_axis] if args.long_axis else runner.rocket_long_axis(data.accel, data.time)
        axis = f"{'+' if sign > 0 else '-'}{'XYZ'[column]}"
        what += f"; long axis {axis}"
        # the rocket layer takes the raw accelerometer's long axis, not the reader's gyro-integrated vertical
        notes = [f"rocket layer: accelerometer along the long axis ({axis}) minus g, not rotated by an attitude"
                 if note == ATTITUDE_NOTE else note for note in data.notes]
    if args.agl:
        what += f"; heights above the start ({run.datum:.2f} m)"
    return what, notes


def _last_finite(values) -> float:
    """The last finite value of ``values``; NaN if none is."""
    import numpy as np

    finite = values[np.isfinite(values)]
    return float(finite[-1]) if finite.size else math.nan


def _print_run_results(run, estimator: str) -> None:
    """Final, max and min altitude (m) of the estimate, baro and reference; final bias, gaps, INS state."""
    import numpy as np

    altitude = np.asarray(run.estimate.altitude, float)
    baro = run.baro_altitude
    columns = [("estimate", altitude), ("baro", baro)]
    if run.reference_altitude is not None:
        columns.append((run.reference_name or "reference", run.reference_altitude))
    rows = [["final altitude (m)"] + [_last_finite(v) for _, v in columns],
            ["max altitude (m)"] + [float(np.nanmax(v)) if np.isfinite(v).any() else math.nan for _, v in columns],
            ["min altitude (m)"] + [float(np.nanmin(v)) if np.isfinite(v).any() else math.nan for _, v in columns]]
    print(format_table([""] + [name for name, _ in columns], rows))
    if hasattr(run.estimate, "accel_bias"):
        print(f"final accel bias estimate: {float(run.estimate.accel_bias[-1]):+.4f} m/s²")
    if getattr(run, "gap_count", None) is not None:
        period = (f" (dt > {run.gap_period:.3g} s, or a step its gains cannot integrate stably)"
                  if getattr(run, "gap_period", None) is not None else "")
        print(f"gaps met by the estimator{period}: {run.gap_count}")
    if estimator == "ins":
        e = run.estimate
        print(f"final INS state: roll {float(e.roll[-1]):+.2f}°, pitch {float(e.pitch[-1]):+.2f}°, "
              f"gyro bias ({float(e.gyro_bias_x[-1]):+.5f}, {float(e.gyro_bias_y[-1]):+.5f}, "
              f"{float(e.gyro_bias_z[-1]):+.5f}) rad/s, accel z bias {float(e.accel_z_bias[-1]):+.4f} m/s², "
              f"baro bias {float(e.baro_bias[-1]):+.3f} m; stationary on {int(np.count_nonzero(e.is_stationary))} "
              "samples")
        if run.baro_rejections is not None:
            readings = int(np.count_nonzero(np.isfinite(run.baro_altitude)))
            print(f"baro innovation gate: {run.baro_rejections} of {readings} readings rejected, "
                  f"{run.baro_resets} height resets after a rejection streak")


def _print_run_comparison(run, agl: bool) -> None:
    """Estimate and raw baro against the log's own estimate: mean, RMS, max (m); velocity RMS (m/s)."""
    import numpy as np

    estimate = run.comparison()
    raw = run.baro_comparison()
    print()
    datum = "above the start" if agl else "on the baro datum"
    print(f"against the log's own estimate, {run.reference_name} ({datum}):")
    rows = [["mean (m)", estimate.mean, raw.mean], ["RMS (m)", estimate.rms, raw.rms],
            ["max |·| (m)", estimate.max, raw.max]]
    reference_velocity = run.reference_velocity
    if reference_velocity is not None and np.isfinite(reference_velocity).any():
        from ..metrics import error_statistics

        velocity = error_statistics(run.time, np.asarray(run.estimate.vertical_velocity, float)
                                    - reference_velocity, 0.0)
        rows.append(["velocity RMS (m/s)", velocity.rms, math.nan])
    print(format_table(["", "estimate − ref", "baro − ref"], rows))


def _write_run_outputs(args: argparse.Namespace, run, progress: _Progress, stdout=None) -> None:
    """Write what ``run`` was asked for: the events CSV, the estimates CSV (``-o -``: to ``stdout``), the plot."""
    from .. import runner

    if args.events_csv:
        with runner.atomic_output(args.events_csv) as temporary:
            run.events.to_csv(temporary)
        print(f"events written to {args.events_csv}")
    if args.output == "-":
        with contextlib.redirect_stdout(stdout):
            runner.write_csv(run, "-")
    elif args.output:
        with progress.stage("writing") as bar:
            runner.write_csv(run, args.output, progress=bar)
        print(f"estimates written to {args.output}")
    if args.plot:
        from ..plotting import plot_log_run

        with progress.stage("plotting"):
            plot_log_run(run, args.plot)
        print(f"plot written to {args.plot}")


def _default_preset(rate) -> str:
    """The observer preset ``run`` uses without ``--preset`` (``rate.default_preset``, of
    :func:`fusion_altitude.estimators.observer_rate`); a change from vtol is said on stderr."""
    name = rate.default_preset
    if name != "vtol":
        print(f"note: the default preset vtol is unstable at this log's rate (nominal period "
              f"{rate.nominal_period:g} s, baro on 1 of {rate.steps_per_baro:.2f} steps): running preset {name}, the "
              "fastest one stable there", file=sys.stderr)
    elif not rate.is_stable(name):
        _warn_if_unstable(name, rate, "the default preset vtol")
    return name


def _warn_if_unstable(settings, rate, what: str) -> None:
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


# ----------------------------------------------------------------------------
# fit


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


def _fit_inputs(args: argparse.Namespace, progress: _Progress):
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
    data = _load(args, progress)
    if data.reference_altitude is None or not np.isfinite(data.reference_altitude).any():
        raise CliError(f"{data.source} has no reference altitude: give --reference COLUMN (CSV), or a .ulg/.bin "
                       "with the autopilot's own height estimate")
    for warning in getattr(data, "warnings", []):
        print(f"warning: {warning}", file=sys.stderr)
    skip = 5.0 if args.skip is None else args.skip
    return (f"{data.source} (reference: {data.reference_name})", data.time, data.vertical_acceleration,
            data.baro_altitude, data.reference_altitude, None, skip)


def _cmd_fit(args: argparse.Namespace) -> int:
    import numpy as np

    from .. import tuning

    progress = _Progress()
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
    _number("--skip", args.skip, 0.0, strict=False)
    _number("--omega-min", args.omega_min, 0.0, maximum=MAX_OMEGA)
    _number("--omega-max", args.omega_max, 0.0, maximum=MAX_OMEGA)
    if args.omega_min >= args.omega_max:
        raise CliError(f"--omega-min ({args.omega_min:g}) must be below --omega-max ({args.omega_max:g})")
    _check_plot(args.plot, [args.file] if args.file else [])
    _parse_train_until(args.train_until)


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


# ----------------------------------------------------------------------------
# compare


def _cmd_compare(args: argparse.Namespace) -> int:
    from .. import comparison

    if args.repeat < 0:
        raise CliError(f"--repeat must be >= 0 (0: no timing), got {args.repeat}")
    if args.seed < 0 or args.fit_seed < 0:
        raise CliError(f"--seed and --fit-seed must be >= 0, got {args.seed} and {args.fit_seed}")
    _check_attitude(args.attitude)
    _check_plot(args.plot, [args.file] if args.file else [])
    if args.file is not None:
        return _compare_log(args)
    scenarios = args.scenario or list(comparison.SCENARIOS)
    with _Progress().stage("comparing") as bar:
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
    _number("--skip", args.skip, 0.0, strict=False)
    progress = _Progress()
    data = _load(args, progress)
    with progress.stage("comparing") as bar:
        try:
            rows = comparison.compare_log(data, repeat=args.repeat, skip=args.skip or 0.0, agl=args.agl,
                                          progress=bar)
        except ValueError as error:
            raise CliError(str(error)) from None
    _print_log_summary(data, "every estimator against the log's own estimate")
    print(f"reference: {data.reference_name}; errors after {args.skip or 0.0:g} s"
          + ("; heights above the start" if args.agl else "") + "; velocity against the log's own vertical velocity")
    print()
    _print_rows(args, rows)
    if args.plot:
        with progress.stage("plotting"):
            comparison.plot_log_comparison(data, rows, args.plot, agl=args.agl)
        print(f"plot written to {args.plot}")
    return _refused_rows(rows)


# ----------------------------------------------------------------------------
# parser


def build_parser() -> argparse.ArgumentParser:
    """The argparse parser of ``fusion-altitude``."""
    parser = argparse.ArgumentParser(
        prog="fusion-altitude",
        description="Altitude and vertical-velocity estimation: barometer + accelerometer fusion.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    _add_demo_parser(commands)
    _add_tune_parser(commands)
    _add_run_parser(commands)
    _add_fit_parser(commands)
    _add_compare_parser(commands)
    from .fleet import add_fleet_parser
    add_fleet_parser(commands)
    from .report import add_report_parser
    add_report_parser(commands)
    return parser


def _add_demo_parser(commands) -> None:
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


def _add_tune_parser(commands) -> None:
    """The ``tune`` subcommand: gains, poles, settling and noise of ω (rad/s), ζ, ω_b (rad/s) at a rate (Hz)."""
    tune = commands.add_parser("tune", help="gains, poles, settling and noise for a bandwidth choice",
                               description="Gains from ω, ζ, ω_b and what they do at a sample rate.")
    tune.add_argument("--omega", type=float, default=1.5,
                      help=f"position-loop bandwidth ω, rad/s, > 0 and <= {MAX_OMEGA:g} (default 1.5)")
    tune.add_argument("--zeta", type=float, default=0.7,
                      help=f"damping ratio ζ, > 0 and <= {MAX_ZETA:g} (default 0.7)")
    tune.add_argument("--omega-b", type=float, default=None,
                      help=f"bias-loop bandwidth ω_b, rad/s, >= 0 and <= {MAX_OMEGA:g} (default ω/5; 0 = no bias "
                           "estimation)")
    tune.add_argument("--rate", type=float, default=100.0,
                      help=f"sample rate, Hz, >= {MIN_TUNE_RATE:g} and <= {MAX_TUNE_RATE:g} (default 100)")
    tune.set_defaults(handler=_cmd_tune)


def _add_run_parser(commands) -> None:
    """The ``run`` subcommand: an estimator on a recorded log."""
    from ..runner import ESTIMATORS

    run = commands.add_parser("run", help="run an estimator on a recorded log (CSV, .ulg, .bin)",
                              description="Run an estimator on a log and compare it with the log's own estimate. "
                                          "PX4 ULog, ArduPilot DataFlash, AltOS CSV and CATS files are recognised "
                                          "by their content; a generic CSV needs --time, --accel and --baro or "
                                          "--pressure.")
    run.add_argument("file", help="the log: PX4 .ulg, ArduPilot .bin, AltOS or CATS CSV, or a generic CSV")
    _add_log_arguments(run)
    run.add_argument("--estimator", default=None, choices=list(ESTIMATORS),
                     help="estimator (default: rocket on a rocket log (AltOS, CATS, Raven, RRC3) or with --rocket, "
                          "else kalman when the baro stops before the log's end and the log has GPS, else ins on a "
                          "log with a raw gyro and accelerometer, else observer): "
                          + "; ".join(f"{e.name}: {e.description}" for e in ESTIMATORS.values()))
    run.add_argument("--rocket", action="store_true",
                     help="run the rocket flight layer (pad calibration, baro lockout, flight events) on any log")
    run.add_argument("--events-csv", metavar="EVENTS.csv",
                     help="rocket: write the flight events, one row each: event,time,height (launch, burnout, "
                          "apogee, main, landed; the log's s, m above the pad)")
    run.add_argument("--long-axis", choices=list(LONG_AXES), metavar="{+X,-X,+Y,-Y,+Z,-Z}",
                     help="rocket: accelerometer axis pointing to the nose (default: the axis carrying gravity in "
                          "the first second of the log)")
    run.add_argument("--preset", default=None, choices=("balloon", "fixed_wing", "vtol", "racing", "rocket"),
                     help="observer gains (default vtol; on a log too slow for vtol the fastest preset stable at "
                          "its rate, said on stderr)")
    run.add_argument("-o", "--output", metavar="OUT.csv",
                     help="write the estimates per sample (full precision; never the input file)")
    run.add_argument("--plot", metavar="OUT.png", help="write a plot (needs the [plot] extra)")
    run.set_defaults(handler=_cmd_run)


def _add_fit_parser(commands) -> None:
    """The ``fit`` subcommand: fit the observer's gains to a reference altitude."""
    from ..sim.scenarios import scenario_names

    fit = commands.add_parser("fit", help="fit the gains to a reference altitude (a log or a scenario)",
                              description="Search omega, zeta, omega_b for the gains whose altitude best matches a "
                                          "reference: a log's reference column or autopilot estimate, or a "
                                          "simulated scenario's truth.")
    fit.add_argument("file", nargs="?", help="CSV (with --reference), PX4 ULog (.ulg) or ArduPilot DataFlash (.bin)")
    _add_log_arguments(fit, agl=False)
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


def _add_compare_parser(commands) -> None:
    """The ``compare`` subcommand: every estimator on the simulator's scenarios or on one log."""
    from ..comparison import SCENARIOS
    from ..sim.scenarios import scenario_names

    comparison = commands.add_parser(
        "compare", help="every estimator on the simulator's scenarios, or on one log: one table",
        description="Without FILE: observer (preset and fitted gains), Kalman filter, two-stage complementary "
                    "filter, quality-weighted alpha-beta fusion, inertial filter (INS, from the simulated raw IMU), "
                    "the rocket layer (rocket scenario) and raw baro on the same simulated data: altitude "
                    "RMS and max error, velocity RMS, recovery time after a sensor fault, C batch ns/sample. "
                    "With a log FILE: every estimator of `run --estimator` against the log's own estimate.")
    comparison.add_argument("file", nargs="?", help="a recorded log with its own estimate (as for `run`)")
    _add_log_arguments(comparison)
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


def _add_log_arguments(parser: argparse.ArgumentParser, agl: bool = True) -> None:
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
