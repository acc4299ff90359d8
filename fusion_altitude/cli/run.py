"""``fusion-altitude run``: any estimator of :data:`fusion_altitude.estimators.ESTIMATORS` on a recorded log
(:mod:`fusion_altitude.logs`), compared with the log's own estimate; the estimates (full precision), the rocket
estimator's events and a plot written on request."""

from __future__ import annotations

import argparse
import contextlib
import math
import sys

from .choice import default_preset, run_estimator, warn_if_unstable
from .common import RUN_OUTPUT_EXTENSIONS, CliError, EstimateError, check_output, check_plot, format_table, \
    same_file_name
from .logargs import add_log_arguments, load, print_log_summary
from .progress import Progress

__all__ = ["add_parser", "LONG_AXES"]


#: ``--long-axis`` values: the accelerometer column along the rocket's nose and its sign.
LONG_AXES = {f"{sign}{axis}": (column, 1.0 if sign == "+" else -1.0)
             for column, axis in enumerate("XYZ") for sign in "+-"}


def add_parser(commands) -> None:
    """The ``run`` subcommand: an estimator on a recorded log."""
    from ..runner import ESTIMATORS

    run = commands.add_parser("run", help="run an estimator on a recorded log (CSV, .ulg, .bin)",
                              description="Run an estimator on a log and compare it with the log's own estimate. "
                                          "PX4 ULog, ArduPilot DataFlash, AltOS CSV and CATS files are recognised "
                                          "by their content; a generic CSV needs --time, --accel and --baro or "
                                          "--pressure.")
    run.add_argument("file", help="the log: PX4 .ulg, ArduPilot .bin, AltOS or CATS CSV, or a generic CSV")
    add_log_arguments(run)
    run.add_argument("--estimator", default=None, choices=list(ESTIMATORS),
                     help="estimator (default: rocket on a rocket log (AltOS, CATS, Raven, RRC3) or with --rocket, "
                          "else kalman when the baro stops before the log's end and the log has GPS, else ins on a "
                          "log with a raw gyro and accelerometer, else observer): "
                          + "; ".join(f"{e.name}: {e.description}" for e in ESTIMATORS.values()))
    run.add_argument("--rocket", action="store_true",
                     help="run the rocket estimator (pad calibration, baro lockout, flight events) on any log")
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


def _cmd_run(args: argparse.Namespace) -> int:
    progress = Progress()
    _check_run_outputs(args)
    if args.output == "-":  # the CSV goes to standard output, the report to stderr
        stdout = sys.stdout
        with contextlib.redirect_stdout(sys.stderr):
            return _run(args, progress, stdout)
    return _run(args, progress, sys.stdout)


def _run(args: argparse.Namespace, progress: "Progress", stdout) -> int:
    """``run`` after the output checks; ``stdout`` is where ``-o -`` writes the CSV."""
    import numpy as np

    from .. import runner
    from .._core._observer import AltitudeSettings
    from ..health import check_estimate, sensor_health

    data = load(args, progress)
    health = sensor_health(data)
    estimator = run_estimator(args, data, health)
    options = {"long_axis": LONG_AXES[args.long_axis]} if args.long_axis else {}
    if runner.ESTIMATORS[estimator].takes_preset:
        rate = runner.observer_rate(data)  # the preset rule, steps per baro and the stability test, once
        options["steps_per_baro"] = rate.steps_per_baro
        if args.preset is None:
            args.preset = default_preset(rate)
        else:
            warn_if_unstable(AltitudeSettings.preset(args.preset), rate, f"--preset {args.preset}")
    with progress.stage("estimating") as bar:
        try:
            run = runner.run_log(data, AltitudeSettings.preset(args.preset) if args.preset else None, progress=bar,
                                 estimator=estimator, agl=args.agl, **options)
        except ValueError as error:  # e.g. an INS input out of range, named by the binding
            raise CliError(f"{data.source}: {error}") from None
    what, notes = _run_description(args, data, run, estimator)
    print_log_summary(data, what, notes)
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
    check_output(args.output, "-o", [args.file], stdout=True, extensions=RUN_OUTPUT_EXTENSIONS)
    check_output(args.events_csv, "--events-csv", [args.file], extensions=(".csv",))
    check_plot(args.plot, [args.file])
    outputs = [(flag, path) for flag, path in (("-o", args.output), ("--plot", args.plot),
                                               ("--events-csv", args.events_csv)) if path]
    for i, (flag_a, a) in enumerate(outputs):
        for flag_b, b in outputs[i + 1:]:
            if same_file_name(a, b):
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
        # the rocket estimator takes the raw accelerometer's long axis, not the reader's gyro-integrated vertical
        notes = [f"rocket estimator: accelerometer along the long axis ({axis}) minus g, not rotated by an attitude"
                 if note == ATTITUDE_NOTE else note for note in data.notes]
    if args.agl:
        what += f"; heights above the start ({run.datum:.2f} m)"
    return what, notes


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
              "rocket log the rocket estimator (the default) has one", file=sys.stderr)


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


def _print_events(run, data) -> None:
    """The rocket estimator's events next to the flight computer's own (when the log has them)."""
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


def _write_run_outputs(args: argparse.Namespace, run, progress: Progress, stdout=None) -> None:
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
